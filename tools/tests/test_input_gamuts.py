"""RGB inputs in other spaces than sRGB (`ColourSpace("acescg", Rgb(...))`), against
colour-science 0.4.7.

prism's XYZ is D65-adapted (src/spectrum/gamut.rs), so an input colour of space S means
`colour.RGB_to_XYZ(rgb, S, illuminant=D65, chromatic_adaptation_transform="Bradford")`:

- the albedo AOV (the reflectance's colour under D65, written as linear sRGB) of a patch in
  each space, converted to XYZ by colour-science, equals that XYZ; and the albedo's 5 nm bands
  (the uplifted spectrum itself), integrated by `colour.sd_to_XYZ` under D65 and converted back
  by `colour.XYZ_to_RGB` to the patch's space, give the value again;
- a flat emitter (`Constant` radiance) given in ACEScg, rendered into the XYZ and ACEScg layers,
  reads back `colour.RGB_to_XYZ` of its value and the value itself;
- an unknown space name exits 2 and lists the valid ones.
"""

from __future__ import annotations

import subprocess

import colour
import numpy as np
import pytest

from prism_tools import outputs

D65_XY = np.array([0.3127, 0.3290])
SPACES = {"srgb": "sRGB", "rec2020": "ITU-R BT.2020", "display_p3": "Display P3", "acescg": "ACEScg"}
# Saturated, but inside the fraction f = 0.6 of every gamut that src/spectrum/uplift_tests.rs
# checks (m + f (c - m), c in the unit cube, m its mean), plus a neutral.
COLOURS = [(0.7, 0.4, 0.2), (0.15, 0.6, 0.3), (0.2, 0.25, 0.75), (0.5, 0.5, 0.5)]


def to_xyz(rgb, space: str) -> np.ndarray:
    return colour.RGB_to_XYZ(
        np.asarray(rgb, float), SPACES[space], illuminant=D65_XY, chromatic_adaptation_transform="Bradford"
    )


def patch_scene(space: str, rgb) -> str:
    r, g, b = rgb
    return f"""(
    camera: (fov: 20, to_world: [LookAt(origin: (0, 0, 4), target: (0, 0, 0), up: (0, 1, 0))]),
    film: (width: 4, height: 4),
    sampler: (spp: 1),
    spectral: (range: (360, 830)),
    outputs: (bands: 94, band_range: (360, 830)),
    aovs: ["albedo"],
    materials: {{"m": Diffuse(reflectance: ColourSpace("{space}", Rgb({r}, {g}, {b})))}},
    shapes: [(shape: Rectangle, material: "m", to_world: [Scale((3, 3, 1))])],
    emitters: [Constant(radiance: Named("D65"))],
)"""


@pytest.mark.parametrize("space", list(SPACES))
def test_albedo_of_each_space_matches_colour_science(render, space):
    worst_xyz = worst_rgb = 0.0
    for rgb in COLOURS:
        r = outputs.read(render(patch_scene(space, rgb)))
        # albedo.R/G/B: linear sRGB under D65 (the layer also holds the bands).
        albedo = np.stack([r.channels[f"albedo.{c}"] for c in "RGB"], axis=-1)
        # Every pixel sees the same patch: one value (noise-free, evaluated at the hit).
        a = albedo.reshape(-1, 3)
        assert np.ptp(a, axis=0).max() < 1e-6
        got_xyz = colour.RGB_to_XYZ(a[0].astype(float), "sRGB", illuminant=D65_XY)
        # Tolerance 3e-3 in XYZ: the uplift table's interpolation error inside
        # f = 0.6 (< 2e-3 per RGB component, uplift_tests.rs) and prism's sRGB matrix, derived from the
        # white (0.31271, 0.32902) rather than colour-science's (0.3127, 0.3290), < 5e-4.
        worst_xyz = max(worst_xyz, np.abs(got_xyz - to_xyz(rgb, space)).max())
        # The spectrum itself: band means (5 nm) at the band centres, integrated under D65 with
        # CIE 1931 (colour-science's tables).
        names = sorted(
            (c for c in r.channels if c.startswith("albedo.S0.")),
            key=lambda c: float(c.split("S0.")[1].rstrip("nm").replace(",", ".")),
        )
        nm = [float(c.split("S0.")[1].rstrip("nm").replace(",", ".")) for c in names]
        values = [float(r.channels[c].mean()) for c in names]
        # The band means, interpolated linearly onto 1 nm between the first and last band
        # centres, weighted by colour-science's CIE 1931 CMFs and D65 (normalised: Y(D65) = 1).
        wl = np.arange(np.ceil(nm[0]), np.floor(nm[-1]) + 1)
        s = np.interp(wl, nm, values)
        cmf = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"][wl]
        d65 = colour.SDS_ILLUMINANTS["D65"][wl]
        xyz = (cmf * (d65 * s)[:, None]).sum(0) / (cmf[:, 1] * d65).sum()
        back = colour.XYZ_to_RGB(xyz, SPACES[space], illuminant=D65_XY, chromatic_adaptation_transform="Bradford")
        worst_rgb = max(worst_rgb, np.abs(back - np.asarray(rgb)).max())
    print(f"{space}: worst XYZ error of the albedo {worst_xyz:.2e}, of the band spectrum {worst_rgb:.2e}")
    assert worst_xyz < 3e-3, worst_xyz
    # 3e-3 as above, plus reading 5 nm band means as point samples at the band centres
    # (measured: < 4e-4 in total); an uplift with another space's table is off by > 0.05 here.
    assert worst_rgb < 3e-3, worst_rgb


def test_acescg_emitter_reads_back(render):
    rgb = (0.2, 0.5, 0.8)
    scene = f"""(
    camera: (fov: 20, to_world: [LookAt(origin: (0, 0, 4), target: (0, 0, 0), up: (0, 1, 0))]),
    film: (width: 16, height: 16),
    sampler: (spp: 16, seed: 5),
    sensor: (xyz: true, rgb: [Srgb, AcesCg], bands: []),
    emitters: [Constant(radiance: ColourSpace("acescg", Rgb({rgb[0]}, {rgb[1]}, {rgb[2]})))],
)"""
    r = outputs.read(render(scene))
    want_xyz = to_xyz(rgb, "acescg")
    for got, want, what in [
        (np.stack([r.channels[c] for c in "XYZ"], -1), want_xyz, "XYZ"),
        (r.layer("acescg"), np.asarray(rgb), "ACEScg"),
    ]:
        px = got.reshape(-1, 3).astype(float)
        mean, se = px.mean(0), px.std(0, ddof=1) / np.sqrt(len(px))
        err = np.abs(mean - want)
        print(f"{what}: mean {mean}, want {want}, standard error {se}")
        # 4 standard errors of the pixel mean (spectral sampling noise) plus 3e-3, the uplift's.
        assert np.all(err < 4 * se + 3e-3), (what, mean, want, se)


def test_unknown_space_exits_2(prism_bin, tmp_path):
    scene = tmp_path / "s.ron"
    scene.write_text(
        '(film: (width: 2, height: 2), outputs: (bands: 0), '
        'emitters: [Constant(radiance: ColourSpace("adobe_rgb", Rgb(1, 1, 1)))])'
    )
    p = subprocess.run(
        [str(prism_bin), "render", str(scene), "-o", str(tmp_path / "o.exr"), "-q"], capture_output=True, text=True
    )
    assert p.returncode == 2, p.stderr
    assert "adobe_rgb" in p.stderr and "srgb, rec2020, display_p3, acescg" in p.stderr, p.stderr
    assert "emitters" in p.stderr, p.stderr
