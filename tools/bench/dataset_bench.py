"""Benchmark of `prism dataset` (issue 17, item 7; not a test).

1. Per-frame overhead: the dataset run's wall time per frame against `prism render` of the same
   frames exported with `--export-frame` (each a lone process: parse, build, render, write).
2. Frames per hour of the dataset run.
3. Peak RSS (the child's ru_maxrss from wait4) of a run of `--rss-long`
   frames against one of `--rss-short` frames.

Full size (the issue's): --frames 200 --size 128 --spp 16 --rss-long 1000 --rss-short 10.
Run: tools/.venv/bin/python tools/bench/dataset_bench.py [--frames N --size S --spp P ...]
The base is configs/datasets/smoke.ron with its resolution and spp replaced.
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import shutil
import subprocess
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[2]


def run(cmd: list[str]) -> tuple[float, int]:
    """(wall seconds, peak RSS of the child in MiB)."""
    t = time.perf_counter()
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, ru = os.wait4(p.pid, 0)
    wall = time.perf_counter() - t
    if status != 0:
        raise RuntimeError(f"{cmd}: {p.stderr.read().decode()}")
    return wall, ru.ru_maxrss // 1024


def config(tmp: pathlib.Path, frames: int, size: int, spp: int) -> pathlib.Path:
    ds = ROOT / "configs" / "datasets"
    text = (ds / "smoke.ron").read_text()
    text = text.replace('"scenes/tabletop.ron"', json.dumps(str(ds / "scenes" / "tabletop.ron")))
    text = text.replace('"../../scenes/textures/sky.exr"', json.dumps(str(ROOT / "scenes" / "textures" / "sky.exr")))
    text = text.replace("frames: 8,", f"frames: {frames},")
    text = text.replace("spp: 8, resolution: (64, 48)", f"spp: {spp}, resolution: ({size}, {size})")
    p = tmp / f"bench_{frames}.ron"
    p.write_text(text)
    return p


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--frames", type=int, default=200)
    ap.add_argument("--lone", type=int, default=20, help="frames also rendered alone")
    ap.add_argument("--size", type=int, default=128)
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--rss-short", type=int, default=10)
    ap.add_argument("--rss-long", type=int, default=1000)
    ap.add_argument("--rss-size", type=int, default=None, help="image size of the RSS runs (default --size)")
    ap.add_argument("--rss-spp", type=int, default=None)
    a = ap.parse_args()
    prism = os.environ.get("PRISM_BIN", str(ROOT / "target" / "release" / "prism"))
    tmp = pathlib.Path(tempfile.mkdtemp(prefix="prism-dataset-bench-"))
    try:
        cfg = config(tmp, a.frames, a.size, a.spp)
        out = tmp / "out"
        wall, _ = run([prism, "dataset", str(cfg), "-o", str(out), "-q"])
        per = wall / a.frames
        lone = []
        for i in range(a.lone):
            run([prism, "dataset", str(cfg), "-o", str(tmp / "export"), "--export-frame", str(i), "-q"])
            scene = tmp / "export" / "frames" / f"{i:06d}.ron"
            w, _ = run([prism, "render", str(scene), "-o", str(tmp / "lone.exr"), "-q",
                        "--preview", str(tmp / "lone.png")])
            lone.append(w)
        lone_mean = sum(lone) / len(lone)
        # The same frames' share of the dataset run (from the manifest's per-frame seconds,
        # which time plan + build + render + write inside the one process).
        lines = [json.loads(x) for x in (out / "manifest.jsonl").read_text().splitlines()]
        in_run = sum(e["seconds"] for e in lines if e["frame"] < a.lone) / a.lone
        print(f"dataset: {a.frames} frames {a.size}x{a.size} {a.spp} spp in {wall:.1f} s: {per:.3f} s/frame, "
              f"{3600 / per:.0f} frames/hour")
        print(f"lone `prism render` of frames 0..{a.lone}: {lone_mean:.3f} s/frame (process wall); "
              f"the same frames inside the dataset run: {in_run:.3f} s/frame; "
              f"dataset wall per frame / lone: {per / lone_mean:.3f}")
        rs, rsp = a.rss_size or a.size, a.rss_spp or a.spp
        rss = {}
        for n in (a.rss_short, a.rss_long):
            c = config(tmp, n, rs, rsp)
            o = tmp / f"rss{n}"
            w, peak = run([prism, "dataset", str(c), "-o", str(o), "-q"])
            rss[n] = peak
            print(f"peak RSS after {n} frames ({rs}x{rs}, {rsp} spp): {peak} MiB ({w:.1f} s)")
        print(f"RSS ratio {a.rss_long}/{a.rss_short} frames: {rss[a.rss_long] / rss[a.rss_short]:.3f}")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
