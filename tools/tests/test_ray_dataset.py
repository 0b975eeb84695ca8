"""`prism_tools.dataset` on a real Ray cluster (ray.cluster_utils.Cluster: a head and a worker
node) running configs/datasets/smoke.ron; the worker node is removed while frames are in flight.
Every frame must be listed exactly once and the output must be byte-identical to a
single-process `prism dataset` run. Also: the lazy reader and the contact sheet."""

from __future__ import annotations

import json
import os
import pathlib
import subprocess
import time

import numpy as np
import pytest

from prism_tools import dataset

ROOT = pathlib.Path(__file__).resolve().parents[2]
SMOKE = ROOT / "configs" / "datasets" / "smoke.ron"


def frame_files(out: pathlib.Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted((out / "frames").iterdir()) if not p.name.startswith(".")}


@pytest.fixture(scope="module")
def single(prism_bin, tmp_path_factory) -> pathlib.Path:
    out = tmp_path_factory.mktemp("single") / "out"
    subprocess.run([str(prism_bin), "dataset", str(SMOKE), "-o", str(out), "-q"], check=True)
    return out


def test_reader_and_contact_sheet(single, tmp_path):
    ds = dataset.open_dataset(single)
    assert ds.indices() == list(range(8))
    f = ds[5]
    assert f.params["frame"] == 5 and "camera" in f.params
    wl, cube = f.spectral()
    assert np.all(np.diff(wl) > 0) and cube.shape == (48, 64, len(wl)) and len(wl) == 47
    assert f.layers()[:3] == ["RGB", "XYZ", "S0"]
    # The spectral cube and the XYZ channels are two estimates of one image: Y from the bands
    # (10 nm means times the 1931 y-bar at their centres, over the y-bar sum) must match the Y
    # channel closely on the whole-image mean (the band means smooth y-bar over 10 nm: < 1%).
    import colour

    ybar = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"].signals["y_bar"]
    y_from_bands = (cube * ybar[wl]).sum(-1) * 10.0 / ybar[np.arange(360, 831)].sum()
    y = f.channel("Y")
    assert abs(y_from_bands.mean() / y.mean() - 1) < 0.01
    assert f.metadata["prism:seed"] == str(f.params["render_seed"])
    sheet = dataset.contact_sheet(ds, tmp_path / "sheet.png", columns=4, width=64)
    import cv2

    img = cv2.imread(str(sheet))
    assert img.shape == (2 * 48, 4 * 64, 3)


def test_ray_cluster_with_a_node_removed(prism_bin, single, tmp_path):
    ray = pytest.importorskip("ray")
    from ray.cluster_utils import Cluster

    os.environ["RAY_USAGE_STATS_ENABLED"] = "0"
    out = tmp_path / "out"
    log = tmp_path / "attempts.log"
    cluster = Cluster(initialize_head=True, head_node_args={"num_cpus": 1})
    worker = cluster.add_node(num_cpus=2)
    cluster.wait_for_nodes()
    try:
        ray.init(address=cluster.address, include_dashboard=False, log_to_driver=False)
        # The driver as run_on_ray runs it, with the node removed once frames are in flight.
        prism = str(prism_bin)
        r = subprocess.run(
            [prism, "dataset", str(SMOKE), "-o", str(out), "--check"], capture_output=True, text=True, check=True
        )
        todo = json.loads(r.stdout)["todo"]
        assert todo == list(range(8))
        task = dataset.frame_task(ray, num_cpus=1, max_retries=3)
        refs = [task.remote(prism, str(SMOKE), str(out), i, 1, str(log)) for i in todo]
        t0 = time.time()
        while not log.exists() or len(log.read_text().splitlines()) < 3:
            assert time.time() - t0 < 60, "no task started"
            time.sleep(0.05)
        cluster.remove_node(worker)
        assert sorted(ray.get(refs, timeout=120)) == todo
        # And through the public driver: nothing left to do, nothing rendered again.
        assert dataset.run_on_ray(SMOKE, out, prism_bin=prism) == []
    finally:
        ray.shutdown()
        cluster.shutdown()
    frames = [json.loads(line)["frame"] for line in (out / "manifest.jsonl").read_text().splitlines()]
    assert sorted(frames) == list(range(8)), frames
    assert frame_files(out) == frame_files(single)
    attempts = len(log.read_text().splitlines())
    print(f"{attempts} task attempts for 8 frames")
