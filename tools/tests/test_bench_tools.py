"""The benchmark tools' own logic: the generated mesh, prism's summary line, the error-time
fits, the interleaved rounds and their ratios, the image agreement check, and the dataset
benchmark's config rewriting (the timings themselves are measured by tools/bench/run_all.sh,
never in tests)."""

from __future__ import annotations

import math
import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "bench"))
import common  # noqa: E402
import dataset_bench  # noqa: E402
import error_time  # noqa: E402
import make_mesh  # noqa: E402
import rounds  # noqa: E402


def test_mesh_is_closed_outward_and_big_enough(tmp_path):
    pos, faces = make_mesh.bumpy_sphere(20_000)
    assert len(faces) >= 20_000
    assert faces.min() >= 0 and faces.max() < len(pos)
    a, b, c = (pos[faces[:, k]].astype(np.float64) for k in range(3))
    cross = np.cross(b - a, c - a)
    assert (np.linalg.norm(cross, axis=1) > 0).all(), "degenerate triangles"
    # Divergence theorem: the signed volume is positive when the faces wind outward, and close
    # to the unit sphere's (the bumps average out).
    volume = np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6
    assert abs(volume - 4 / 3 * math.pi) < 0.15 * 4 / 3 * math.pi
    # Every edge is shared by exactly two triangles once coincident vertices (each pole's row)
    # are merged: no holes at the seam or the poles.
    _, weld = np.unique(pos, axis=0, return_inverse=True)
    f = weld.reshape(-1)[faces]
    edges = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    assert (counts == 2).all()


def test_ply_round_trip(tmp_path):
    pos, faces = make_mesh.bumpy_sphere(500)
    path = tmp_path / "m.ply"
    make_mesh.write_ply(path, pos, faces)
    data = path.read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode()
    assert f"element vertex {len(pos)}" in header and f"element face {len(faces)}" in header
    body = np.frombuffer(data[end:end + pos.nbytes], dtype="<f4").reshape(-1, 3)
    assert np.array_equal(body, pos)
    rec = np.frombuffer(data[end + pos.nbytes:], dtype=[("n", "u1"), ("i", "<i4", (3,))])
    assert (rec["n"] == 3).all() and np.array_equal(rec["i"], faces)


def test_summary_line_parses():
    line = ("rendered 256x256 at 64 spp (4.2 Msamples) in 5.12 s (0.82 Msamples/s, 2 threads); "
            "scene load 0.03 s; 0 invalid samples, 4 clamped at 10 -> /tmp/o.exr")
    m = common.SUMMARY.search(line)
    assert m and m.group(3) == "64" and m.group(5) == "5.12" and m.group(7) == "2" and m.group(8) == "0.03"
    one = line.replace("2 threads", "1 thread")
    assert common.SUMMARY.search(one).group(7) == "1"
    # Adaptive sampling prints its settings in place of the count (error_time's adaptive curve).
    adaptive = ("rendered 320x180 at Adaptive(rel_error: 0.1, min: 16, max: 4096, target: Y, floor: 0.001) spp "
                "(5.8 Msamples) in 4.80 s (1.20 Msamples/s, 2 threads); scene load 0.18 s; 0 invalid samples -> /tmp/a.exr")
    m = common.SUMMARY.search(adaptive)
    assert m and m.group(3).startswith("Adaptive(") and m.group(5) == "4.80" and m.group(6) == "1.20"


def test_prism_render_reports_an_adaptive_renders_mean_spp(monkeypatch, tmp_path):
    # The render itself is not run: `measured` returns the line prism prints.
    line = ("rendered 100x50 at Adaptive(rel_error: 0.1, min: 16, max: 4096, target: Y, floor: 0.001) spp "
            "(0.2 Msamples) in 2.00 s (0.10 Msamples/s, 2 threads); scene load 0.10 s; 0 invalid samples -> x")
    seen = []
    monkeypatch.setattr(common, "measured", lambda cmd: (seen.append(cmd), (0, "", line, 10.0, 2.2))[1])
    r = common.prism_render(pathlib.Path("prism"), pathlib.Path("s.ron"), None, 2, tmp_path / "x.exr", ["--rel-error", "0.1"])
    assert "--spp" not in map(str, seen[0])
    # 0.10 Msamples/s over 2 s on 5,000 pixels: 40 samples a pixel on average.
    assert r["spp"] == 40.0 and r["render_s"] == 2.0 and r["threads"] == 2 and r["load_s"] == 0.1


def test_power_law_fit_and_equal_error_time():
    pts = [(t, 0.3 * t**-1.0) for t in (0.5, 1.0, 2.0, 4.0)]
    a, b = error_time.fit(pts)
    assert abs(b + 1.0) < 1e-9 and abs(math.exp(a) - 0.3) < 1e-9
    assert abs(error_time.time_for((a, b), 0.15) - 2.0) < 1e-9
    assert error_time.ladder(32) == [1, 2, 4, 8, 16, 32]
    ref = np.ones((4, 4, 3))
    assert error_time.relmse(ref, ref) == 0.0
    assert abs(error_time.relmse(ref * 1.1, ref) - 0.01 / 1.01) < 1e-12


def test_p90_relative_error_counts_the_worst_tenth_and_floors_dark_pixels():
    ref = np.ones((10, 10, 3))
    img = ref.copy()
    img[0, :9] *= 1.5  # 9 pixels of 100 off by 50%: below the 90th percentile
    assert error_time.p90_rel(img, ref) < 1e-12
    img[1, :2] *= 1.2  # 11 off: the percentile lands among them (numpy's linear interpolation)
    assert 0.19 < error_time.p90_rel(img, ref) < 0.51
    # A black reference pixel measures against the floor, not against 0.
    dark = np.zeros((1, 1, 3))
    assert abs(error_time.p90_rel(dark + 1e-4, dark) - 0.1) < 1e-9


def test_speedup_reads_off_the_fits():
    rows = [{"scene": "s", "renderer": "prism", "seconds": t, "relmse": 1 / t} for t in (1, 2, 4)]
    rows += [{"scene": "s", "renderer": "other", "seconds": 2 * t, "relmse": 1 / t} for t in (1, 2, 4)]
    sp = {r["renderer"]: r for r in error_time.speedups(rows, "s")}
    assert abs(sp["prism"]["speedup_of_prism"] - 1.0) < 1e-9
    assert abs(sp["other"]["speedup_of_prism"] - 2.0) < 1e-9
    # The same by another measure; rows without it are left out.
    for r in rows:
        r["p90_rel"] = r["relmse"] ** 0.5
    rows.append({"scene": "s", "renderer": "third", "seconds": 1.0, "relmse": 1.0})
    sp = {r["renderer"]: r for r in error_time.speedups(rows, "s", "p90_rel")}
    assert set(sp) == {"prism", "other"} and abs(sp["other"]["speedup_of_prism"] - 2.0) < 1e-9


def test_rounds_rotate_the_order_and_pair_ratios_by_round(monkeypatch):
    order = []

    def runner(name, speed):
        def run(seed):
            order.append((name, seed))
            return {"render_s": 1.0 / speed[seed - 1], "msamples_per_s": speed[seed - 1]}
        return run

    monkeypatch.setattr(rounds, "log", lambda _msg: None)
    # B is twice A in every round while the machine's speed drifts 3x between rounds: the
    # same-round ratio is exactly 2, the ratio of medians need not be.
    runs = rounds.run_rounds({"a": runner("a", [1.0, 3.0, 2.0]), "b": runner("b", [2.0, 6.0, 4.0])}, 3)
    assert order == [("a", 1), ("b", 1), ("b", 2), ("a", 2), ("a", 3), ("b", 3)]
    s = rounds.summary(runs, [("b", "a"), ("b", "missing")])
    assert s["renderers"]["a"] == {"median": 2.0, "min": 1.0, "max": 3.0, "n": 3}
    assert s["ratios"]["b / a"]["all"] == [2.0, 2.0, 2.0]
    assert list(s["ratios"]) == ["b / a"]
    assert "load average" in rounds.markdown("t", s)[2].lower()


def test_agreement_tells_noise_from_a_different_image():
    rng = np.random.default_rng(1)
    truth = np.tile(np.linspace(0.1, 1.0, 64), (48, 1))[..., None].repeat(3, axis=2)
    a = truth + rng.normal(0, 0.3, truth.shape)
    b = truth + rng.normal(0, 0.3, truth.shape)
    same = rounds.agreement(a, b)
    assert abs(same["z_image"]) < 4 and same["max_abs_z_block"] < 5 and same["blocks"] == 12
    # 10% brighter everywhere: the difference's noise is 0.3·√2/√3 per pixel, its standard
    # error over 3072 pixels 0.0044, the shift 0.055: about 12 standard errors.
    other = rounds.agreement(a * 1.1, b)
    assert other["z_image"] > 8 and abs(other["mean_ratio"] - 1.1) < 0.01


def test_dataset_config_is_made_absolute_and_resized(tmp_path):
    root = pathlib.Path(__file__).resolve().parents[2]
    for base in (None, root / "configs/datasets/tabletop.ron"):
        text = dataset_bench.config(tmp_path, 5, 32, 2, base).read_text()
        assert "frames: 5," in text and "spp: 2, resolution: (32, 32)" in text
        assert f'"{root}/configs/datasets/scenes/tabletop.ron"' in text
        assert f'"{root}/scenes/textures/sky.exr"' in text
    kept = dataset_bench.config(tmp_path, 5, 0, 0, root / "configs/datasets/tabletop.ron").read_text()
    assert "spp: 32, resolution: (160, 120)" in kept
