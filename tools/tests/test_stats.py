"""The bias test itself: it must pass on two samples of the same distribution (at its stated
false-alarm rate) and catch a small systematic offset."""

from __future__ import annotations

import numpy as np

from prism_tools import stats


def noisy_renders(mean: np.ndarray, k: int, rng: np.random.Generator, noise: float = 0.2) -> list[np.ndarray]:
    return [mean * (1.0 + noise * rng.standard_normal(mean.shape)) for _ in range(k)]


def test_holm_adjustment() -> None:
    adj = stats.holm(np.array([0.01, 0.04, 0.03, 0.005]))
    np.testing.assert_allclose(adj, [0.03, 0.06, 0.06, 0.02])


def test_same_distribution_passes_and_offset_fails() -> None:
    rng = np.random.default_rng(1)
    truth = rng.uniform(0.1, 1.0, size=(64, 64, 3))
    # 200 repetitions of the null hypothesis: the family-wise false-alarm rate is <= alpha = 1e-2,
    # so at most a few failures are expected (binomial(200, 0.01) exceeds 6 with p < 0.005).
    failures = sum(
        stats.bias_test(noisy_renders(truth, 6, rng), noisy_renders(truth, 6, rng), ["R", "G", "B"], alpha=1e-2).biased
        for _ in range(200)
    )
    assert failures <= 6, failures
    # A 3% offset in one 8x8-pixel tile's green channel is caught: with 5% pixel noise a tile
    # mean varies by 5%/8 = 0.63% per render, so with 20 renders per side the difference has a
    # standard error of 0.63%·√(2/20) = 0.2%: the offset is ~15σ, far past the Holm threshold.
    shifted = truth.copy()
    shifted[8:16, 8:16, 1] *= 1.03
    res = stats.bias_test(noisy_renders(truth, 20, rng, 0.05), noisy_renders(shifted, 20, rng, 0.05), ["R", "G", "B"])
    assert res.biased and res.worst[1:] == (1, 1, "G"), res.worst


def test_rel_mse_and_ci() -> None:
    ref = np.full((4, 4, 3), 2.0)
    assert stats.rel_mse(ref, ref) == 0.0
    assert abs(stats.rel_mse(ref * 1.1, ref) - 0.04 / 4.01) < 1e-9
    rng = np.random.default_rng(2)
    mean, half = stats.mean_ci([ref + 0.01 * rng.standard_normal(ref.shape) for _ in range(10)])
    assert np.all(np.abs(mean - 2.0) < 3 * half)
