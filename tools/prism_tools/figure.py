"""The side-by-side figure of a comparison: prism, Mitsuba, and two false-colour error maps
(per-pixel relative difference of luminance; per-tile relative difference with the tiles the bias
test flags outlined)."""

from __future__ import annotations

import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.patches import Rectangle  # noqa: E402

from .images import srgb_encode  # noqa: E402
from .renderers import xyz_to_srgb_matrix  # noqa: E402

#: Colour scale of the per-pixel map: ±20% (per-pixel noise at test settings is of that order).
PIXEL_RANGE = 0.2
#: Colour scale of the tile map: ±5% (the size of bias worth seeing at a glance).
TILE_RANGE = 0.05


def _display(rgb: np.ndarray, white: float) -> np.ndarray:
    return np.clip(srgb_encode(rgb / white), 0.0, 1.0)


def _rgb_and_y(image: np.ndarray, channels: list[str]) -> tuple[np.ndarray, np.ndarray]:
    """Linear sRGB and luminance from whichever of R, G, B / X, Y, Z a comparison has."""
    if "R" in channels:
        rgb = image[..., [channels.index(c) for c in "RGB"]]
    else:
        rgb = image[..., [channels.index(c) for c in "XYZ"]] @ xyz_to_srgb_matrix().T
    y = image[..., channels.index("Y")] if "Y" in channels else rgb @ np.array([0.2126, 0.7152, 0.0722])
    return rgb, y


def write_figure(result, path: str | pathlib.Path) -> None:
    """Writes the figure of a `compare.Comparison` as PNG."""
    prism, prism_y = _rgb_and_y(result.prism_image, result.channels)
    mitsuba, mitsuba_y = _rgb_and_y(result.mitsuba_image, result.channels)
    # White: the 97th percentile, so a small bright emitter does not darken the rest.
    white = max(float(np.percentile(mitsuba_y, 97)), 1e-6)
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.where(mitsuba_y > 0, prism_y / mitsuba_y - 1.0, 0.0)
    bias = result.bias
    # The tile map shows Y, or G when the scene writes no XYZ.
    tile_rel = bias.rel_diff[..., result.channels.index("Y" if "Y" in result.channels else "G")]
    flagged = (bias.p_adjusted < bias.alpha).any(axis=-1)

    h, w = mitsuba.shape[:2]
    fig, axes = plt.subplots(1, 4, figsize=(16, 4.4 * h / w + 0.6), constrained_layout=True)
    axes[0].imshow(_display(prism, white))
    axes[0].set_title("prism")
    axes[1].imshow(_display(mitsuba, white))
    axes[1].set_title("Mitsuba 3")
    im = axes[2].imshow(rel, cmap="RdBu_r", vmin=-PIXEL_RANGE, vmax=PIXEL_RANGE)
    axes[2].set_title("prism / Mitsuba − 1 (Y, per pixel)")
    fig.colorbar(im, ax=axes[2], shrink=0.8, format=lambda v, _: f"{v:+.0%}")
    g = bias.grid
    th, tw = h // g, w // g
    im = axes[3].imshow(tile_rel, cmap="RdBu_r", vmin=-TILE_RANGE, vmax=TILE_RANGE, extent=(0, g * tw, g * th, 0))
    for r, c in zip(*np.nonzero(flagged)):
        axes[3].add_patch(Rectangle((c * tw, r * th), tw, th, fill=False, edgecolor="black", linewidth=2))
    p = bias.worst[0]
    axes[3].set_title(f"per tile (Y); biased tiles outlined\nmin Holm p = {p:.2g}", fontsize=10)
    fig.colorbar(im, ax=axes[3], shrink=0.8, format=lambda v, _: f"{v:+.0%}")
    for ax in axes:
        ax.set_xticks([])
        ax.set_yticks([])
    verdict = "PASS" if result.passed else "FAIL: bias"
    fig.suptitle(f"{pathlib.Path(result.scene).name}: {verdict}")
    fig.savefig(path, dpi=80)
    plt.close(fig)
