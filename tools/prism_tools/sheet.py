"""A PNG contact sheet of a render's layers: the colour image, depth, normals (world and
camera frame, mapped n/2 + 1/2), alpha and the id layers in false colour.

    python -m prism_tools.sheet out.exr sheet.png
"""

from __future__ import annotations

import argparse
import pathlib

import numpy as np

from . import images, outputs


def _false_colour(ids: np.ndarray) -> np.ndarray:
    """A fixed pseudo-random colour per id (0, the background, black)."""
    h = (ids.astype(np.uint64) * np.uint64(2654435761)) & np.uint64(0xFFFFFF)
    rgb = np.stack([(h >> np.uint64(s)) & np.uint64(255) for s in (16, 8, 0)], axis=-1) / 255.0
    rgb = 0.25 + 0.75 * rgb
    rgb[ids == 0] = 0.0
    return rgb


def _depth(d: np.ndarray) -> np.ndarray:
    ok = np.isfinite(d)
    out = np.zeros(d.shape + (3,))
    if ok.any():
        lo, hi = np.percentile(d[ok], [1, 99])
        v = 1.0 - np.clip((d - lo) / max(hi - lo, 1e-12), 0, 1)
        out[ok] = v[ok, None]
    return out


def tiles(r: outputs.Render) -> list[tuple[str, np.ndarray]]:
    out = []
    if all(c in r.channels for c in "RGB"):
        out.append(("rgb", images.srgb_encode(r.rgb())))
    layers = sorted({c.split(".", 1)[0] for c in r.channels if "." in c and not c.startswith("S0.")})
    for name in layers:
        v = r.layer(name)
        if name in ("depth", "distance"):
            out.append((name, _depth(v)))
        elif v.dtype == np.uint32:
            out.append((name, _false_colour(v)))
        elif name.startswith(("normal", "geo_normal")):
            out.append((name, np.where(np.any(v != 0, axis=-1, keepdims=True), 0.5 * v + 0.5, 0.0)))
        elif v.ndim == 2:
            out.append((name, np.repeat(np.clip(v, 0, 1)[..., None], 3, axis=-1)))
        elif v.shape[-1] == 2:
            out.append((name, np.concatenate([np.mod(v, 1.0), np.zeros(v.shape[:2] + (1,))], axis=-1)))
        else:
            lo, hi = np.nanmin(v), np.nanmax(v)
            out.append((name, (v - lo) / max(hi - lo, 1e-12)))
    return out


def sheet(r: outputs.Render, columns: int = 4) -> np.ndarray:
    """The tiles side by side, `columns` per row, 4-pixel gaps."""
    ts = [t for _, t in tiles(r)]
    h, w = ts[0].shape[:2]
    rows = (len(ts) + columns - 1) // columns
    gap = 4
    img = np.ones((rows * (h + gap) - gap, min(columns, len(ts)) * (w + gap) - gap, 3))
    for k, t in enumerate(ts):
        y, x = divmod(k, columns)
        img[y * (h + gap) : y * (h + gap) + h, x * (w + gap) : x * (w + gap) + w] = t
    return img


def main(argv: list[str] | None = None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("exr", type=pathlib.Path)
    p.add_argument("png", type=pathlib.Path)
    p.add_argument("--columns", type=int, default=4)
    a = p.parse_args(argv)
    images.write_png(a.png, sheet(outputs.read(a.exr), a.columns))


if __name__ == "__main__":
    main()
