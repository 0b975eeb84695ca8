"""`scene.params` (python/src/params.rs): a scene's changeable values by the names the dataset
config targets, set from Python; the next render equals, bit for bit, the render of a RON file
that says the same, and the scene's geometry is not built again."""

from __future__ import annotations

import pathlib

import numpy as np
import prism
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
MESH = ROOT / "scenes" / "meshes" / "prism.obj"

BASE = dict(
    red="Rgb(0.570068, 0.0430135, 0.0443706)",
    alpha="0.1",
    ior="1.5",
    light="Rgb(18.387, 13.9873, 6.75357)",
    fov="39.3077",
    pose="Matrix(((-1, 0, 0, 0), (0, 1, 0, 0), (0, 0, -1, 3.9), (0, 0, 0, 1)))",
)


def scene_text(**changes):
    """The Cornell box at 20x14 px with a rough plastic large box, a triangle mesh (an OBJ, the
    part a rebuild would read again) and a named light; `changes` replace BASE's values."""
    v = {**BASE, **changes}
    return f"""(
    camera: (fov: {v['fov']}, fov_axis: Smaller, to_world: [{v['pose']}]),
    film: (width: 20, height: 14, filter: Box()),
    sampler: (kind: Independent, spp: 2, seed: 3),
    spectral: (wavelengths: 4),
    integrator: (max_depth: 4),
    aovs: ["depth"],
    materials: {{
        "white": Diffuse(reflectance: Rgb(0.885809, 0.698859, 0.666422)),
        "green": Diffuse(reflectance: Rgb(0.105421, 0.37798, 0.076425)),
        "red": Diffuse(reflectance: {v['red']}),
        "shiny": RoughPlastic(alpha: {v['alpha']}, int_ior: {v['ior']}, diffuse_reflectance: Rgb(0.2, 0.3, 0.6)),
    }},
    shapes: [
        (name: "lamp", shape: Rectangle, material: "white", emitter: (radiance: {v['light']}),
         to_world: [Matrix(((0.23, 0, 0, 0), (0, -8.30516e-09, -0.19, 0.99), (0, 0.19, -8.30516e-09, 0.01), (0, 0, 0, 1)))]),
        (shape: Rectangle, material: "white", to_world: [Matrix(((1, 0, 0, 0), (0, -4.37114e-08, 1, -1), (0, -1, -4.37114e-08, 0), (0, 0, 0, 1)))]),
        (shape: Rectangle, material: "white", to_world: [Matrix(((1, 0, 0, 0), (0, 1, 0, 0), (0, 0, 1, -1), (0, 0, 0, 1)))]),
        (shape: Rectangle, material: "green", to_world: [Matrix(((-4.37114e-08, 0, -1, 1), (0, 1, 0, 0), (1, 0, -4.37114e-08, 0), (0, 0, 0, 1)))]),
        (shape: Rectangle, material: "red", to_world: [Matrix(((-4.37114e-08, 0, 1, -1), (0, 1, 0, 0), (-1, 0, -4.37114e-08, 0), (0, 0, 0, 1)))]),
        (shape: Cube, material: "shiny", to_world: [Matrix(((0.28491, 0, 0.0939491, -0.33), (0, 0.61, 0, -0.4), (-0.0939491, 0, 0.28491, -0.28), (0, 0, 0, 1)))]),
        (shape: Mesh(path: "{MESH}"), material: "shiny", to_world: [Scale((0.5, 0.5, 0.5)), Translate((0.35, -0.75, 0.3))]),
    ],
)"""


# (parameter, value from Python, the same in RON)
CHANGES = [
    ("materials.red.reflectance", {"Rgb": [0.2, 0.5, 0.1]}, dict(red="Rgb(0.2, 0.5, 0.1)")),
    ("materials.shiny.roughness", 0.35, dict(alpha="0.35")),
    ("materials.shiny.ior", 1.7, dict(ior="1.7")),
    ("lights.lamp.radiance", {"Blackbody": 3000}, dict(light="Blackbody(3000)")),
    ("camera.fov", 55.0, dict(fov="55.0")),
    (
        "camera.to_world",
        [{"LookAt": {"origin": [0.3, 0.2, 3.6], "target": [0, -0.1, 0], "up": [0, 1, 0]}}],
        dict(pose="LookAt(origin: (0.3, 0.2, 3.6), target: (0, -0.1, 0), up: (0, 1, 0))"),
    ),
]


@pytest.fixture
def scene(tmp_path):
    p = tmp_path / "base.ron"
    p.write_text(scene_text())
    return prism.load_file(p)


def ron_render(tmp_path, changes, **kw):
    p = tmp_path / "want.ron"
    p.write_text(scene_text(**changes))
    return prism.render(prism.load_file(p), threads=2, progress=False, **kw).channels


def assert_same(got, want):
    assert sorted(got) == sorted(want)
    for name in want:
        np.testing.assert_array_equal(got[name], want[name], err_msg=name)


def test_the_parameters_by_name(scene):
    assert list(scene.params) == [
        "materials.green.reflectance",
        "materials.red.reflectance",
        "materials.shiny.reflectance",
        "materials.shiny.roughness",
        "materials.shiny.ior",
        "materials.white.reflectance",
        "lights.lamp.radiance",
        "camera.fov",
        "camera.to_world",
        "sensor.exposure",
    ]
    assert scene.params["materials.shiny.roughness"] == pytest.approx(0.1)
    assert scene.params["lights.lamp.radiance"] == {"Rgb": pytest.approx([18.387, 13.9873, 6.75357])}
    assert scene.params["sensor.exposure"] == 0.0


@pytest.mark.parametrize("name, value, ron", CHANGES, ids=[c[0] for c in CHANGES])
def test_a_parameter_renders_as_the_ron_that_says_it(scene, tmp_path, name, value, ron):
    """Tolerance: none. One parameter set from Python: the scene's own render (geometry kept)
    and a render with spp and seed overrides (the scene rebuilt from its changed config) both
    equal the RON file's bit for bit; and the change shows (the render differs from before)."""
    before = prism.render(scene, threads=2, progress=False).channels
    scene.params[name] = value
    assert scene.geometry_builds == 1
    got = prism.render(scene, threads=2, progress=False).channels
    assert_same(got, ron_render(tmp_path, ron))
    assert not np.array_equal(got["Y"], before["Y"])
    again = prism.render(scene, spp=3, seed=11, threads=2, progress=False).channels
    assert_same(again, ron_render(tmp_path, ron, spp=3, seed=11))


def test_several_parameters_at_once_keep_the_geometry(scene, tmp_path):
    """Tolerance: none. Every parameter changed (one by one, then back and again with
    `update`), renders in between: the RON render's bits, and the geometry built once."""
    want = {}
    for name, value, ron in CHANGES:
        scene.params[name] = value
        want.update(ron)
        prism.render(scene, spp=1, threads=1, progress=False)
    assert_same(prism.render(scene, threads=2, progress=False).channels, ron_render(tmp_path, want))
    scene.params.update({name: prism.load_string(scene_text()).params[name] for name, _, _ in CHANGES})
    assert_same(prism.render(scene, threads=2, progress=False).channels, ron_render(tmp_path, {}))
    scene.params.update({name: value for name, value, _ in CHANGES})
    assert_same(prism.render(scene, threads=2, progress=False).channels, ron_render(tmp_path, want))
    assert scene.geometry_builds == 1


def test_exposure_scales_the_sensor_channels(scene):
    """Tolerance: none. sensor.exposure = 1 stop doubles every sensor channel (a power of two
    scales a float exactly) as a dataset frame's exposure does, and leaves the AOVs alone;
    numpy scalars are taken as numbers."""
    base = prism.render(scene, threads=2, progress=False).channels
    scene.params["sensor.exposure"] = np.float32(1.0)
    got = prism.render(scene, threads=2, progress=False).channels
    for name in base:
        want = base[name] if name.startswith("depth") else 2 * base[name]
        np.testing.assert_array_equal(got[name], want, err_msg=name)
    assert scene.params["sensor.exposure"] == 1.0


def test_bad_parameters_raise_and_change_nothing(scene):
    """An unknown name lists the names; a value of the wrong kind names the parameter and shows
    the form; a value out of range gives the scene build's message (the CLI's); and after each
    the scene renders as before. `update` sets all or nothing."""
    before = prism.render(scene, threads=2, progress=False).channels
    with pytest.raises(prism.SceneError, match=r"no parameter \"materials.blue.reflectance\"(.|\n)*hint: the parameters are: materials.green.reflectance"):
        scene.params["materials.blue.reflectance"] = {"Rgb": [1, 0, 0]}
    with pytest.raises(prism.SceneError, match=r"no parameter \"materials.red.roughness\""):
        scene.params["materials.red.roughness"] = 0.2
    with pytest.raises(prism.SceneError, match="no parameter"):
        scene.params["camera.zoom"]
    with pytest.raises(prism.SceneError, match=r'params\["materials.red.reflectance"\]: unknown variant `Rbg`(.|\n)*hint: give a spectrum'):
        scene.params["materials.red.reflectance"] = {"Rbg": [1, 0, 0]}
    with pytest.raises(prism.SceneError, match=r'params\["camera.fov"\]: invalid type: string "wide", expected f32'):
        scene.params["camera.fov"] = "wide"
    with pytest.raises(prism.SceneError, match=r"camera.fov: fov 500 must lie in \(0, 180\) degrees"):
        scene.params["camera.fov"] = 500
    with pytest.raises(prism.SceneError, match=r'params\["sensor.exposure"\]: exposure 60 stops lies outside(.|\n)*hint'):
        scene.params["sensor.exposure"] = 60
    with pytest.raises(prism.SceneError, match=r'the value of "sensor.exposure" is not plain data(.|\n)*hint: give'):
        scene.params["sensor.exposure"] = float("inf")
    with pytest.raises(prism.SceneError, match="is not plain data"):
        scene.params["camera.fov"] = object()
    with pytest.raises(prism.SceneError, match=r"materials.\"shiny\".alpha: roughness -1 must lie in \(0, 1\]"):
        scene.params.update({"materials.red.reflectance": {"Rgb": [0.9, 0.1, 0.1]}, "materials.shiny.roughness": -1})
    assert scene.params["materials.red.reflectance"] == {"Rgb": pytest.approx([0.570068, 0.0430135, 0.0443706])}
    assert_same(prism.render(scene, threads=2, progress=False).channels, before)
