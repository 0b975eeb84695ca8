"""Statistics for comparing two Monte Carlo renderers.

Two renderers agree if their images have the same expectation. Each is rendered K times with
independent seeds; a region's mean then has an empirical spread across the K renders, so a
difference between renderers can be judged against noise instead of against a fixed tolerance:

- `bias_test`: per tile and channel, Welch's t-test between the two sets of K tile means, with
  Holm's step-down correction over all tiles and channels. Bias (a test failure) is a corrected
  p-value below `alpha`; noise alone fails with probability at most `alpha`.
- `mean_ci`: per-channel image mean with a t confidence interval.
- `rel_mse`: relative mean squared error against a reference, (x − r)² / (r² + ε), averaged.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy import stats


def tile_means(image: np.ndarray, grid: int) -> np.ndarray:
    """Per-channel means over a grid×grid tiling: (grid, grid, channels). Edge pixels that do
    not fill a whole tile are dropped."""
    h, w = image.shape[:2]
    th, tw = h // grid, w // grid
    img = image[: th * grid, : tw * grid]
    if img.ndim == 2:
        img = img[..., None]
    return img.reshape(grid, th, grid, tw, img.shape[-1]).mean(axis=(1, 3))


def mean_ci(renders: list[np.ndarray], confidence: float = 0.95) -> tuple[np.ndarray, np.ndarray]:
    """Per-channel image mean over K independent renders, and the CI half-width."""
    means = np.stack([r.reshape(-1, r.shape[-1]).mean(axis=0) for r in renders])
    k = means.shape[0]
    half = stats.t.ppf(0.5 + confidence / 2, k - 1) * means.std(axis=0, ddof=1) / np.sqrt(k)
    return means.mean(axis=0), half


def rel_mse(image: np.ndarray, reference: np.ndarray, eps: float = 1e-2) -> float:
    """Relative MSE: mean of (x − r)² / (r² + eps) over pixels and channels (eps keeps black
    pixels from dominating; 1e-2 as in the denoising literature)."""
    return float(np.mean((image - reference) ** 2 / (reference**2 + eps)))


def holm(pvalues: np.ndarray) -> np.ndarray:
    """Holm's step-down adjusted p-values (controls the family-wise error rate)."""
    p = np.asarray(pvalues, dtype=float).ravel()
    order = np.argsort(p)
    m = len(p)
    adjusted = np.empty(m)
    running = 0.0
    for rank, idx in enumerate(order):
        running = max(running, min(1.0, (m - rank) * p[idx]))
        adjusted[idx] = running
    return adjusted.reshape(np.shape(pvalues))


@dataclass
class BiasResult:
    """Outcome of `bias_test`."""

    alpha: float
    grid: int
    channels: list[str]
    #: Holm-adjusted p-values, (grid, grid, channels).
    p_adjusted: np.ndarray
    #: Relative difference of the tile means (b − a) / a, (grid, grid, channels).
    rel_diff: np.ndarray
    #: Smallest adjusted p-value and where it is (row, column, channel name).
    worst: tuple[float, int, int, str] = field(default=(1.0, 0, 0, ""))

    @property
    def biased(self) -> bool:
        return bool(self.worst[0] < self.alpha)


def bias_test(
    renders_a: list[np.ndarray],
    renders_b: list[np.ndarray],
    channels: list[str],
    grid: int = 8,
    alpha: float = 1e-3,
) -> BiasResult:
    """Welch t-tests of tile means between independent renders of A and B, Holm-corrected.

    Tiles whose means are (nearly) zero in both renderers carry no information and get p = 1.
    """
    ta = np.stack([tile_means(r, grid) for r in renders_a])
    tb = np.stack([tile_means(r, grid) for r in renders_b])
    ma, mb = ta.mean(axis=0), tb.mean(axis=0)
    va, vb = ta.var(axis=0, ddof=1) / len(ta), tb.var(axis=0, ddof=1) / len(tb)
    se = np.sqrt(va + vb)
    scale = np.maximum(np.abs(ma), np.abs(mb))
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (mb - ma) / se
        dof = (va + vb) ** 2 / (va**2 / (len(ta) - 1) + vb**2 / (len(tb) - 1))
        p = 2.0 * stats.t.sf(np.abs(t), dof)
        rel = np.where(scale > 0, (mb - ma) / np.where(ma != 0, ma, scale), 0.0)
    # Tiles (nearly) black in both renderers carry no information. A tile with zero spread in
    # both (a fully deterministic region) has no t statistic (0/0 degrees of freedom): it agrees
    # exactly when the means are equal and disagrees with certainty otherwise. Only these two
    # cases may be decided outside the t-test, so a NaN p-value cannot stand for "agree".
    empty = scale < 1e-8
    exact = se == 0
    p = np.where(exact, np.where(mb == ma, 1.0, 0.0), p)
    p = np.where(empty, 1.0, p)
    if not np.all(np.isfinite(p)):
        raise ValueError("bias_test: non-finite p-value (non-finite pixel values in a render?)")
    adjusted = holm(p)
    i = np.unravel_index(np.argmin(adjusted), adjusted.shape)
    result = BiasResult(alpha, grid, channels, adjusted, rel)
    result.worst = (float(adjusted[i]), int(i[0]), int(i[1]), channels[int(i[2])])
    return result
