"""prism's sensor channels against Mitsuba 3's `specfilm` on the converted scene: the ColorChecker
(24 measured reflectances, colour-science's "ColorChecker N Ohta") under a constant 2856 K
blackbody sky, rendered 360–1000 nm through a named camera's R, G, B (white balance and exposure
included) and NIR bands (a Gaussian filter at 850 nm, a box at 880–1000 nm, 100 nm even bands),
by prism and by Mitsuba (`scalar_spectral`) from `prism export`'s scene.json
(`sensor.channels`: one response curve and gain per EXR channel; tools/prism_tools/mitsuba_scene.py
`specfilm`). Mitsuba's film records ∫ L·srf dλ and samples λ from the sum of the curves, so
bands past its 830 nm colour range render too.

Regions: the inner 60% of each patch (the mean over its pixels) and a strip of sky above the
chart; plus each channel's mean over all those regions (pixel-weighted).

Tolerance: |prism − Mitsuba| ≤ 5 combined standard errors (√(se_prism² + se_mitsuba²); pixels
are independent estimates in both renderers, σ from their spread; P(|z| > 5) < 6e-7 per
comparison, ~250 comparisons) plus 0.1% of the value for what differs besides noise: the export
tabulates the blackbody and the Gaussian on 1 nm (linear between samples, < 1e-4 relative
here) and both films store float32. The noise must be small enough for this to fail: the
median relative standard error of a region is asserted < 2% (so a 10% error in a patch fails),
that of a channel's mean over all regions < 0.5% (a 2.6% error fails).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from prism_tools import colorchecker as cc
from prism_tools import mitsuba_scene as ms
from prism_tools import renderers
from prism_tools.images import read_channels

SPP = 32
# Mitsuba traces 4 wavelengths per sample to prism's 8 here and draws them in proportion to the
# curves' plain sum: 4× the samples bring its noise near prism's.
MITSUBA_SPP = 4 * SPP
PX_PER_UNIT = 12.0
K_SE = 5.0
REL = 1e-3

CASES = {
    # The RGB + NIR preset: Sony ILCE-7M3 white-balanced to D65, a Gaussian 850 nm band (nir.Y).
    "rgb_nir": 'File("{root}/configs/sensors/rgb_nir.ron")',
    # A second camera with exposure and white balance to A, even visible bands and a NIR box.
    "nikon_d810": (
        "(observer: Cie1964, bands: [Even(count: 3, range: (400, 700)), Boxes([(880, 1000)])], "
        'camera: (curves: Named("nikon_d810"), white_balance: Illuminant("A"), '
        "exposure: (iso: 400, shutter: 0.01, f_number: 2)))"
    ),
}


def regions(width: int, height: int) -> list[tuple[slice, slice]]:
    """The 24 patches' inner pixels and the sky strip above the chart (inside the top gap)."""
    gap_px = int(cc.GAP * PX_PER_UNIT)
    return [cc.patch_pixels(i, width, height) for i in range(24)] + [(slice(0, gap_px - 1), slice(0, width))]


def stats(img: np.ndarray, where: list[tuple[slice, slice]]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per region: mean, its standard error, pixel count."""
    m, se, n = [], [], []
    for rows, cols in where:
        v = img[rows, cols].ravel().astype(np.float64)
        m.append(v.mean())
        se.append(v.std(ddof=1) / math.sqrt(v.size))
        n.append(v.size)
    return np.array(m), np.array(se), np.array(n, dtype=np.float64)


@pytest.mark.parametrize("case", list(CASES))
def test_sensor_channels_match_mitsuba_specfilm(prism_bin, tmp_path, case):
    mi = pytest.importorskip("mitsuba")
    mi.set_variant(renderers.VARIANT)
    sensor = CASES[case].format(root=cc.ROOT)
    scene = tmp_path / "chart.ron"
    scene.write_text(
        cc.scene_ron(
            spp=SPP,
            sensor=sensor,
            emitter="Scaled(0.001, Blackbody(2856))",
            spectral="range: (360, 1000), sampling: Sensor, wavelengths: 8",
            hi=1000.0,
            px_per_unit=PX_PER_UNIT,
        )
    )
    exported = renderers.export(prism_bin, scene, tmp_path / "export")
    _, names, gains = ms.specfilm(exported)
    assert "camera.G" in names and len(names) >= 4, names
    got = renderers.render_prism(prism_bin, scene, seed=7, names=names)
    mts = mi.load_dict(ms.convert(exported, spp=MITSUBA_SPP, spectral_film=True))
    ref = np.array(mi.render(mts, seed=11, spp=MITSUBA_SPP), dtype=np.float64) * gains
    assert ref.shape == got.shape, (ref.shape, got.shape)

    h, w = got.shape[:2]
    where = regions(w, h)
    for k, name in enumerate(names):
        pm, pse, n = stats(got[..., k], where)
        mm, mse, _ = stats(ref[..., k], where)
        # Each channel's mean over all regions (independent region means, pixel-weighted).
        wts = n / n.sum()
        pm, pse = np.append(pm, wts @ pm), np.append(pse, math.sqrt(wts**2 @ pse**2))
        mm, mse = np.append(mm, wts @ mm), np.append(mse, math.sqrt(wts**2 @ mse**2))
        se = np.hypot(pse, mse)
        err = np.abs(pm - mm)
        tol = K_SE * se + REL * np.abs(mm)
        z = err / se
        print(f"{case} {name}: max z {z.max():.2f}, mean prism {pm[-1]:.6g} mitsuba {mm[-1]:.6g}, median rel se {np.median(se / np.abs(mm)):.4f} (prism {np.median(pse / np.abs(mm)):.4f}, mitsuba {np.median(mse / np.abs(mm)):.4f})")
        worst = int(np.argmax(err / tol))
        assert np.all(err <= tol), f"{name} region {worst}: prism {pm[worst]} vs Mitsuba {mm[worst]} (se {se[worst]})"
        # The comparison can fail: noise is small against the values.
        assert np.median(se[:-1] / np.abs(mm[:-1])) < 0.02 and se[-1] < 0.005 * abs(mm[-1]), name
