"""glTF KHR_lights_punctual lights in prism's radiometric units: a point (100 cd, orange), a spot
(50 cd) and a directional light (3 lx, bluish) in a glTF file included by a RON scene, exported
by `prism export`. Their luminous values computed back with colour-science's CIE 1931 2° CMFs,
683 lm/W · ∫ I_e(λ) ȳ(λ) dλ, must be glTF's candela and lux, and their placement the nodes'.

Tolerance: 0.2% on the luminous values (the export tabulates at 1 nm, integrated here by the
trapezoid rule; prism integrates its own 1-nm table at 0.25 nm); 1e-5 on positions and
directions (f32 quaternion rotations).
"""

from __future__ import annotations

import base64
import json
import struct
import subprocess

import colour
import numpy as np


def gltf_with_lights() -> dict:
    pos = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    down = [-0.7071068, 0, 0, 0.7071068]  # a quarter turn about x: −z becomes −y
    return {
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "point", "color": [1, 0.5, 0.25], "intensity": 100, "name": "bulb"},
            {"type": "spot", "intensity": 50, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}},
            {"type": "directional", "color": [0.8, 0.9, 1], "intensity": 3},
        ]}},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2, 3]}],
        "nodes": [
            {"mesh": 0, "name": "tri"},
            {"translation": [0, 2, 0], "extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"translation": [0, 3, 0], "rotation": down, "extensions": {"KHR_lights_punctual": {"light": 1}}},
            {"rotation": down, "extensions": {"KHR_lights_punctual": {"light": 2}}},
        ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64," + base64.b64encode(pos).decode()}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]}],
    }


def luminous(spec: dict) -> float:
    nm = np.asarray(spec["wavelengths"], float)
    v = np.asarray(spec["values"], float)
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    ybar = np.interp(nm, cmfs.wavelengths, cmfs.values[:, 1], left=0.0, right=0.0)
    return 683.0 * np.trapezoid(v * ybar, nm)


def test_photometric_units_and_placement(prism_bin, tmp_path):
    (tmp_path / "lights.gltf").write_text(json.dumps(gltf_with_lights()))
    (tmp_path / "s.ron").write_text('(shapes: [(shape: Gltf(path: "lights.gltf"))])')
    subprocess.run([str(prism_bin), "export", str(tmp_path / "s.ron"), "-o", str(tmp_path / "out")], check=True)
    em = json.loads((tmp_path / "out" / "scene.json").read_text())["emitters"]
    point, spot, sun = em
    assert point["type"] == "point" and spot["type"] == "spot" and sun["type"] == "directional"
    assert abs(luminous(point["intensity"]) / 100 - 1) < 2e-3
    assert abs(luminous(spot["intensity"]) / 50 - 1) < 2e-3
    assert abs(luminous(sun["irradiance"]) / 3 - 1) < 2e-3
    # The orange light is orange: more power at 650 nm than at 450 nm.
    p = point["intensity"]
    assert np.interp(650, p["wavelengths"], p["values"]) > 2 * np.interp(450, p["wavelengths"], p["values"])
    np.testing.assert_allclose(point["position"], [0, 2, 0], atol=1e-5)
    np.testing.assert_allclose(sun["direction"], [0, -1, 0], atol=1e-5)
    m = np.asarray(spot["to_world"])
    np.testing.assert_allclose(m[:3, 3], [0, 3, 0], atol=1e-5)
    np.testing.assert_allclose(m[:3, 2], [0, -1, 0], atol=1e-5)  # prism's spot shines along +z
    assert abs(spot["cutoff_angle"] - np.degrees(0.5)) < 1e-4 and abs(spot["beam_width"] - np.degrees(0.2)) < 1e-4
