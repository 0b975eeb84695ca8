"""Throughput of prism against Mitsuba 3 on the Cornell box, measured in one run on one machine.

    tools/.venv/bin/python tools/bench/cornell_throughput.py [--spp 256] [--repeats 3]

prism renders scenes/cornell.ron (Mitsuba's cornell_box() with a box filter) through its CLI,
with the packet kernel (`--simd auto`) and the scalar integrator (`--simd off`);
Mitsuba 3.9.1 renders the same dict (`mi.cornell_box()` with the box filter) in the
`scalar_spectral` and `llvm_ad_spectral` variants. Each renderer gets one warm-up render (Mitsuba's
LLVM variant compiles its kernels then), then `--repeats` timed renders; the best time counts.
Throughput = width · height · spp / render seconds (scene loading excluded for both: prism's
summary line reports render time separately; Mitsuba's scene is loaded before the timer starts).

`llvm_ad_spectral` needs libLLVM >= 19 (Debian: `apt-get install -y libllvm19`, then
DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1); it is skipped if unavailable.
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import re
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from common import ROOT, llvm_error, mitsuba_env  # noqa: E402


def prism_throughput(binary: pathlib.Path, spp: int, repeats: int, threads: int | None, simd: str = "auto") -> dict:
    times = []
    with tempfile.TemporaryDirectory() as tmp:
        for i in range(repeats + 1):
            cmd = [str(binary), "render", str(ROOT / "scenes/cornell.ron"), "-o", f"{tmp}/c.exr", "-q", "--spp", str(spp), "--simd", simd]
            if threads:
                cmd += ["--threads", str(threads)]
            err = subprocess.run(cmd, check=True, capture_output=True, text=True).stderr
            seconds = float(re.search(r"in ([0-9.]+) s \(", err).group(1))
            if i > 0:
                times.append(seconds)
    best = min(times)
    return {"seconds": best, "msamples_per_s": 256 * 256 * spp / best / 1e6, "all_seconds": times}


def mitsuba_throughput(variant: str, spp: int, repeats: int) -> dict | None:
    """Runs in a subprocess so each variant starts fresh (Dr.Jit fixes its backend per process)."""
    code = f"""
import json, time, mitsuba as mi
try:
    mi.set_variant({variant!r})
    d = mi.cornell_box(); d['sensor']['film']['rfilter'] = {{'type': 'box'}}
    scene = mi.load_dict(d)
    mi.render(scene, spp={spp}, seed=100)  # warm-up (LLVM compiles its kernels here)
    times = []
    for k in range({repeats}):
        t = time.perf_counter(); img = mi.render(scene, spp={spp}, seed=k)
        import drjit as dr; dr.eval(img); dr.sync_thread()
        times.append(time.perf_counter() - t)
    print(json.dumps(times))
except Exception as e:
    print(json.dumps({{"error": str(e)}}))
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=mitsuba_env())
    try:
        res = json.loads(out.stdout.strip().splitlines()[-1])
    except (IndexError, json.JSONDecodeError):
        return {"error": llvm_error(variant, out.stderr.strip()[-300:])}
    if isinstance(res, dict):
        return {"error": llvm_error(variant, res["error"])} if "error" in res else res
    best = min(res)
    return {"seconds": best, "msamples_per_s": 256 * 256 * spp / best / 1e6, "all_seconds": res}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--spp", type=int, default=256)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--prism", type=pathlib.Path, default=ROOT / "target/release/prism")
    ap.add_argument("--json", type=pathlib.Path, help="also write the results here")
    args = ap.parse_args()
    results = {
        "machine": {"cpus": os.cpu_count(), "load_average_before": os.getloadavg()},
        "spp": args.spp,
        "prism": prism_throughput(args.prism, args.spp, args.repeats, None),
        "prism_scalar": prism_throughput(args.prism, args.spp, args.repeats, None, "off"),
        "prism_1_thread": prism_throughput(args.prism, args.spp // 4, args.repeats, 1),
        "prism_scalar_1_thread": prism_throughput(args.prism, args.spp // 4, args.repeats, 1, "off"),
        "mitsuba_scalar_spectral": mitsuba_throughput("scalar_spectral", args.spp, args.repeats),
        "mitsuba_llvm_ad_spectral": mitsuba_throughput("llvm_ad_spectral", args.spp, args.repeats),
    }
    p = results["prism"]["msamples_per_s"]
    print(f"Cornell box 256x256, {args.spp} spp, {os.cpu_count()} cores (best of {args.repeats}):")
    for key in ("prism", "prism_scalar", "prism_1_thread", "prism_scalar_1_thread", "mitsuba_scalar_spectral", "mitsuba_llvm_ad_spectral"):
        r = results[key]
        if "error" in r:
            print(f"  {key:26s} unavailable: {r['error'][:120]}")
        else:
            print(f"  {key:26s} {r['msamples_per_s']:6.3f} Msamples/s   prism / this = {p / r['msamples_per_s']:.2f}x")
    if args.json:
        args.json.write_text(json.dumps(results, indent=2) + "\n")


if __name__ == "__main__":
    main()
