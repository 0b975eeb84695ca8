"""Spectral EXR channels come back in wavelength order from colour-science's
`read_spectral_image_Fichet2021` and from OpenImageIO, also when the bands span 300–1100 nm
(OpenEXR stores channels sorted by name: unpadded, `S0.1025,000000nm` would sort before
`S0.325,000000nm`; prism pads every wavelength to the widest integer part when they differ,
src/sensor/names.rs).

The band values are checked against colour-science's Planck law, so a band read under the wrong
wavelength fails: a grey plane (ρ = 0.5) under a constant 2856 K blackbody sky has radiance
ρ·B(λ) exactly; band k holds its mean over [lo_k, hi_k). Tolerance: 5 standard errors of the
image mean (pixels are independent estimates; σ from their spread) plus 0.2% for the
reference's quadrature (midpoint rule on 0.1 nm cells) and float32 storage.
"""

from __future__ import annotations

import json
import math

import colour
import numpy as np
import OpenImageIO as oiio

SCENE = """(
    camera: (fov: 30, to_world: [LookAt(origin: (0, 3, 0.5), target: (0, 0, 0), up: (0, 0, -1))]),
    film: (width: 16, height: 16, filter: Box()),
    sampler: (spp: 32, seed: 1),
    spectral: (range: (300, 1100), sampling: Uniform, wavelengths: 8),
    sensor: (bands: [Even(count: 16), Boxes([(600, 640)]), Box(lo: 1000, hi: 1100)]),
    materials: { "grey": Diffuse(reflectance: Constant(0.5)) },
    shapes: [(shape: Rectangle, material: "grey", to_world: [Scale((50, 50, 1)), Rotate(axis: (1, 0, 0), angle: -90)])],
    emitters: [Constant(radiance: Scaled(0.001, Blackbody(2856)))],
)"""

VISIBLE = SCENE.replace("range: (300, 1100)", "range: (360, 830)").replace(
    "[Even(count: 16), Boxes([(600, 640)]), Box(lo: 1000, hi: 1100)]", "[Even(count: 47)]"
)


def band_mean_radiance(lo: float, hi: float) -> float:
    """0.5 · 0.001 · mean of colour-science's Planck law (W m⁻² sr⁻¹ nm⁻¹) over [lo, hi)."""
    step = 0.1
    wl = np.arange(lo + step / 2, hi, step)
    return float(0.5 * 1e-3 * colour.colorimetry.planck_law(wl * 1e-9, 2856).mean() * 1e-9)


def test_wide_bands_read_in_wavelength_order(render):
    out = render(SCENE)
    # 16 even bands of 50 nm, and the boxes 600–640 nm and 1000–1100 nm (centres 620, 1050).
    even = {c: (c - 25.0, c + 25.0) for c in np.arange(325.0, 1100.0, 50.0)}
    ranges = even | {620.0: (600.0, 640.0), 1050.0: (1000.0, 1100.0)}
    want = np.sort(list(ranges))

    # OpenImageIO: the spectral channels in file order are in wavelength order.
    inp = oiio.ImageInput.open(str(out))
    names = [n for n in inp.spec().channelnames if n.startswith("S0.")]
    pixels = inp.read_image(format="float")
    all_names = list(inp.spec().channelnames)
    inp.close()
    assert names[0] == "S0.0325,000000nm" and "S0.1075,000000nm" in names, names
    parsed = [float(n[3:-2].replace(",", ".")) for n in names]
    np.testing.assert_array_equal(parsed, want)

    # colour-science: the same order, the same data.
    components = colour.io.read_spectral_image_Fichet2021(str(out))
    wavelengths, image = components["S0"]
    np.testing.assert_array_equal(wavelengths, want)
    for k, nm in enumerate(want):
        name = names[k]
        np.testing.assert_array_equal(image[..., k], pixels[..., all_names.index(name)])

    # The sidecar names the same channels.
    side = json.loads(out.with_suffix(".json").read_text())["sensor"]
    name = {c: "S0." + f"{c:011.6f}".replace(".", ",") + "nm" for c in ranges}
    assert [b["channel"] for b in side["bands"]["bands"]] == [name[c] for c in even]
    assert side["response_channels"] == [name[620.0], name[1050.0]] == ["S0.0620,000000nm", "S0.1050,000000nm"]

    # Each band's value is the blackbody's mean over its own wavelengths.
    for k, nm in enumerate(wavelengths):
        v = image[..., k].astype(np.float64).ravel()
        m, se = v.mean(), v.std(ddof=1) / math.sqrt(v.size)
        ref = band_mean_radiance(*ranges[float(nm)])
        assert abs(m - ref) <= 5 * se + 2e-3 * ref, (nm, m, ref, se)
        assert se < 0.01 * ref, (nm, se / ref)


def test_visible_names_are_unchanged(render):
    out = render(VISIBLE)
    inp = oiio.ImageInput.open(str(out))
    names = [n for n in inp.spec().channelnames if n.startswith("S0.")]
    inp.close()
    assert names[0] == "S0.365,000000nm" and names[-1] == "S0.825,000000nm", names
    wavelengths, _ = colour.io.read_spectral_image_Fichet2021(str(out))["S0"]
    np.testing.assert_array_equal(wavelengths, np.arange(365.0, 830.0, 10.0))
