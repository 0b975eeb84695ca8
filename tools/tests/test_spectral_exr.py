"""prism's EXR is a Fichet et al. 2021 spectral image that colour-science reads, and its X, Y, Z
channels agree with colour-science's integration of its spectral bands."""

from __future__ import annotations

import colour
import numpy as np
import OpenImageIO as oiio

# A diffuse plane under a smooth tabulated sky, seen from above: every pixel has the same
# expectation, so pixel spread is pure noise.
SCENE = """(
    camera: (fov: 30, to_world: [LookAt(origin: (0, 3, 0.5), target: (0, 0, 0), up: (0, 0, -1))]),
    film: (width: 24, height: 24, filter: Box()),
    sampler: (spp: 256, seed: 1),
    spectral: (sampling: Uniform, wavelengths: 8),
    outputs: (bands: 47),
    materials: { "paint": Diffuse(reflectance: Tabulated([(360, 0.2), (500, 0.7), (600, 0.4), (830, 0.6)])) },
    shapes: [(shape: Rectangle, material: "paint", to_world: [Scale((50, 50, 1)), Rotate(axis: (1, 0, 0), angle: -90)])],
    emitters: [Constant(radiance: Tabulated([(360, 1.5), (550, 0.8), (830, 1.2)]))],
)"""


def read_channels(path):
    inp = oiio.ImageInput.open(str(path))
    names = list(inp.spec().channelnames)
    pixels = inp.read_image(format="float")
    inp.close()
    return {n: pixels[..., i] for i, n in enumerate(names)}


def test_colour_reads_the_layout(render):
    out = render(SCENE)
    components, spec = colour.io.read_spectral_image_Fichet2021(str(out), additional_data=True)
    assert spec.is_emissive and not spec.is_polarised and not spec.is_bispectral
    wavelengths, image = components["S0"]
    # 47 bands of 10 nm over 360–830 nm, named after their centres.
    np.testing.assert_allclose(wavelengths, np.arange(365, 830, 10))
    assert image.shape == (24, 24, 47)
    attrs = {a.name: a.value for a in spec.attributes}
    assert attrs["spectralLayoutVersion"] == "1.0"
    assert attrs["emissiveUnits"] == "W.m^-2.sr^-1"
    # The bands colour-science read are the channels prism wrote.
    ch = read_channels(out)
    np.testing.assert_array_equal(image[..., 19], ch["S0.555,000000nm"])


def test_xyz_channels_match_colour_integration_of_the_bands(render):
    """Integrate the mean band spectrum with colour-science's CIE 1931 CMFs and compare with
    prism's own X, Y, Z. Tolerance 1%: 10 nm box bands sample a smooth spectrum with < 0.3%
    quadrature error, and the image means carry < 0.2% noise at this sample count."""
    out = render(SCENE)
    (wavelengths, image), = colour.io.read_spectral_image_Fichet2021(str(out)).values()
    mean_band = image.reshape(-1, image.shape[-1]).mean(0)
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    fine = np.arange(360.0, 830.5, 1.0)
    radiance = np.interp(fine, wavelengths, mean_band)
    xyz_bar = cmfs[fine]
    xyz = (radiance[:, None] * xyz_bar).sum(0) / xyz_bar[:, 1].sum()
    ch = read_channels(out)
    prism_xyz = np.array([ch[c].mean() for c in "XYZ"])
    np.testing.assert_allclose(prism_xyz, xyz, rtol=0.01)
    # And prism's RGB is colour-science's XYZ -> linear sRGB of prism's XYZ.
    rgb = colour.XYZ_to_RGB(prism_xyz, colour.RGB_COLOURSPACES["sRGB"], apply_cctf_encoding=False)
    prism_rgb = np.array([ch[c].mean() for c in "RGB"])
    np.testing.assert_allclose(prism_rgb, rgb, rtol=2e-3)
