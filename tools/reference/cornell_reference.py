#!/usr/bin/env python3
"""Make the Mitsuba 3 Cornell-box reference statistics used by prism's tests.

prism's test suite compares its Cornell box render against Mitsuba 3. Committing
a reference image would bloat the repository, so this script commits only
summary statistics, each with a Monte Carlo standard error so the tests can use
tolerances that reflect the noise in the reference itself.

Scene
    Exactly Mitsuba's built-in Cornell box, with a single change: the pixel
    reconstruction filter is a box filter instead of the default gaussian::

        d = mi.cornell_box()
        d['sensor']['film']['rfilter'] = {'type': 'box'}

    That gives 256x256 pixels, the `path` integrator with max_depth 8 (rr_depth
    left at its default, 5), a perspective camera, an independent sampler and an
    `hdrfilm` with rgb float32 output. We render it with a spectral variant,
    where Mitsuba converts the spectral samples to linear sRGB (Rec. 709
    primaries) inside the film.

Statistics
    K independent renders (``mi.render(scene, seed=k, spp=S)`` for k = 0..K-1)
    are made. For each render we take the per-channel mean over the whole image
    and over each tile of an 8x8 grid of 32x32-pixel tiles (row-major, tile row
    0 is at the top of the image, i.e. image row 0 as Mitsuba writes it). The
    reported values are the averages over the K renders, and the standard
    errors come from the spread of the K per-render values:
    ``std(ddof=1) / sqrt(K)``.

LLVM variant
    llvm_ad_spectral needs libLLVM >= 19. On Debian 12:
    ``apt-get install -y libllvm19`` and, to be explicit about which library is
    used, ``export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1``.
    When that variant cannot be loaded, scalar_spectral is used instead.

Usage (from the repository root)::

    tools/.venv/bin/python tools/reference/cornell_reference.py --spp 1024 --renders 8
"""

from __future__ import annotations

import argparse
import json
import math
import re
import sys
import time
from pathlib import Path

import mitsuba as mi
import numpy as np

REPO_ROOT = Path(__file__).resolve().parents[2]
DEFAULT_OUT = "tests/data/cornell_mitsuba.json"
LLVM_VARIANT = "llvm_ad_spectral"
SCALAR_VARIANT = "scalar_spectral"
TILE_GRID = 8
SIGNIFICANT_DIGITS = 7


def variant_works(variant: str) -> bool:
    """True when `variant` can be selected and can actually run a kernel."""
    try:
        mi.set_variant(variant)
        import drjit as dr

        # An LLVM variant only fails once a kernel is compiled, so run one.
        total = dr.sum(dr.arange(mi.Float, 4))
        return int(np.asarray(total).reshape(-1)[0]) == 6
    except Exception as err:  # noqa: BLE001 - any failure means "unusable"
        print(f"variant {variant} is unusable: {err}", file=sys.stderr)
        return False


def default_variant() -> str:
    return LLVM_VARIANT if variant_works(LLVM_VARIANT) else SCALAR_VARIANT


def scene_dict() -> dict:
    """Mitsuba's Cornell box with a box reconstruction filter."""
    d = mi.cornell_box()
    d["sensor"]["film"]["rfilter"] = {"type": "box"}
    return d


def load_scene(variant: str):
    mi.set_variant(variant)
    return mi.load_dict(scene_dict())


def render(scene, seed: int, spp: int) -> np.ndarray:
    """One render as a float64 array of shape (height, width, 3), row 0 at the top."""
    image = np.array(mi.render(scene, seed=seed, spp=spp), dtype=np.float64)
    return image[..., :3]


def timed_render(scene, seed: int, spp: int) -> tuple[np.ndarray, float]:
    start = time.perf_counter()
    image = render(scene, seed, spp)
    return image, time.perf_counter() - start


def tile_means(image: np.ndarray, grid: int) -> np.ndarray:
    """Per-channel means of a grid x grid tiling, shape (grid, grid, channels)."""
    height, width, channels = image.shape
    if height % grid or width % grid:
        raise ValueError(f"{width}x{height} image does not split into a {grid}x{grid} grid")
    tiles = image.reshape(grid, height // grid, grid, width // grid, channels)
    return tiles.mean(axis=(1, 3))


def mean_and_stderr(samples: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Mean over axis 0 and its standard error from the spread along axis 0."""
    count = samples.shape[0]
    return samples.mean(axis=0), samples.std(axis=0, ddof=1) / math.sqrt(count)


def rounded(values) -> list | float:
    """Nested lists of floats rounded to SIGNIFICANT_DIGITS significant digits."""
    array = np.asarray(values, dtype=np.float64)
    if array.ndim == 0:
        return float(f"{float(array):.{SIGNIFICANT_DIGITS}g}")
    return [rounded(item) for item in array]


def to_json(value) -> str:
    """Indented JSON with each innermost list of numbers kept on one line."""
    text = json.dumps(value, indent=2)
    number_list = re.compile(r"\[\s*(-?[\d.eE+-]+(?:,\s*-?[\d.eE+-]+)*)\s*\]")
    return number_list.sub(lambda m: "[" + ", ".join(re.split(r",\s*", m.group(1))) + "]", text)


def parse_args() -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.split("\n", 1)[0])
    parser.add_argument("--spp", type=int, default=1024, help="samples per pixel of each render")
    parser.add_argument("--renders", type=int, default=8, help="number of independent renders (K)")
    parser.add_argument(
        "--variant",
        default=None,
        help=f"Mitsuba variant (default: {LLVM_VARIANT} if it loads, else {SCALAR_VARIANT})",
    )
    parser.add_argument("--out", default=DEFAULT_OUT, help="output JSON, relative to the repository root")
    parser.add_argument("--exr", default=None, help="also write the averaged image here (float32 EXR)")
    return parser.parse_args()


def main() -> None:
    args = parse_args()
    if args.renders < 2:
        sys.exit("--renders must be at least 2 to estimate a standard error")

    variant = args.variant or default_variant()
    scene = load_scene(variant)
    print(f"mitsuba {mi.__version__}, variant {variant}, {args.renders} renders x {args.spp} spp", flush=True)

    images = []
    render_seconds = 0.0
    for seed in range(args.renders):
        image, seconds = timed_render(scene, seed=seed, spp=args.spp)
        render_seconds += seconds
        images.append(image)
        print(f"render {seed}: {seconds:.1f} s, mean {image.mean(axis=(0, 1))}", flush=True)
    images = np.stack(images)
    renders, height, width, _ = images.shape

    image_mean, image_mean_stderr = mean_and_stderr(images.mean(axis=(1, 2)))
    tiles, tiles_stderr = mean_and_stderr(np.stack([tile_means(image, TILE_GRID) for image in images]))

    if args.exr:
        mi.Bitmap(images.mean(axis=0).astype(np.float32)).write(args.exr)
        print(f"wrote {args.exr}", flush=True)

    result = {
        "description": (
            f"Statistics of Mitsuba {mi.__version__} renders of mi.cornell_box() with the film's "
            "rfilter replaced by {'type': 'box'} (256x256, path integrator max_depth 8, rr_depth 5, "
            f"independent sampler, hdrfilm rgb float32, linear sRGB output), variant {variant}. "
            f"{renders} independent renders (seed 0..{renders - 1}) of {args.spp} spp each. "
            "image_mean and tile_means are per-channel means of the average image; the standard "
            "errors are std(ddof=1)/sqrt(renders) of the per-render means. Tiles are an 8x8 grid "
            "of 32x32 pixels, row-major, tile row 0 at the top of the image. "
            "Made by tools/reference/cornell_reference.py."
        ),
        "command": (
            f"tools/.venv/bin/python tools/reference/cornell_reference.py "
            f"--spp {args.spp} --renders {renders}"
        ),
        "mitsuba_version": mi.__version__,
        "variant": variant,
        "spp_per_render": args.spp,
        "renders": renders,
        "width": width,
        "height": height,
        "filter": "box",
        "max_depth": 8,
        "rr_depth": 5,
        "channels": ["R", "G", "B"],
        "image_mean": rounded(image_mean),
        "image_mean_stderr": rounded(image_mean_stderr),
        "tile_grid": TILE_GRID,
        "tile_means": rounded(tiles),
        "tile_stderr": rounded(tiles_stderr),
        "wall_seconds": round(render_seconds, 1),
    }

    out = Path(args.out)
    if not out.is_absolute():
        out = REPO_ROOT / out
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(to_json(result) + "\n")
    print(f"wrote {out}", flush=True)


if __name__ == "__main__":
    main()
