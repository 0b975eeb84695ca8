"""Compare the render throughput of two prism binaries on one scene, fairly.

    tools/.venv/bin/python tools/bench/ab_throughput.py OLD_BINARY NEW_BINARY scenes/cornell.ron --runs 8 --spp 64

Runs alternate (A, B, A, B, ...), so slow drifts of a shared machine hit both equally; each run's
Msamples/s comes from prism's own summary line (render time only, scene loading excluded). Prints
the mean throughput of each with its standard error and the ratio B/A with a 95% confidence
interval (t distribution on the per-pair ratios). "Equal within noise" means the interval
contains 1.
"""

from __future__ import annotations

import argparse
import re
import statistics
import subprocess
import tempfile

from scipy import stats


def run(binary: str, scene: str, spp: int, threads: int | None) -> float:
    with tempfile.TemporaryDirectory() as tmp:
        cmd = [binary, "render", scene, "-o", f"{tmp}/o.exr", "-q", "--spp", str(spp)]
        if threads:
            cmd += ["--threads", str(threads)]
        err = subprocess.run(cmd, check=True, capture_output=True, text=True).stderr
    return float(re.search(r"\(([0-9.]+) Msamples/s", err).group(1))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("a")
    ap.add_argument("b")
    ap.add_argument("scene")
    ap.add_argument("--runs", type=int, default=8)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--threads", type=int)
    args = ap.parse_args()
    run(args.a, args.scene, args.spp, args.threads)  # warm caches
    a, b = [], []
    for _ in range(args.runs):
        a.append(run(args.a, args.scene, args.spp, args.threads))
        b.append(run(args.b, args.scene, args.spp, args.threads))
    ratios = [y / x for x, y in zip(a, b)]
    m = statistics.mean(ratios)
    half = stats.t.ppf(0.975, len(ratios) - 1) * statistics.stdev(ratios) / len(ratios) ** 0.5
    se = lambda v: statistics.stdev(v) / len(v) ** 0.5  # noqa: E731
    print(f"A {args.a}: {statistics.mean(a):.3f} ± {se(a):.3f} Msamples/s")
    print(f"B {args.b}: {statistics.mean(b):.3f} ± {se(b):.3f} Msamples/s")
    print(f"B / A = {m:.3f}, 95% CI [{m - half:.3f}, {m + half:.3f}] over {args.runs} pairs")


if __name__ == "__main__":
    main()
