"""The camera against numbers prism did not produce (issue 27, items 1 and 2).

Rotation: the sidecar's `rvec` (and `outputs.camera_matrices`) at 0°, 90°, 179.9° and 180°
and for the Cornell box's camera (180°, where the skew-part Rodrigues formula gives [0, 0, 0]):
cv2.Rodrigues of it must give the R the scene's transform implies, computed here in numpy,
and cv2.projectPoints of every surface point in the position layer must land on its own
pixel centre.

Intrinsics and distortion: the sidecar's K and dist must be the scene's `intrinsics` and
`distortion` exactly (to f32 rounding), and the rendered positions projected with the INPUT
K, dist and a look-at pose built here (not the sidecar's) land on their pixel centres, so a
conversion error that the sidecar shares with the renderer (cx off by half a pixel, p1 and p2
swapped) fails.
"""

from __future__ import annotations

import pathlib
import subprocess

import cv2
import numpy as np
import pytest

from prism_tools import outputs

ROOT = pathlib.Path(__file__).resolve().parents[2]
# Positions are f32, a few units from the camera (~1e-6 relative): 1e-3 px is ~100x that at
# these focal lengths.
PX_TOL = 1e-3
# R from an f32 transform: a few f32 ulps.
R_TOL = 1e-5


def room(camera: str, film: str = "width: 48, height: 36") -> str:
    """A sphere of radius 10 around every camera here: each pixel sees a surface, whatever the
    camera's orientation."""
    return f"""(
    camera: ({camera}),
    film: ({film}, filter: Box()),
    sampler: (spp: 1),
    outputs: (bands: 0),
    shapes: [(shape: Sphere(center: (0.2, -0.1, 0.3), radius: 10), name: "room")],
    emitters: [Constant(radiance: Constant(1))],
    aovs: ["position", "instance"],
)"""


def rot(axis, deg: float) -> np.ndarray:
    """Counter-clockwise rotation about `axis` (prism's `Rotate`), via cv2-free numpy."""
    a = np.asarray(axis, dtype=np.float64)
    a = a / np.linalg.norm(a)
    t = np.radians(deg)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(t) * k + (1 - np.cos(t)) * (k @ k)


def pixel_centres(shape) -> np.ndarray:
    j, i = np.mgrid[0 : shape[0], 0 : shape[1]]
    return np.stack([i, j], axis=-1).astype(np.float64)


def reprojection_error(r: outputs.Render, rvec, t, k, dist) -> float:
    hit = r.layer("instance") > 0
    assert hit.sum() > 0.5 * hit.size
    p = r.layer("position")[hit].astype(np.float64)
    uv, _ = cv2.projectPoints(p, np.asarray(rvec, dtype=np.float64), np.asarray(t, dtype=np.float64), k, dist)
    return float(np.abs(uv[:, 0, :] - pixel_centres(hit.shape)[hit]).max())


AXIS = (1.0, 2.0, -3.0)


@pytest.mark.parametrize("deg", [0.0, 90.0, 179.9, 180.0])
def test_rvec_at_every_angle(render, deg):
    # prism's camera frame is +x left, +y up; turning it 180° about z first makes OpenCV's
    # camera-to-world exactly rot(AXIS, deg), so R = rot(AXIS, deg)ᵀ and |rvec| = deg.
    cam = f"fov: 50, to_world: [Rotate(axis: (0, 0, 1), angle: 180), Rotate(axis: {AXIS}, angle: {deg}), Translate((0.1, 0.2, -0.3))]"
    r = outputs.read(render(room(cam)))
    want = rot(AXIS, deg).T
    side = np.array(r.sidecar["camera"]["rvec"], dtype=np.float64)
    for rvec in (side, outputs.camera_matrices(r.sidecar)["rvec"]):
        assert np.abs(cv2.Rodrigues(rvec)[0] - want).max() < R_TOL, (deg, rvec)
        assert abs(np.linalg.norm(rvec) - np.radians(deg)) < R_TOL, (deg, rvec)
        m = outputs.camera_matrices(r.sidecar)
        assert reprojection_error(r, rvec, m["t"], m["K"], m["dist"]) < PX_TOL


def test_rvec_of_the_cornell_camera(prism_bin, tmp_path):
    out = tmp_path / "cornell.exr"
    subprocess.run(
        [str(prism_bin), "render", str(ROOT / "scenes" / "cornell.ron"), "-o", str(out), "-q", "--spp", "1", "--aovs", "position,instance"],
        check=True,
    )
    r = outputs.read(out)
    # Mitsuba's camera matrix diag(-1, 1, -1) at z = 3.9: OpenCV's R is diag(1, -1, -1), 180° about x.
    want = np.diag([1.0, -1.0, -1.0])
    m = outputs.camera_matrices(r.sidecar)
    for rvec in (np.array(r.sidecar["camera"]["rvec"]), m["rvec"]):
        assert abs(np.linalg.norm(rvec) - np.pi) < R_TOL, rvec
        assert np.abs(cv2.Rodrigues(rvec)[0] - want).max() < R_TOL, rvec
        assert reprojection_error(r, rvec, m["t"], m["K"], m["dist"]) < PX_TOL


FX, FY, CX, CY = 41.0, 39.5, 23.3, 17.6
DIST = (-0.12, 0.02, 0.004, -0.003, 0.001)
EYE, TARGET, UP = (0.4, 0.8, 3.5), (0.1, -0.2, 0.3), (0.0, 1.0, 0.0)


def look_at_opencv(eye, target, up):
    """World → OpenCV camera (x right, y down, z forward) for a look-at, built here."""
    eye, target, up = (np.asarray(v, dtype=np.float64) for v in (eye, target, up))
    z = (target - eye) / np.linalg.norm(target - eye)
    x = np.cross(z, up)
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    r = np.stack([x, y, z])
    return r, -r @ eye


@pytest.mark.parametrize("model", ["Pinhole", "ThinLens(aperture_radius: 1e-6, focus_distance: 3.0)"])
def test_projection_with_the_scene_inputs(render, model):
    k1, k2, p1, p2, k3 = DIST
    cam = (
        f"model: {model}, intrinsics: Some((fx: {FX}, fy: {FY}, cx: {CX}, cy: {CY})), "
        f"distortion: Some((k1: {k1}, k2: {k2}, p1: {p1}, p2: {p2}, k3: {k3})), "
        f"to_world: [LookAt(origin: {EYE}, target: {TARGET}, up: {UP})]"
    )
    r = outputs.read(render(room(cam)))
    k_in = np.array([[FX, 0, CX], [0, FY, CY], [0, 0, 1]])
    d_in = np.array(DIST)
    side = r.sidecar["camera"]
    # The sidecar states the inputs (prism holds them in f32: 1e-6 relative).
    assert np.allclose(side["K"], k_in, rtol=1e-6, atol=0), side["K"]
    assert np.allclose(side["dist"], d_in, rtol=1e-6, atol=0), side["dist"]
    rmat, t = look_at_opencv(EYE, TARGET, UP)
    assert np.abs(np.array(side["R"]) - rmat).max() < R_TOL
    # The render agrees with OpenCV driven by the user's numbers alone.
    err = reprojection_error(r, cv2.Rodrigues(rmat)[0], t, k_in, d_in)
    assert err < PX_TOL, err
    # And the test can tell: half a pixel on cx, or p1 and p2 swapped, is seen.
    k_off = k_in.copy()
    k_off[0, 2] += 0.5
    assert reprojection_error(r, cv2.Rodrigues(rmat)[0], t, k_off, d_in) > 0.4
    d_swap = d_in[[0, 1, 3, 2, 4]]
    assert reprojection_error(r, cv2.Rodrigues(rmat)[0], t, k_in, d_swap) > 100 * PX_TOL
