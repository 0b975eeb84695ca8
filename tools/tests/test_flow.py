"""The flow layers (issue 30 item 3) against independent data: OpenCV's projection of the
position layer with the next frame's own sidecar, the closed form of a moving object's
motion, and the inverse relation between forward and backward flow.

Each test renders frames of one animated scene at times t and t + 1/fps with
`prism render --time`: the flow of frame t is computed by prism from the motion alone, the
next frame's K, R, t and dist are what its own render wrote in its sidecar.
"""

from __future__ import annotations

import subprocess

import cv2
import numpy as np
import pytest

from prism_tools import outputs

FPS = 10.0
W, H = 96, 72
K = "intrinsics: Some((fx: 90, fy: 88, cx: 46.2, cy: 37.1))"
DIST = "distortion: Some((k1: -0.12, k2: 0.02, p1: 0.002, p2: -0.003, k3: 0.0))"
# A camera walking to the right and turning towards the scene's centre.
WALK = """animation: (keys: [
    (time: 0, to_world: [LookAt(origin: (-0.8, 0.9, 3.4), target: (0.2, 0, 0), up: (0, 1, 0))]),
    (time: 1, to_world: [LookAt(origin: (0.9, 0.6, 3.1), target: (-0.1, 0.1, 0), up: (0, 1, 0))]),
])"""
STILL = "to_world: [LookAt(origin: (0.4, 0.8, 3.5), target: (0, 0, 0), up: (0, 1, 0))]"
FLOWS = [
    "position",
    "instance",
    "flow_forward",
    "flow_backward",
    "flow_forward_occlusion",
    "flow_backward_occlusion",
    "scene_flow_forward",
    "scene_flow_forward_camera",
]
# A cube sliding right and up while it turns 90° about y over the second (to_world applies
# its entries first to last: the key at 1 s is T(0.5, 0.2, 0)·R_y(90°)).
SPIN = """(shape: Cube, name: "cube", to_world: [], animation: (keys: [
    (time: 0, to_world: [Scale((0.3, 0.3, 0.3)), Translate((-0.5, 0, 0))]),
    (time: 1, to_world: [Scale((0.3, 0.3, 0.3)), Rotate(axis: (0, 1, 0), angle: 90), Translate((0.5, 0.2, 0))]),
]))"""


def scene(camera: str, moving: str = "") -> str:
    shapes = [
        '(shape: Sphere(center: (-0.6, 0.3, 0.0), radius: 0.35))',
        '(shape: Sphere(center: (0.6, -0.2, 0.5), radius: 0.3))',
        '(shape: Rectangle, to_world: [Scale((4, 4, 1)), Rotate(axis: (1, 0, 0), angle: -90), Translate((0, -0.6, 0))])',
    ]
    if moving:
        shapes.append(moving.replace("to_world: [], ", ""))
    aovs = ", ".join(f'"{a}"' for a in FLOWS)
    return f"""(
    camera: ({camera}, fps: {FPS}),
    film: (width: {W}, height: {H}, filter: Box()),
    sampler: (spp: 1),
    outputs: (bands: 0),
    shapes: [{", ".join(shapes)}],
    emitters: [Constant(radiance: Constant(1))],
    aovs: [{aovs}],
)"""


@pytest.fixture
def frames(prism_bin, tmp_path):
    """frames(scene_text, times) -> [outputs.Render] rendered at each time."""

    def run(text: str, times: list[float]) -> list:
        path = tmp_path / "scene.ron"
        path.write_text(text)
        out = []
        for k, t in enumerate(times):
            exr = tmp_path / f"f{k}.exr"
            subprocess.run(
                [str(prism_bin), "render", str(path), "-o", str(exr), "-q", "--time", repr(t)],
                check=True,
            )
            out.append(outputs.read(exr))
        return out

    return run


def centres() -> np.ndarray:
    j, i = np.mgrid[0:H, 0:W]
    return np.stack([i, j], axis=-1).astype(np.float64)


def project(points: np.ndarray, sidecar: dict) -> np.ndarray:
    m = outputs.camera_matrices(sidecar)
    uv, _ = cv2.projectPoints(points.reshape(-1, 1, 3), m["rvec"], m["t"], m["K"], m["dist"])
    return uv[:, 0, :]


@pytest.mark.parametrize("camera", [f"fov: 50, {WALK}", f"{K}, {DIST}, {WALK}"])
def test_static_scene_flow_is_the_next_frames_projection(frames, camera):
    t = 0.4
    a, b = frames(scene(camera), [t, t + 1 / FPS])
    for src, dst, name in [(a, b, "flow_forward"), (b, a, "flow_backward")]:
        hit = src.layer("instance") > 0
        p = src.layer("position")[hit].astype(np.float64)
        uv = project(p, dst.sidecar)
        want = uv - centres()[hit]
        got = src.layer(name)[hit].astype(np.float64)
        # Only where the point stays near the image: beyond it a strong distortion folds, and
        # prism gives no flow (the point is marked as leaving) while OpenCV still projects.
        near = np.all((uv > -10) & (uv < np.array([W + 10, H + 10])), axis=1)
        err = np.abs(got - want)[near]
        # Positions are f32 (~1e-7 relative, a few units from the camera): 1e-3 px is far
        # above their rounding and far below any error in the motion or the camera model.
        assert near.sum() > 0.9 * hit.sum() > 3000
        assert err.max() < 1e-3, (name, err.max())
        assert np.abs(want).max() > 3, "the camera moves several pixels per frame"


def rot_y(deg: float) -> np.ndarray:
    a = np.radians(deg)
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def cube_pose(t: float) -> tuple[np.ndarray, np.ndarray]:
    """The cube's rotation and centre at time t: linear translation, slerp about y."""
    c = np.array([-0.5, 0, 0]) + t * np.array([1.0, 0.2, 0])
    return rot_y(90 * t), c


def test_moving_object_flow_is_its_closed_form(frames):
    t = 0.3
    (a,) = frames(scene(STILL, SPIN), [t])
    ids = a.layer("instance")
    cube = ids == 4
    p = a.layer("position")[cube].astype(np.float64)
    (r0, c0), (r1, c1) = cube_pose(t), cube_pose(t + 1 / FPS)
    p2 = (p - c0) @ r0 @ r1.T + c1  # R1 · R0ᵀ · (p − c0) + c1, row vectors
    want = project(p2, a.sidecar) - centres()[cube]
    got = a.layer("flow_forward")[cube].astype(np.float64)
    # f32 hit points and f32 keys (1e-7 relative): 1e-3 px.
    assert cube.sum() > 200
    assert np.abs(got - want).max() < 1e-3, np.abs(got - want).max()
    sf = a.layer("scene_flow_forward")[cube].astype(np.float64)
    assert np.abs(sf - (p2 - p)).max() < 1e-5
    # The camera stands still: the camera-frame scene flow is R·(p' − p).
    m = outputs.camera_matrices(a.sidecar)
    sfc = a.layer("scene_flow_forward_camera")[cube].astype(np.float64)
    assert np.abs(sfc - (p2 - p) @ m["R"].T).max() < 1e-5
    # Everything else stands still.
    still = (ids > 0) & ~cube
    assert np.abs(a.layer("flow_forward")[still]).max() < 1e-3


def bilinear(img: np.ndarray, xy: np.ndarray) -> np.ndarray:
    x0 = np.floor(xy[:, 0]).astype(int)
    y0 = np.floor(xy[:, 1]).astype(int)
    fx, fy = (xy[:, 0] - x0)[:, None], (xy[:, 1] - y0)[:, None]
    v = lambda dx, dy: img[y0 + dy, x0 + dx]
    return (v(0, 0) * (1 - fx) + v(1, 0) * fx) * (1 - fy) + (v(0, 1) * (1 - fx) + v(1, 1) * fx) * fy


def test_forward_and_backward_flow_are_inverse(frames):
    t = 0.4
    a, b = frames(scene(f"{K}, {WALK}", SPIN), [t, t + 1 / FPS])
    fwd = a.layer("flow_forward").astype(np.float64)
    ok = a.layer("flow_forward_occlusion") == 0
    xy = centres()[ok] + fwd[ok]
    ids_a = a.layer("instance")[ok]
    src = fwd[ok]
    # The 4×4 pixels around the landing point's cell: inside the image, seen at t (backward
    # occlusion 0) and on the same object, so the backward flow is smooth over them.
    x0, y0 = np.floor(xy[:, 0]).astype(int), np.floor(xy[:, 1]).astype(int)
    inside = (x0 >= 1) & (y0 >= 1) & (x0 < W - 2) & (y0 < H - 2)
    xy, ids_a, src, x0, y0 = xy[inside], ids_a[inside], src[inside], x0[inside], y0[inside]
    occ_b, ids_b = b.layer("flow_backward_occlusion"), b.layer("instance")
    same = np.ones(len(xy), bool)
    for dx in (-1, 0, 1, 2):
        for dy in (-1, 0, 1, 2):
            same &= (occ_b[y0 + dy, x0 + dx] == 0) & (ids_b[y0 + dy, x0 + dx] == ids_a)
    bwd = b.layer("flow_backward").astype(np.float64)
    back = bilinear(bwd, xy[same])
    err = np.abs(back + src[same]).max(axis=1)
    # Bilinear interpolation over a pixel cell errs by at most (|f_xx| + |f_yy|)/8 there
    # (it reproduces the xy term exactly). The bound per point takes the largest second
    # differences of the backward flow at the cell's four pixels, doubled for the terms a
    # second difference leaves out, plus 1e-3 px for the f32 positions.
    dxx = np.abs(bwd[:, 2:] - 2 * bwd[:, 1:-1] + bwd[:, :-2]).max(axis=-1)
    dyy = np.abs(bwd[2:] - 2 * bwd[1:-1] + bwd[:-2]).max(axis=-1)
    xs, ys = x0[same], y0[same]
    curv = np.zeros(len(xs))
    for dx in (0, 1):
        for dy in (0, 1):
            curv = np.maximum(curv, dxx[ys + dy, xs + dx - 1] + dyy[ys + dy - 1, xs + dx])
    bound = 0.25 * curv + 1e-3
    assert same.sum() > 2000, same.sum()
    assert np.all(err <= bound), (err.max(), err[err > bound][:5], bound[err > bound][:5])
    # Most of the image is smooth: there the two flows agree to a few thousandths of a pixel.
    assert np.median(err) < 1e-3, np.median(err)
    # Where the mask says a point is seen next frame, the next frame's pixel there shows the
    # same object (rounding to the nearest pixel: all but the outline's pixels agree).
    near = np.rint(xy).astype(int)
    agree = ids_b[near[:, 1], near[:, 0]] == ids_a
    assert agree.mean() > 0.97, agree.mean()
