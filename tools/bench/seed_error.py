"""relMSE and render time of prism on one scene, averaged over seeds, against a reference EXR:
a quick A/B of render settings at equal spp (error_time.py draws whole curves).

    tools/.venv/bin/python tools/bench/seed_error.py REF.exr SCENE.ron --spp 64 [--seeds 1,2,3]
        [--blocks] [-- PRISM RENDER ARGS...]

relMSE as in error_time.py: mean over pixels and R, G, B of (x − ref)² / (ref² + 0.01). Prints
the mean relMSE, the mean render seconds (prism's own summary line: render time, scene loading
excluded) and their product (lower is better at equal spp); `--blocks` adds relMSE per image
block (6 × 8 blocks, ·10⁻³) of the first seed, to see where the error is.
"""

from __future__ import annotations

import argparse
import pathlib
import re
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from common import ROOT  # noqa: E402
from error_time import read_rgb  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("ref", type=pathlib.Path)
    ap.add_argument("scene", type=pathlib.Path)
    ap.add_argument("--spp", type=int, required=True)
    ap.add_argument("--seeds", default="1,2,3")
    ap.add_argument("--blocks", action="store_true")
    ap.add_argument("--prism", type=pathlib.Path, default=ROOT / "target/release/prism")
    argv = sys.argv[1:]
    cut = argv.index("--") if "--" in argv else len(argv)
    args = ap.parse_args(argv[:cut])
    # After `--`: more `prism render` arguments.
    args.extra = argv[cut + 1 :]
    ref = read_rgb(args.ref)
    errors, seconds = [], []
    with tempfile.TemporaryDirectory() as tmp:
        for i, seed in enumerate(int(s) for s in args.seeds.split(",")):
            out = pathlib.Path(tmp) / "x.exr"
            cmd = [str(args.prism), "render", str(args.scene), "-o", str(out), "-q", "--spp", str(args.spp),
                   "--seed", str(seed), *args.extra]
            err = subprocess.run(cmd, check=True, capture_output=True, text=True).stderr
            seconds.append(float(re.search(r"in ([0-9.]+) s \(", err).group(1)))
            e = np.mean((read_rgb(out) - ref) ** 2 / (ref**2 + 0.01), axis=-1)
            errors.append(float(e.mean()))
            if args.blocks and i == 0:
                h, w = e.shape
                blocks = e[: h - h % 6, : w - w % 8].reshape(6, h // 6, 8, w // 8).mean(axis=(1, 3))
                print(np.array2string(blocks * 1e3, precision=2, max_line_width=160))
    e, t = float(np.mean(errors)), float(np.mean(seconds))
    per = " ".join(f"{x:.5f}" for x in errors)
    print(f"{args.scene.name} {' '.join(args.extra)} spp {args.spp}: relMSE {e:.5f} ({per}), "
          f"{t:.2f} s, relMSE x s {e * t:.5f}")


if __name__ == "__main__":
    main()
