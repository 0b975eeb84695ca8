"""The raw sensor over a broad band (issue 27, item 6): the flat field of tests/raw_sensor.rs
renders 550-551 nm only, so the λ weighting of photon counts and the 1/pdf weight of the
wavelength samples are never exercised. Here: a constant sky L seen through camera curves
spanning 400-700 nm, rendered over 380-780 nm with uniform, visible and sensor wavelength
sampling, noise off. Each Bayer site's mean DN must equal g · S_c + black with

    S_c = t · A · π / (4 N²) · η / ĉ · L · ∫ c̄_c(λ) λ dλ / (h c)

the integral taken by colour-science over the same (linearly interpolated) curves. Tolerance:
4 standard errors of the site mean (the pixels differ only by wavelength-sampling noise) plus
1 DN (read-out rounding, against means of ~1e5 DN).
"""

from __future__ import annotations

import colour
import numpy as np
import pytest

from prism_tools import outputs

L, T, N, PITCH, QE, GAIN, BLACK = 0.75, 0.01, 4.0, 4.0, 0.5, 8.0, 64.0
CURVES = {
    "r": {400: 0.0, 560: 0.2, 620: 1.0, 700: 0.0},
    "g": {420: 0.0, 530: 0.8, 600: 0.1, 680: 0.0},
    "b": {400: 0.0, 450: 0.7, 520: 0.05, 600: 0.0},
}


def tabulated(c: dict) -> str:
    return "Tabulated([" + ", ".join(f"({k}, {v})" for k, v in c.items()) + "])"


def scene(sampling: str) -> str:
    r, g, b = (tabulated(CURVES[k]) for k in "rgb")
    return f"""(
    camera: (fov: 30, to_world: [LookAt(origin: (0, 0, 0), target: (0, 0, 1), up: (0, 1, 0))]),
    film: (width: 48, height: 48),
    sampler: (spp: 16, seed: 3),
    spectral: (range: (380, 780), sampling: {sampling}),
    shapes: [(shape: Sphere(center: (0, 0, -10), radius: 1), material: "m")],
    materials: {{ "m": Diffuse(reflectance: Constant(0.5)) }},
    emitters: [Constant(radiance: Constant({L}))],
    sensor: (rgb: [], bands: [],
        camera: (curves: Curves(r: {r}, g: {g}, b: {b}), exposure: (iso: 100, shutter: {T}, f_number: {N})),
        raw: (pixel_pitch: {PITCH}, quantum_efficiency: {QE}, full_well: 1e9, read_noise: 0, dark_current: 0,
              gain: PerElectron({GAIN}), black_level: {BLACK}, bits: 32, noise: false)),
)"""


def electrons() -> np.ndarray:
    """S_c for R, G, B: the curves as colour-science SpectralDistributions (linear, as prism's
    Tabulated), ∫ c̄ λ dλ by colour-science's alignment to 0.01 nm and the trapezoid rule."""
    shape = colour.SpectralShape(380, 780, 0.01)
    sds = [
        colour.SpectralDistribution(CURVES[k], interpolator=colour.LinearInterpolator, extrapolator_kwargs={"method": "Constant", "left": 0, "right": 0})
        .align(shape)
        for k in "rgb"
    ]
    peak = max(sd.values.max() for sd in sds)
    hc = 6.62607015e-34 * 299792458.0
    k = T * (PITCH * 1e-6) ** 2 * np.pi / (4 * N * N) * QE / peak
    return np.array([k * L * np.trapezoid(sd.values * sd.wavelengths, sd.wavelengths) * 1e-9 / hc for sd in sds])


@pytest.mark.parametrize("sampling", ["Uniform", "Visible", "Sensor"])
def test_broadband_flat_field(render, sampling):
    r = outputs.read(render(scene(sampling)))
    dn = r.channels["raw.Y"].astype(np.float64)
    s = electrons()
    assert s.min() > 1e4, s  # thousands of electrons: rounding is negligible
    for (dy, dx), c in zip([(0, 0), (0, 1), (1, 0), (1, 1)], [0, 1, 1, 2]):
        v = dn[dy::2, dx::2].ravel()
        want = GAIN * s[c] + BLACK
        se = v.std(ddof=1) / np.sqrt(v.size)
        # The test can tell: the site's precision is better than 0.5% of the signal (~0.03% measured).
        assert se < 0.005 * want, (sampling, c, se, want)
        assert abs(v.mean() - want) < 4 * se + 1.0, (sampling, c, v.mean(), want, se)
