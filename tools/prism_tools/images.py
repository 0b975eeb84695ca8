"""Image I/O through OpenImageIO: named float channels in, PNG previews out."""

from __future__ import annotations

import pathlib

import numpy as np
import OpenImageIO as oiio


def read_channels(path: str | pathlib.Path) -> dict[str, np.ndarray]:
    """All channels of an image as float32 arrays of shape (height, width), by name."""
    inp = oiio.ImageInput.open(str(path))
    if inp is None:
        raise OSError(f"cannot open {path}: {oiio.geterror()}")
    names = list(inp.spec().channelnames)
    pixels = inp.read_image(format="float")
    inp.close()
    if pixels is None:
        raise OSError(f"cannot read {path}")
    return {name: np.asarray(pixels[..., i], dtype=np.float32) for i, name in enumerate(names)}


def rgb(path: str | pathlib.Path) -> np.ndarray:
    """The R, G, B channels as (height, width, 3)."""
    ch = read_channels(path)
    return np.stack([ch["R"], ch["G"], ch["B"]], axis=-1)


def srgb_encode(linear: np.ndarray) -> np.ndarray:
    x = np.clip(linear, 0.0, None)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1.0 / 2.4) - 0.055)


def write_png(path: str | pathlib.Path, rgb01: np.ndarray) -> None:
    """Writes an (h, w, 3) array of display values in [0, 1] as 8-bit PNG."""
    data = (np.clip(rgb01, 0.0, 1.0) * 255.0 + 0.5).astype(np.uint8)
    h, w, c = data.shape
    out = oiio.ImageOutput.create(str(path))
    out.open(str(path), oiio.ImageSpec(w, h, c, "uint8"))
    out.write_image(data)
    out.close()
