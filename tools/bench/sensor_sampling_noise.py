"""Noise of a NIR band and of Y under the three wavelength samplings, at equal time.

    tools/.venv/bin/python tools/bench/sensor_sampling_noise.py [--prism target/release/prism] [--spp 32]

The ColorChecker under a 2856 K blackbody sky, spectral range 360-1000 nm, the `rgb_nir` sensor
(Sony ILCE-7M3 curves plus an 850 nm Gaussian band, `nir.Y`). A patch's pixels are independent
estimates of one radiance, so their relative standard deviation is the per-pixel noise; at equal
time it scales as sigma * sqrt(t / t_ref) (variance ~ 1 / samples). Prints, per sampling, the render
time and the median over the 24 patches of the equal-time relative noise of nir.Y, camera.G and Y,
relative to Uniform.
"""

from __future__ import annotations

import argparse
import pathlib
import re
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))
from prism_tools import colorchecker as cc  # noqa: E402
from prism_tools.images import read_channels  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--prism", default=str(ROOT / "target/release/prism"))
    ap.add_argument("--spp", type=int, default=32)
    args = ap.parse_args()
    sensor = f'File("{ROOT / "configs/sensors/rgb_nir.ron"}")'
    rows = {}
    for sampling in ["Visible", "Uniform", "Sensor"]:
        text = cc.scene_ron(
            spp=args.spp,
            sensor=sensor,
            emitter="Scaled(0.001, Blackbody(2856))",
            spectral=f"range: (360, 1000), sampling: {sampling}, wavelengths: 8",
            hi=1000.0,
        )
        with tempfile.TemporaryDirectory() as tmp:
            scene = pathlib.Path(tmp) / "s.ron"
            scene.write_text(text)
            out = pathlib.Path(tmp) / "o.exr"
            err = subprocess.run([args.prism, "render", str(scene), "-o", str(out), "-q"], check=True, capture_output=True, text=True).stderr
            secs = float(re.search(r"in ([0-9.]+) s", err).group(1))
            ch = read_channels(out)
        h, w = ch["Y"].shape
        rel = {}
        for name in ["nir.Y", "camera.G", "Y"]:
            vals = []
            for i in range(24):
                r, c = cc.patch_pixels(i, w, h)
                v = ch[name][r, c].astype(np.float64)
                vals.append(v.std(ddof=1) / v.mean())
            rel[name] = np.median(vals)
        rows[sampling] = (secs, rel)
    t0 = rows["Uniform"][0]
    print(f"{'sampling':10s} {'time s':>8s} " + " ".join(f"{n + ' (eq. time, ×Uniform)':>28s}" for n in ["nir.Y", "camera.G", "Y"]))
    for s, (t, rel) in rows.items():
        eq = {n: rel[n] * np.sqrt(t / t0) for n in rel}
        ref = {n: rows["Uniform"][1][n] for n in rel}
        print(f"{s:10s} {t:8.2f} " + " ".join(f"{eq[n]:>16.4f} ({eq[n] / ref[n]:5.2f}x)      " for n in eq))


if __name__ == "__main__":
    main()
