"""One reader for prism's files: `prism_tools.dataset.Frame` and `prism_tools.outputs.read` give
the same layers with the same shapes and types (ids uint32 (H, W), floats float32), "RGB" is a
layer in both, `Frame.spectral()` on a frame without bands says what to do, and
`FrameDataset` is a map-style dataset a torch DataLoader can take (checked without torch: its
protocol, `len` and `[k]`)."""

from __future__ import annotations

import pathlib
import re
import subprocess

import numpy as np
import pytest

from prism_tools import dataset, outputs

ROOT = pathlib.Path(__file__).resolve().parents[2]
DS = ROOT / "configs" / "datasets"


@pytest.fixture(scope="module")
def frames(prism_bin, tmp_path_factory) -> pathlib.Path:
    """Three frames of the smoke dataset on a base scene with id and depth layers, each frame's
    sensor the CIE 1931 one (XYZ and sRGB, no bands)."""
    d = tmp_path_factory.mktemp("reader")
    sky = ROOT / "scenes" / "textures" / "sky.exr"
    base = (DS / "scenes" / "tabletop.ron").read_text()
    base = base.replace('"../../../scenes/textures/sky.exr"', f'"{sky}"')
    base = base.replace("    integrator: (max_depth: 6),\n", '    integrator: (max_depth: 6),\n    aovs: ["depth", "instance", "label"],\n')
    base = base.replace('(name: "ball",', '(name: "ball", label: "toy",')
    (d / "base.ron").write_text(base)
    cfg = (DS / "smoke.ron").read_text()
    cfg = cfg.replace('"scenes/tabletop.ron"', '"base.ron"').replace('"../../scenes/textures/sky.exr"', f'"{sky}"')
    cfg = re.sub(r"frames: \d+,", "frames: 3,", cfg)
    cfg = cfg.replace("seed: 1,", f'seed: 1,\n    sensor: (files: ["{ROOT / "configs" / "sensors" / "cie1931.ron"}"]),')
    (d / "ds.ron").write_text(cfg)
    out = d / "out"
    subprocess.run([str(prism_bin), "dataset", str(d / "ds.ron"), "-o", str(out), "-q"], check=True)
    return out


def test_frame_and_outputs_read_agree(frames):
    ds = dataset.open_dataset(frames)
    f = ds[1]
    r = outputs.read(f.exr_path)
    assert f.layers() == r.layers() and "RGB" in f.layers() and "instance" in f.layers()
    for name in f.layers():
        a, b = f.layer(name), r.layer(name)
        assert a.dtype == b.dtype and a.shape == b.shape and np.array_equal(a, b), name
    h, w = 48, 64
    assert f.layer("instance").dtype == np.uint32 and f.layer("instance").shape == (h, w)
    assert f.layer("label").dtype == np.uint32
    assert f.layer("depth").dtype == np.float32 and f.layer("depth").shape == (h, w)
    assert f.layer("RGB").dtype == np.float32 and f.layer("RGB").shape == (h, w, 3)
    # The ids are the sidecar's: every instance id in the layer names one of its objects.
    ids = {o["instance_id"] for o in f.sidecar["objects"]}
    assert set(np.unique(f.layer("instance"))) - {0} <= ids
    assert f.metadata["prism:seed"] == str(f.params["render_seed"])
    with pytest.raises(KeyError, match="no spectral channels.*bands"):
        f.spectral()
    with pytest.raises(KeyError, match="no layer 'normal'"):
        f.layer("normal")


def test_frame_dataset_is_map_style(frames):
    fd = dataset.FrameDataset(frames, layers=("RGB", "label"))
    assert len(fd) == 3
    items = [fd[k] for k in range(len(fd))]
    assert [it["frame"] for it in items] == [0, 1, 2]
    assert items[2]["RGB"].shape == (48, 64, 3) and items[2]["label"].dtype == np.uint32
    assert np.array_equal(items[1]["label"], dataset.open_dataset(frames)[1].layer("label"))
    with pytest.raises(IndexError):
        fd[3]
    doubled = dataset.FrameDataset(frames, layers=("label",), transform=lambda it: it["label"].astype(np.int64) * 2)
    assert doubled[0].dtype == np.int64
