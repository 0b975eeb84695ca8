"""Benchmark of `prism dataset` (issue 17, item 7; not a test).

1. Per-frame overhead of a dataset run over a lone `prism render` of the same frame. The
   dataset's frames run in chunks of `--chunk` frames (`--frames lo..hi` into one output
   folder, which resumes it); after each chunk its first frame, exported beforehand with
   `--export-frame`, is rendered alone (`prism render ... --preview`, the dataset's outputs).
   The interleaving cancels the drift of a shared machine's load. Reported:
   - paired wall time: the frame's seconds inside the dataset run (manifest: build, render,
     write) against the lone process's wall time for the same frame;
   - CPU (user + system, from wait4, less load-sensitive than wall time): the chunked dataset
     run's CPU per frame (all frames, each chunk paying one process start and scene load)
     against the lone renders' mean CPU per frame (the sampled frames).
2. Frames per hour of the dataset run (the chunks' wall and CPU time together).
3. Peak RSS (the child's ru_maxrss from wait4) of an uninterrupted run of `--rss-long` frames
   against one of `--rss-short` frames.

Full size (the issue's): --frames 200 --size 128 --spp 16 --rss-long 1000 --rss-short 10
(the defaults; --rss-spp 1 keeps the RSS runs short). configs/README.md has the figures.
Run: tools/.venv/bin/python tools/bench/dataset_bench.py [--frames N --size S --spp P ...]
The base is configs/datasets/smoke.ron (the tabletop scene, every kind of variation), or
`--config FILE` (e.g. configs/datasets/tabletop.ron), with its frame count, resolution and spp
replaced. PRISM_BIN=BINARY measures another build.
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import re
import shutil
import subprocess
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[2]


def run(cmd: list[str]) -> dict:
    """Wall seconds, CPU seconds (user + system) and peak RSS (MiB) of a child process."""
    t = time.perf_counter()
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, ru = os.wait4(p.pid, 0)
    wall = time.perf_counter() - t
    if status != 0:
        raise RuntimeError(f"{cmd}: {p.stderr.read().decode()}")
    return {"wall": wall, "user": ru.ru_utime, "cpu": ru.ru_utime + ru.ru_stime, "rss": ru.ru_maxrss / 1024}


def config(tmp: pathlib.Path, frames: int, size: int, spp: int, base: pathlib.Path | None = None) -> pathlib.Path:
    """`base` (default configs/datasets/smoke.ron) with its frame count, spp and resolution
    replaced, written to `tmp`: every quoted relative path that names a file beside the base is
    made absolute."""
    base = base or ROOT / "configs" / "datasets" / "smoke.ron"
    text = base.read_text()

    def absolute(m: re.Match) -> str:
        p = base.parent / m.group(1)
        return json.dumps(str(p.resolve())) if not pathlib.Path(m.group(1)).is_absolute() and p.is_file() else m.group(0)

    text = re.sub(r'"([^"\n]+\.[A-Za-z]+)"', absolute, text)
    text = re.sub(r"\bframes: \d+,", f"frames: {frames},", text, count=1)
    n = 1
    if size:  # 0: the config's own resolution and spp
        text, n = re.subn(r"spp: \d+, resolution: \(\d+, \d+\)", f"spp: {spp}, resolution: ({size}, {size})", text)
    if n != 1:
        raise SystemExit(f"{base}: no `outputs: (... spp: N, resolution: (W, H))` to replace")
    p = tmp / f"bench_{frames}_{size}_{spp}.ron"
    p.write_text(text)
    return p


def load() -> str:
    return " ".join(f"{x:.1f}" for x in os.getloadavg())


def timing(a, prism: str, tmp: pathlib.Path) -> None:
    """Figures 1 and 2 of the module docs: the chunked run against lone renders."""
    cfg = config(tmp, a.frames, a.size, a.spp, a.config)
    out = tmp / "out"
    starts = list(range(0, a.frames, a.chunk))
    for i in starts:
        run([prism, "dataset", str(cfg), "-o", str(tmp / "export"), "--export-frame", str(i), "-q"])
    print(f"load average before: {load()}", flush=True)
    chunks, lone, scalar = [], [], []
    for i in starts:
        hi = min(i + a.chunk, a.frames)
        chunks.append(run([prism, "dataset", str(cfg), "-o", str(out), "--frames", f"{i}..{hi}", "-q"]))
        scene = tmp / "export" / "frames" / f"{i:06d}.ron"
        lone.append(run([prism, "render", str(scene), "-o", str(tmp / "lone.exr"), "-q",
                         "--preview", str(tmp / "lone.png")]))
        print(f"  frames {i}..{hi}: dataset {chunks[-1]['wall']:.1f} s wall {chunks[-1]['cpu']:.2f} s CPU; "
              f"lone frame {i}: {lone[-1]['wall']:.2f} s wall {lone[-1]['cpu']:.2f} s CPU; load {load()}", flush=True)
        if a.lone_scalar:
            scalar.append(run([prism, "render", str(scene), "-o", str(tmp / "lone.exr"), "-q", "--simd", "off",
                               "--preview", str(tmp / "lone.png")]))
            print(f"    lone frame {i} with --simd off: {scalar[-1]['wall']:.2f} s wall {scalar[-1]['cpu']:.2f} s CPU",
                  flush=True)
    print(f"load average after: {load()}")
    lines = {e["frame"]: e for e in map(json.loads, (out / "manifest.jsonl").read_text().splitlines())}
    assert sorted(lines) == list(range(a.frames)), "every frame listed once"
    n = len(starts)
    in_run = sum(lines[i]["seconds"] for i in starts) / n
    lone_wall = sum(x["wall"] for x in lone) / n
    lone_cpu = sum(x["cpu"] for x in lone) / n
    ds_wall = sum(x["wall"] for x in chunks)
    ds_cpu = sum(x["cpu"] for x in chunks)
    size = f"{a.size}x{a.size} {a.spp} spp" if a.size else "at the config's size and spp"
    print(f"dataset: {a.frames} frames {size} in {n} processes of {a.chunk}: "
          f"{ds_wall:.1f} s wall ({ds_wall / a.frames:.3f} s/frame, {3600 * a.frames / ds_wall:.0f} frames/hour), "
          f"{ds_cpu:.1f} s CPU ({ds_cpu / a.frames:.3f} s/frame, {3600 * a.frames / ds_cpu:.0f} frames per CPU-hour)")
    print(f"paired wall, frames {starts[0]}, {starts[1] if n > 1 else ''}...: inside the dataset run "
          f"{in_run:.3f} s/frame; lone `prism render` {lone_wall:.3f} s/frame; ratio {in_run / lone_wall:.3f}")
    print(f"CPU: dataset {ds_cpu / a.frames:.3f} s/frame (all {a.frames}); lone {lone_cpu:.3f} s/frame "
          f"({n} sampled); ratio {ds_cpu / a.frames / lone_cpu:.3f}")
    if scalar:
        ratios = sorted(x["cpu"] / y["cpu"] for x, y in zip(scalar, lone))
        print(f"lone frames, --simd off over --simd auto (CPU seconds, same frame, run one after the other): "
              f"median {ratios[len(ratios) // 2]:.3f}, range {ratios[0]:.3f}-{ratios[-1]:.3f} over {len(ratios)} frames")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--frames", type=int, default=200)
    ap.add_argument("--chunk", type=int, default=10, help="dataset frames per process; the first of each is rendered alone")
    ap.add_argument("--size", type=int, default=128, help="square film size; 0 keeps the config's resolution and spp")
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--rss-short", type=int, default=10)
    ap.add_argument("--rss-long", type=int, default=1000)
    ap.add_argument("--rss-size", type=int, default=None, help="image size of the RSS runs (default --size)")
    ap.add_argument("--rss-spp", type=int, default=None)
    ap.add_argument("--skip-rss", action="store_true")
    ap.add_argument("--lone-scalar", action="store_true",
                    help="also render each sampled frame alone with --simd off (the dataset command has no --simd)")
    ap.add_argument("--config", type=pathlib.Path, help="base dataset config (default configs/datasets/smoke.ron; "
                    "e.g. configs/datasets/tabletop.ron)")
    ap.add_argument("--skip-timing", action="store_true", help="only the RSS runs")
    a = ap.parse_args()
    prism = os.environ.get("PRISM_BIN", str(ROOT / "target" / "release" / "prism"))
    tmp = pathlib.Path(tempfile.mkdtemp(prefix="prism-dataset-bench-"))
    try:
        if not a.skip_timing:
            timing(a, prism, tmp)
        if a.skip_rss:
            return
        rs, rsp = a.rss_size or a.size, a.rss_spp or a.spp
        rss = {}
        for k in (a.rss_short, a.rss_long):
            c = config(tmp, k, rs, rsp, a.config)
            r = run([prism, "dataset", str(c), "-o", str(tmp / f"rss{k}"), "-q"])
            rss[k] = r["rss"]
            print(f"peak RSS after {k} frames ({rs}x{rs}, {rsp} spp): {r['rss']:.1f} MiB "
                  f"({r['wall']:.1f} s wall, {r['cpu']:.1f} s CPU; load {load()})", flush=True)
        print(f"RSS ratio {a.rss_long}/{a.rss_short} frames: {rss[a.rss_long] / rss[a.rss_short]:.3f}")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
