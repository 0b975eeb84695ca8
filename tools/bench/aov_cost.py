"""What each AOV layer costs: wall-clock seconds of whole `prism render` runs (load, render, AOV
pass, EXR and sidecar writing) with no AOVs and with each AOV alone, runs interleaved so a
shared machine's drifts hit all alike; optionally a second binary (e.g. main's) without AOVs.
With `--instructions`, also the instructions each run executes (valgrind's callgrind, one
thread: a count a loaded machine does not disturb).

    tools/.venv/bin/python tools/bench/aov_cost.py target/release/prism scenes/cornell.ron \\
        --spp 16 --runs 5 [--baseline /work/main/target/release/prism] [--instructions]

Prints, per configuration, the mean wall time ± its standard error and the extra time over the
no-AOV run of the same binary, and with `--instructions` the instruction count and its extra
over the no-AOV run.
"""

from __future__ import annotations

import argparse
import re
import statistics
import subprocess
import tempfile
import time

AOVS = ["depth", "distance", "position", "normal", "geo_normal", "normal_camera", "uv", "instance", "label", "material", "alpha", "stderr", "albedo"]


def wall(binary: str, scene: str, spp: int, aovs: str | None, threads: int | None) -> float:
    with tempfile.TemporaryDirectory() as tmp:
        cmd = [binary, "render", scene, "-o", f"{tmp}/o.exr", "-q", "--spp", str(spp)]
        if aovs is not None:
            cmd += ["--aovs", aovs]
        if threads:
            cmd += ["--threads", str(threads)]
        t = time.perf_counter()
        subprocess.run(cmd, check=True, capture_output=True)
        return time.perf_counter() - t


def instructions(binary: str, scene: str, spp: int, aovs: str | None) -> int:
    """Instructions one single-threaded run executes, counted by callgrind."""
    with tempfile.TemporaryDirectory() as tmp:
        cmd = ["valgrind", "--tool=callgrind", f"--callgrind-out-file={tmp}/cg.out", binary, "render", scene]
        cmd += ["-o", f"{tmp}/o.exr", "-q", "--spp", str(spp), "--threads", "1"]
        if aovs is not None:
            cmd += ["--aovs", aovs]
        err = subprocess.run(cmd, check=True, capture_output=True, text=True).stderr
    return int(re.search(r"Collected : (\d+)", err).group(1))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("binary")
    ap.add_argument("scene")
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--runs", type=int, default=5, help="wall-clock runs of each (0: instructions only)")
    ap.add_argument("--threads", type=int)
    ap.add_argument("--baseline", help="another binary, run without AOVs (it may predate them)")
    ap.add_argument("--aovs", default=",".join(AOVS), help="comma-separated AOVs to time one by one")
    ap.add_argument("--instructions", action="store_true", help="also count instructions (valgrind, 1 thread)")
    a = ap.parse_args()
    configs: list[tuple[str, str, str | None]] = []
    if a.baseline:
        configs.append(("baseline, no AOVs", a.baseline, None))
    configs.append(("no AOVs", a.binary, ""))
    configs += [(name, a.binary, name) for name in a.aovs.split(",")]
    times: dict[str, list[float]] = {c[0]: [] for c in configs}
    wall(a.binary, a.scene, a.spp, "", a.threads)  # warm caches
    for _ in range(a.runs):
        for label, binary, aovs in configs:
            times[label].append(wall(binary, a.scene, a.spp, aovs, a.threads))
    base = statistics.mean(times["no AOVs"]) if a.runs else 0.0
    for label, v in times.items() if a.runs else ():
        m = statistics.mean(v)
        se = statistics.stdev(v) / len(v) ** 0.5 if len(v) > 1 else 0.0
        print(f"{label:>20}: {m:7.3f} ± {se:.3f} s   ({m - base:+.3f} s vs no AOVs)")
    if a.instructions:
        counts = {label: instructions(binary, a.scene, a.spp, aovs) for label, binary, aovs in configs}
        base_n = counts["no AOVs"]
        for label, n in counts.items():
            print(f"{label:>20}: {n:15,d} instructions   ({n - base_n:+,d}, {100 * (n - base_n) / base_n:+.3f}% vs no AOVs)")


if __name__ == "__main__":
    main()
