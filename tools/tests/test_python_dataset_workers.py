"""`prism.Dataset` in worker processes, as a PyTorch `DataLoader` with workers uses it: the
dataset pickled (spawn) or inherited (fork) into each worker, frames read there. The module does
not depend on torch; the DataLoader test runs where torch is installed and skips elsewhere."""

from __future__ import annotations

import multiprocessing

import numpy as np
import prism
import pytest
from test_python_module import tiny_dataset_config


def frame_sum(args):
    ds, i = args
    f = ds[i]
    return f["frame"], float(np.asarray(f["R"], np.float64).sum()), f["spectral"].shape


@pytest.fixture(scope="module")
def dataset(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("workers")
    out = tmp / "out"
    prism.run_dataset(tiny_dataset_config(tmp, frames=4), out, threads=2, progress=False)
    return prism.Dataset(out)


@pytest.mark.parametrize("method", ["fork", "spawn"])
def test_frames_read_in_worker_processes(dataset, method):
    """Tolerance: none. Two workers of each start method read every frame as the parent does
    (its number, the sum of R to the bit, the spectral cube's shape)."""
    want = [frame_sum((dataset, i)) for i in range(len(dataset))]
    with multiprocessing.get_context(method).Pool(2) as pool:
        got = pool.map(frame_sum, [(dataset, i) for i in range(len(dataset))])
    assert got == want


def test_a_torch_dataloader_with_workers(dataset):
    """Tolerance: none. A DataLoader with two workers yields each frame once, its R channel as
    a tensor equal to the parent's array."""
    torch = pytest.importorskip(
        "torch",
        reason="torch is not installed: it is no requirement of prism (its Linux wheels with their CUDA "
        "libraries are ~3 GB to download, 5 GB installed); tools/run_tests.sh installs it where PyPI can be reached",
    )
    loader = torch.utils.data.DataLoader(dataset, batch_size=None, num_workers=2)
    seen = {}
    for f in loader:
        seen[int(f["frame"])] = f["R"]
    assert sorted(seen) == list(range(len(dataset)))
    for i, r in seen.items():
        assert isinstance(r, torch.Tensor)
        np.testing.assert_array_equal(r.numpy(), dataset[i]["R"])
