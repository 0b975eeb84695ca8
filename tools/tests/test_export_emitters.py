"""`prism export` of the spot, directional and envmap example scenes, converted by
`prism_tools.mitsuba_scene`, loads in Mitsuba 3 and gives its emitters the parameters of the RON
files: checked through Mitsuba's own emitter queries (exact values, no rendering).

Tolerances: 1e-5 on directions (f32 round trips through the JSON); the spot's falloff 1e-4
(f32 acos, as tests/emitters_mitsuba.rs); the envmap's orientation by a factor of 100 between
the sun and the opposite side of the sky (the sun is ~400x brighter than the sky).
"""

from __future__ import annotations

import json
import math
import pathlib
import subprocess

import mitsuba as mi
import numpy as np
import pytest

from prism_tools import mitsuba_scene

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module", autouse=True)
def variant():
    mi.set_variant("scalar_spectral")


def export(prism_bin, tmp_path, name: str) -> dict:
    out = tmp_path / name
    subprocess.run([str(prism_bin), "export", str(ROOT / "scenes/materials" / f"{name}.ron"), "-o", str(out)], check=True, capture_output=True)
    return json.loads((out / "scene.json").read_text())


def the_emitter(scene: dict):
    (e,) = [e for e in scene["emitters"] if e["type"] != "area"]
    return mi.load_dict(mitsuba_scene.emitter(e)), e


def query(em, p, wavelength=550.0):
    it = mi.Interaction3f()
    it.p = mi.Point3f(*p)
    it.wavelengths = [wavelength] * 4
    ds, weight = em.sample_direction(it, [0.5, 0.5])
    return np.array(ds.d), float(weight[0])


def test_directional(prism_bin, tmp_path):
    scene = export(prism_bin, tmp_path, "directional")
    em, _ = the_emitter(scene)
    # directional.ron: direction (0.6, -0.643, -0.48).
    d = np.array([0.6, -0.643, -0.48])
    to_light, _ = query(em, [0.1, 0.0, 0.2])
    np.testing.assert_allclose(to_light, -d / np.linalg.norm(d), atol=1e-5)
    mitsuba_scene.convert(scene)  # the whole scene converts


def test_spot(prism_bin, tmp_path):
    scene = export(prism_bin, tmp_path, "spot")
    em, e = the_emitter(scene)
    assert (e["cutoff_angle"], e["beam_width"]) == (30.0, 20.0)
    # spot.ron: LookAt(origin: (-1.2, 2.5, 0.6), target: (0.2, 0, 0)); cutoff 30°, beam 20°.
    origin, target = np.array([-1.2, 2.5, 0.6]), np.array([0.2, 0.0, 0.0])
    axis = (target - origin) / np.linalg.norm(target - origin)
    side = np.cross(axis, [0.0, 1.0, 0.0])
    side /= np.linalg.norm(side)
    on_axis = query(em, origin + axis)[1]
    for deg, falloff in [(10.0, 1.0), (25.0, 0.5), (28.0, 0.2), (35.0, 0.0)]:
        t = math.radians(deg)
        p = origin + math.cos(t) * axis + math.sin(t) * side
        assert abs(query(em, p)[1] / on_axis - falloff) < 1e-4, deg
    mitsuba_scene.convert(scene)


def test_envmap(prism_bin, tmp_path):
    scene = export(prism_bin, tmp_path, "envmap")
    em, e = the_emitter(scene)
    assert pathlib.Path(e["filename"]) == ROOT / "scenes/textures/sky.exr"
    # make_test_envmap.py puts the sun at azimuth 140°, elevation 35° of the map's frame;
    # envmap.ron turns the map 180° about +y.
    az, el = math.radians(140.0), math.radians(35.0)
    t = math.pi / 2 - el
    sun = np.array([math.sin(az) * math.sin(t), math.cos(t), -math.cos(az) * math.sin(t)])
    turned = np.array([-sun[0], sun[1], -sun[2]])

    def radiance(d):
        si = mi.SurfaceInteraction3f()
        si.wi = mi.Vector3f(*(-d))
        si.wavelengths = [550.0] * 4
        return float(em.eval(si)[0])

    assert radiance(turned) > 100 * radiance(sun), (radiance(turned), radiance(sun))
    mitsuba_scene.convert(scene)
