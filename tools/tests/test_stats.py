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


def test_exact_disagreement_is_caught() -> None:
    """Both renderers exact (zero spread across renders) but different in one tile: the t-test
    has 0/0 degrees of freedom there, and the tile must count as a certain disagreement, not
    as p = 1 (the bug this pins: NaN degrees of freedom used to be read as an empty tile)."""
    rng = np.random.default_rng(3)
    truth = rng.uniform(0.1, 1.0, size=(64, 64, 3))
    shifted = truth.copy()
    shifted[8:16, 40:48, 2] *= 1.0001
    same = stats.bias_test([truth] * 4, [truth.copy()] * 4, ["R", "G", "B"])
    assert not same.biased and same.worst[0] == 1.0, same.worst
    res = stats.bias_test([truth] * 4, [shifted] * 4, ["R", "G", "B"])
    assert res.biased and res.worst == (0.0, 1, 5, "B"), res.worst
    # One side exact, the other noisy: an ordinary Welch test with k − 1 degrees of freedom.
    noisy = noisy_renders(shifted, 6, rng, 0.05)
    mixed = stats.bias_test([truth] * 6, noisy, ["R", "G", "B"])
    assert np.all(np.isfinite(mixed.p_adjusted))
    # Black in both: no information, p = 1.
    black = np.zeros_like(truth)
    assert stats.bias_test([black] * 3, [black] * 3, ["R", "G", "B"]).worst[0] == 1.0


def test_non_finite_pixels_are_an_error() -> None:
    bad = np.ones((16, 16, 3))
    bad[0, 0, 0] = np.nan
    try:
        stats.bias_test([bad] * 3, [np.ones((16, 16, 3))] * 3, ["R", "G", "B"], grid=2)
    except ValueError:
        return
    raise AssertionError("NaN pixels passed the bias test")
