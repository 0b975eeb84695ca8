"""Writes the small test textures that scenes/materials use (committed; rerun to regenerate).

    tools/.venv/bin/python tools/make_test_textures.py

- scenes/textures/grid.png: 64x64 sRGB 8-bit, coloured cells with dark lines (a bitmap
  reflectance test: orientation, filtering and colours are easy to see).
- scenes/textures/leaf_alpha.png: 64x64 8-bit grey, a disc of opacity 1 fading to 0 (for mask).
"""

from __future__ import annotations

import pathlib

import numpy as np
import OpenImageIO as oiio

OUT = pathlib.Path(__file__).resolve().parent.parent / "scenes" / "textures"


def write_png(path: pathlib.Path, pixels: np.ndarray) -> None:
    h, w, c = pixels.shape
    spec = oiio.ImageSpec(w, h, c, "uint8")
    out = oiio.ImageOutput.create(str(path))
    out.open(str(path), spec)
    out.write_image(pixels.astype(np.uint8))
    out.close()
    print(f"wrote {path.relative_to(OUT.parent.parent)}")


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    y, x = np.mgrid[0:64, 0:64]
    cells = np.zeros((64, 64, 3))
    palette = np.array([[230, 60, 50], [60, 170, 70], [50, 90, 220], [235, 200, 60]])
    cells[:] = palette[((x // 16) + 2 * (y // 16)) % 4]
    # The top-left cell is white, so texture orientation is unambiguous.
    cells[:16, :16] = 240
    lines = (x % 16 == 0) | (y % 16 == 0)
    cells[lines] = 20
    write_png(OUT / "grid.png", cells)
    r = np.hypot(x - 31.5, y - 31.5) / 32.0
    alpha = np.clip((1.0 - r) * 3.0, 0.0, 1.0) * 255.0
    write_png(OUT / "leaf_alpha.png", np.repeat(alpha[..., None], 3, axis=2))


if __name__ == "__main__":
    main()
