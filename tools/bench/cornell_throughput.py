"""Throughput of prism against Mitsuba 3 on the Cornell box, measured in one run on one machine.

    tools/.venv/bin/python tools/bench/cornell_throughput.py [--spp 256] [--repeats 3] [--json F]

prism renders scenes/cornell.ron (Mitsuba's cornell_box() with a box filter) through its CLI,
with the packet kernel (`--simd auto`) and the scalar integrator (`--simd off`);
Mitsuba 3.9.1 renders the same dict (`mi.cornell_box()` with the box filter) in the
`scalar_spectral` and `llvm_ad_spectral` variants, each in a server process that loads the scene
and renders one warm-up first (the LLVM variant compiles its kernels then). Then `--repeats`
interleaved rounds (tools/bench/rounds.py: each renderer once per round, the order rotated, the
load average recorded): medians, min–max and same-round ratios. Throughput = width · height · spp
/ render seconds (scene loading excluded for both). The images of the last round are compared
(rounds.agreement): Mitsuba's two variants with each other, prism's with Mitsuba's scalar one.

`llvm_ad_spectral` needs libLLVM >= 19 (Debian: `apt-get install -y libllvm19`; common.LLVM19 is
found by itself, or set DRJIT_LIBLLVM_PATH); it is skipped, saying why, if unavailable.
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import sys
import tempfile

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import rounds  # noqa: E402
from common import ROOT, log  # noqa: E402

PAIRS = [("prism", "mitsuba_llvm_ad_spectral"), ("prism_scalar", "mitsuba_llvm_ad_spectral"),
         ("prism", "mitsuba_scalar_spectral"), ("prism_scalar", "mitsuba_scalar_spectral"), ("prism", "prism_scalar"),
         ("mitsuba_llvm_ad_spectral", "mitsuba_scalar_spectral")]


def measure(binary: pathlib.Path, spp: int, repeats: int, threads: int | None, tmp: pathlib.Path,
            also: list[tuple[str, pathlib.Path]] = ()) -> dict:
    """The interleaved rounds; `also`: (name, binary) of further prism builds (packet kernel)."""
    scene = ROOT / "scenes/cornell.ron"
    runners = {
        "prism": rounds.prism_runner(binary, scene, spp, threads, tmp / "prism.exr", ["--simd", "auto"]),
        "prism_scalar": rounds.prism_runner(binary, scene, spp, threads, tmp / "prism_scalar.exr", ["--simd", "off"]),
    }
    for label, other in also:
        runners[label] = rounds.prism_runner(other, scene, spp, threads, tmp / f"{label}.exr", ["--simd", "auto"])
    runners["prism"](100)  # warm-up: page cache, CPU clocks
    servers, errors = [], {}
    for v in ("scalar_spectral", "llvm_ad_spectral"):
        try:
            servers.append(rounds.MitsubaServer(sys.executable, "cornell_box", v, spp, threads, tmp / f"{v}.exr"))
            runners[f"mitsuba_{v}"] = servers[-1]
        except RuntimeError as e:
            errors[f"mitsuba_{v}"] = str(e)
            log(f"  mitsuba {v} unavailable: {e}")
    try:
        runs = rounds.run_rounds(runners, repeats)
    finally:
        for s in servers:
            s.close()
    pairs = PAIRS + [p for label, _ in also for p in ((label, "mitsuba_llvm_ad_spectral"), (label, "prism"))]
    out = {"runs": runs, "summary": rounds.summary(runs, pairs), "unavailable": errors, "agreement": {}}
    images = {k: tmp / f"{k.removeprefix('mitsuba_')}.exr" for k in runners}
    for a, b in [("mitsuba_llvm_ad_spectral", "mitsuba_scalar_spectral"), ("prism", "mitsuba_scalar_spectral"),
                 ("prism_scalar", "mitsuba_scalar_spectral")]:
        if a in runners and b in runners:
            out["agreement"][f"{a} vs {b}"] = rounds.agreement(rounds.read_rgb(images[a]), rounds.read_rgb(images[b]))
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--spp", type=int, default=256)
    ap.add_argument("--repeats", type=int, default=3, help="interleaved rounds")
    ap.add_argument("--threads", type=int, help="threads of every renderer (default: all cores)")
    ap.add_argument("--prism", type=pathlib.Path, default=ROOT / "target/release/prism")
    ap.add_argument("--json", type=pathlib.Path, help="also write the results here")
    ap.add_argument("--also", action="append", default=[], metavar="NAME=BINARY",
                    help="another prism build whose packet kernel joins the rounds as NAME (repeatable)")
    args = ap.parse_args()
    also = [(a.split("=", 1)[0], pathlib.Path(a.split("=", 1)[1])) for a in args.also]
    with tempfile.TemporaryDirectory() as tmp:
        res = measure(args.prism, args.spp, args.repeats, args.threads, pathlib.Path(tmp), also)
    res.update(machine={"cpus": os.cpu_count(), "load_average_after": os.getloadavg()}, spp=args.spp,
               prism=str(args.prism))
    title = f"Cornell box 256x256, {args.spp} spp, {args.threads or os.cpu_count()} threads, {args.repeats} rounds"
    log("\n".join(rounds.markdown(title, res["summary"])))
    for k, e in res["unavailable"].items():
        log(f"{k} unavailable: {e[:300]}")
    for k, a in res["agreement"].items():
        log(f"images {k}: mean ratio {a['mean_ratio']:.4f}, z {a['z_image']:.1f} (image), "
            f"max |z| {a['max_abs_z_block']:.1f} over {a['blocks']} blocks")
    if args.json:
        args.json.write_text(json.dumps(res, indent=2) + "\n")


if __name__ == "__main__":
    main()
