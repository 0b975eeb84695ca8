"""Make `scenes/textures/sky.exr`, the small environment map the example scenes use.

Run: `tools/.venv/bin/python tools/make_test_envmap.py` (numpy and OpenImageIO).

A 128×64 latitude-longitude map of linear sRGB radiance, half-float OpenEXR: a sky that deepens
from a pale horizon to a blue zenith, a warm sun (a disk of 2.5° radius with a soft glow) 35°
above the horizon, and a dim brown ground. Pixel directions follow Mitsuba 3's `envmap` (and
prism's), with +y up: column i is at φ = 2π (i + ½)/W, row j at θ = π j/(H − 1) from +y, and the
direction is (sin φ sin θ, cos θ, −cos φ sin θ).
"""

from __future__ import annotations

import pathlib

import numpy as np
import OpenImageIO as oiio

OUT = pathlib.Path(__file__).resolve().parent.parent / "scenes" / "textures" / "sky.exr"
WIDTH, HEIGHT = 128, 64
SUN_ELEVATION, SUN_AZIMUTH = np.radians(35.0), np.radians(140.0)
SUN_RADIUS = np.radians(2.5)


def directions() -> np.ndarray:
    """Unit direction of every pixel, shape (H, W, 3)."""
    theta = np.pi * np.arange(HEIGHT) / (HEIGHT - 1)
    phi = 2 * np.pi * (np.arange(WIDTH) + 0.5) / WIDTH
    t, p = np.meshgrid(theta, phi, indexing="ij")
    return np.stack([np.sin(p) * np.sin(t), np.cos(t), -np.cos(p) * np.sin(t)], axis=-1)


def main() -> None:
    d = directions()
    up = np.clip(d[..., 1], 0.0, 1.0)[..., None]
    horizon = np.array([0.85, 0.9, 1.0])
    zenith = np.array([0.15, 0.3, 0.8])
    sky = horizon + (zenith - horizon) * up**0.5
    ground = np.array([0.12, 0.09, 0.06])
    img = np.where(d[..., 1:2] >= 0.0, sky, ground)

    t = np.pi / 2 - SUN_ELEVATION
    sun = np.array([np.sin(SUN_AZIMUTH) * np.sin(t), np.cos(t), -np.cos(SUN_AZIMUTH) * np.sin(t)])
    angle = np.arccos(np.clip(d @ sun, -1.0, 1.0))[..., None]
    warm = np.array([1.0, 0.85, 0.6])
    disk = np.where(angle <= SUN_RADIUS, 400.0, 0.0)
    glow = 8.0 * np.exp(-0.5 * (angle / np.radians(8.0)) ** 2)
    img = img + (disk + glow) * warm

    OUT.parent.mkdir(parents=True, exist_ok=True)
    spec = oiio.ImageSpec(WIDTH, HEIGHT, 3, oiio.HALF)
    spec.attribute("compression", "zip")
    out = oiio.ImageOutput.create(str(OUT))
    if not out.open(str(OUT), spec):
        raise RuntimeError(oiio.geterror())
    out.write_image(img.astype(np.float32))
    out.close()
    print(f"wrote {OUT} ({OUT.stat().st_size} bytes)")


if __name__ == "__main__":
    main()
