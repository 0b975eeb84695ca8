"""The camera and the ground-truth layers against OpenCV (an independent implementation of the
pinhole and its distortion model): every surface point the position layer shows, projected by
cv2.projectPoints with the sidecar's K, dist, R and t, lands on its own pixel centre; known 3D
points (sphere centres, a tilted cube's corners) land on pixels whose id and depth layers show
them (the cube's corners and outline to a fraction of a pixel);
cv2.undistortPoints inverts the rendered distortion; the OpenGL pose agrees with OpenCV's;
the sidecar's boxes are the id layer's; the thin lens blurs a point into its circle of confusion.
"""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from prism_tools import outputs, sheet

SPHERES = [((-0.6, 0.3, 0.0), 0.35), ((0.5, -0.2, 0.4), 0.3), ((0.1, 0.6, -0.8), 0.25)]


def scene(camera: str, aovs: str = '"position", "depth", "instance"', extra: str = "") -> str:
    shapes = ", ".join(
        f'(shape: Sphere(center: {c}, radius: {r}), name: "s{i}", label: "ball")' for i, (c, r) in enumerate(SPHERES)
    )
    return f"""(
    camera: ({camera}),
    film: (width: 96, height: 72, filter: Box()),
    sampler: (spp: 2),
    outputs: (bands: 0),
    shapes: [{shapes}, (shape: Rectangle, name: "floor", to_world: [Scale((4, 4, 1)), Rotate(axis: (1, 0, 0), angle: -90), Translate((0, -0.6, 0))])],
    emitters: [Constant(radiance: Constant(1))],
    aovs: [{aovs}],
    {extra}
)"""


LOOK = "to_world: [LookAt(origin: (0.4, 0.8, 3.5), target: (0, 0, 0), up: (0, 1, 0))]"
K = "intrinsics: Some((fx: 90, fy: 88, cx: 46.2, cy: 37.1))"
DIST = "distortion: Some((k1: -0.12, k2: 0.02, p1: 0.002, p2: -0.003, k3: 0.0))"


def pixel_grid(h: int, w: int) -> np.ndarray:
    j, i = np.mgrid[0:h, 0:w]
    return np.stack([i, j], axis=-1).astype(np.float64)


@pytest.mark.parametrize("camera", [f"fov: 45, {LOOK}", f"{K}, {LOOK}", f"{K}, {DIST}, {LOOK}"])
def test_project_points_lands_on_pixel_centres(render, camera):
    r = outputs.read(render(scene(camera)))
    m = outputs.camera_matrices(r.sidecar)
    ids = r.layer("instance")
    hit = ids > 0
    p = r.layer("position")[hit].astype(np.float64)
    uv, _ = cv2.projectPoints(p, m["rvec"], m["t"], m["K"], m["dist"])
    err = np.abs(uv[:, 0, :] - pixel_grid(*ids.shape)[hit])
    # Positions are f32 (~1e-7 relative, a few units from the camera): 1e-3 px is ~100x that.
    assert hit.sum() > 3000
    assert err.max() < 1e-3, err.max()


@pytest.mark.parametrize("camera", [f"{K}, {LOOK}", f"{K}, {DIST}, {LOOK}"])
def test_sphere_centres_on_their_pixels(render, camera):
    r = outputs.read(render(scene(camera)))
    m = outputs.camera_matrices(r.sidecar)
    ids, depth = r.layer("instance"), r.layer("depth")
    for k, (c, rad) in enumerate(SPHERES):
        uv, _ = cv2.projectPoints(np.array([c], dtype=np.float64), m["rvec"], m["t"], m["K"], m["dist"])
        u, v = uv[0, 0]
        i, j = int(round(u)), int(round(v))
        assert ids[j, i] == k + 1, (k, u, v, ids[j, i])
        z = (m["R"] @ np.array(c) + m["t"])[2]
        # The pixel centre is within half a pixel of the centre's image: the surface there is
        # at depth z − rad up to the sphere's curvature over that offset (< 1% of rad here).
        assert abs(depth[j, i] - (z - rad)) < 0.01 * rad + 0.02 * rad, (depth[j, i], z - rad)


def test_undistort_points_inverts_rendered_distortion(render):
    r = outputs.read(render(scene(f"{K}, {DIST}, {LOOK}")))
    m = outputs.camera_matrices(r.sidecar)
    ids = r.layer("instance")
    hit = ids > 0
    pts = pixel_grid(*ids.shape)[hit].reshape(-1, 1, 2)
    crit = (cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS, 100, 1e-14)
    und = cv2.undistortPointsIter(pts, m["K"], m["dist"], None, None, crit)[:, 0, :]
    pc = r.layer("position")[hit].astype(np.float64) @ m["R"].T + m["t"]
    ray = pc[:, :2] / pc[:, 2:3]
    assert np.abs(und - ray).max() < 1e-5
    # And the distortion is real: the undistorted rays are not the pinhole's.
    pin = (pts[:, 0, :] - m["K"][[0, 1], [2, 2]]) / m["K"][[0, 1], [0, 1]]
    assert np.abs(pin - ray).max() > 0.01


def test_opengl_pose_agrees_with_opencv(render):
    r = outputs.read(render(scene(f"fov: 45, {LOOK}")))
    m = outputs.camera_matrices(r.sidecar)
    flip = np.diag([1.0, -1.0, -1.0, 1.0])
    c2w_cv = np.linalg.inv(m["world_to_camera"])
    # The pose comes from prism's f32 camera transform: 1e-6 is a few f32 ulps of a 4-unit pose.
    assert np.allclose(m["camera_to_world_opengl"], c2w_cv @ flip, atol=1e-6)
    # OpenGL looks along −z: the camera's −z axis points at the look-at target.
    fwd = -m["camera_to_world_opengl"][:3, 2]
    eye = m["camera_to_world_opengl"][:3, 3]
    assert np.allclose(eye, [0.4, 0.8, 3.5], atol=1e-6)
    assert np.allclose(fwd, -eye / np.linalg.norm(eye), atol=1e-6)
    assert np.allclose(m["R"] @ m["R"].T, np.eye(3), atol=1e-6)  # f32 look-at columns


def test_sidecar_boxes_are_the_id_layers(render):
    r = outputs.read(render(scene(f"fov: 45, {LOOK}")))
    ids = r.layer("instance")
    for o in r.sidecar["objects"]:
        ys, xs = np.nonzero(ids == o["instance_id"])
        assert o["visible_pixels"] == len(xs)
        if len(xs):
            assert o["bbox"] == [xs.min(), ys.min(), xs.max(), ys.max()]
    assert r.sidecar["labels"] == [{"id": 1, "name": "ball"}]
    assert r.sidecar["render"]["scene_sha256"]


def test_thin_lens_circle_of_confusion(render):
    """An emissive disk of radius a facing the camera at depth z, the lens focused at f: through
    each lens point the disk's image is its in-focus image (a disk of radius s = fx·a/z) shifted
    by fx·o·(1/f − 1/z) (similar triangles through the thin lens), so the image is that disk
    convolved with the circle of confusion, a disk of radius ρ = fx·A·|1/f − 1/z|. Variances of
    a convolution add: E[r²] = s²/2 + ρ²/2 + 1/6 (the box filter)."""
    a_lens, focus, z, fx, a = 0.1, 2.0, 4.0, 200.0, 0.1
    text = f"""(
    camera: (model: ThinLens(aperture_radius: {a_lens}, focus_distance: {focus}),
             intrinsics: Some((fx: {fx}, fy: {fx}, cx: 31.5, cy: 31.5))),
    film: (width: 64, height: 64, filter: Box()),
    sampler: (spp: 64),
    outputs: (bands: 0, rgb: false),
    shapes: [(shape: Disk, flip_normals: true, to_world: [Scale(({a}, {a}, 1)), Translate((0, 0, {z}))],
              emitter: (radiance: Constant(1)))],
)"""
    r = outputs.read(render(text))
    y = r.channels["Y"].astype(np.float64)
    j, i = np.mgrid[0:64, 0:64]
    w = y / y.sum()
    ci, cj = (w * i).sum(), (w * j).sum()
    m2 = (w * ((i - ci) ** 2 + (j - cj) ** 2)).sum()
    s = fx * a / z
    rho = np.sqrt(2 * (m2 - 1 / 6 - s * s / 2))
    expect = fx * a_lens * abs(1 / focus - 1 / z)
    assert abs(ci - 31.5) < 0.05 and abs(cj - 31.5) < 0.05, (ci, cj)
    # 64 spp over ~300 pixels of a mostly covered disk: the second moment's noise is ~0.3%.
    assert abs(rho - expect) < 0.01 * expect, (rho, expect)
    # In focus (z = f) the same disk is sharp: E[r²] = s²/2 + 1/6 alone.
    r = outputs.read(render(text.replace(f"Translate((0, 0, {z}))", f"Translate((0, 0, {focus}))")))
    y = r.channels["Y"].astype(np.float64)
    w = y / y.sum()
    m2 = (w * ((i - 31.5) ** 2 + (j - 31.5) ** 2)).sum()
    s = fx * a / focus
    assert abs(m2 - (s * s / 2 + 1 / 6)) < 0.01 * m2


def test_outputs_reader_and_sheet(render, tmp_path):
    out = render(scene(f"fov: 45, {LOOK}", aovs='"depth", "normal", "instance", "alpha"'), "--aovs", "depth,normal,instance,uv")
    r = outputs.read(out)
    assert r.layer("instance").dtype == np.uint32
    assert r.layer("normal").shape == (72, 96, 3)
    assert "uv.U" in r.channels and "alpha.A" not in r.channels  # --aovs overrides the scene
    hit = r.layer("instance") > 0
    assert np.allclose(np.linalg.norm(r.layer("normal")[hit], axis=-1), 1, atol=1e-5)
    assert np.all(np.isinf(r.layer("depth")[~hit]))
    img = sheet.sheet(r)
    assert img.shape[2] == 3 and img.shape[1] > 3 * 96


def test_spectral_cube_sorted_with_its_wavelengths(render):
    out = render(scene(f"fov: 45, {LOOK}", extra="").replace("outputs: (bands: 0),", "outputs: (bands: 12, band_range: (380, 740)),"))
    r = outputs.read(out)
    assert r.spectral.shape == (72, 96, 12)
    assert np.all(np.diff(r.wavelengths) > 0)
    side = [b["center_nm"] for b in r.sidecar["sensor"]["bands"]["bands"]]
    assert np.allclose(r.wavelengths, side)


def test_stderr_matches_spread_across_seeds(render):
    """stderr.Y and a band's stderr against the spread of the same pixel over 16 seeds (the
    Independent sampler, whose samples are independent as the formula assumes; Sobol's
    stratified estimate has a smaller real error, so there stderr is conservative). Mean over
    ~800 lit pixels of the variance across seeds (ddof 1) against the mean of stderr². The
    light's paths are heavy-tailed, so the ratio scatters more than Gaussian samples would:
    three sets of 16 seeds gave 0.996, 0.979, 0.971 (8 seeds: 1.056, 1.084); 12% covers that."""
    text = """(
    camera: (fov: 40, to_world: [LookAt(origin: (0, 1, 4), target: (0, 0, 0), up: (0, 1, 0))]),
    film: (width: 64, height: 48),
    sampler: (kind: Independent, spp: 8),
    outputs: (bands: 4, band_range: (400, 700)),
    shapes: [(shape: Sphere(radius: 1)), (shape: Rectangle, emitter: (radiance: Constant(3)),
              to_world: [Scale((0.5, 0.5, 1)), Rotate(axis: (1, 0, 0), angle: 90), Translate((0.5, 2, 0))])],
    aovs: ["stderr"],
)"""
    runs = [outputs.read(render(text, "--seed", str(s))) for s in range(16)]
    for ch in ["Y", "S0.512,500000nm"]:
        vals = np.stack([r.channels[ch] for r in runs])
        se = np.stack([r.channels[f"stderr.{ch}"] for r in runs])
        lit = vals.mean(axis=0) > 0.01 * vals.mean()
        assert lit.sum() > 600
        ratio = vals.var(axis=0, ddof=1)[lit].mean() / (se**2)[:, lit].mean()
        assert abs(ratio - 1) < 0.12, (ch, ratio)
    assert "stderr.S0.512,500000nm" in runs[0].sidecar["aovs"][0]["channels"]


def test_orthographic_camera_maps_points_linearly(render):
    """Orthographic: pixel = K·(x_cam, y_cam) with fx, fy in pixels per unit (the sidecar's K),
    depth is z_cam, distance equals depth, and every ray is parallel to the optical axis."""
    r = outputs.read(render(scene(f"model: Orthographic(width: 3.0), {LOOK}", aovs='"position", "depth", "distance", "instance"')))
    m = outputs.camera_matrices(r.sidecar)
    assert r.sidecar["camera"]["model"] == "orthographic"
    assert m["K"][0, 0] == pytest.approx(96 / 3.0)
    hit = r.layer("instance") > 0
    pc = r.layer("position")[hit].astype(np.float64) @ m["R"].T + m["t"]
    uv = pc[:, :2] * m["K"][[0, 1], [0, 1]] + m["K"][[0, 1], [2, 2]]
    assert hit.sum() > 3000
    assert np.abs(uv - pixel_grid(*hit.shape)[hit]).max() < 1e-3
    assert np.allclose(r.layer("depth")[hit], pc[:, 2], atol=1e-5)
    assert np.array_equal(r.layer("depth"), r.layer("distance"))


# A cube ([-1, 1]³ in its own frame) scaled, tilted about two axes and moved: three faces and
# seven corners in view (six on the silhouette, one inside it), the eighth behind the cube.
CUBE_OPS = [("scale", 0.6), ("rotate", (1, 0, 0), 28.0), ("rotate", (0, 1, 0), -37.0), ("translate", (0.15, 0.1, 0.0))]
CUBE_K = "intrinsics: Some((fx: 150, fy: 146, cx: 63.4, cy: 47.8))"


def cube_scene(camera: str) -> str:
    steps = []
    for op in CUBE_OPS:
        if op[0] == "scale":
            steps.append(f"Scale(({op[1]}, {op[1]}, {op[1]}))")
        elif op[0] == "rotate":
            steps.append(f"Rotate(axis: {op[1]}, angle: {op[2]})")
        else:
            steps.append(f"Translate({op[1]})")
    return f"""(
    camera: ({camera}),
    film: (width: 128, height: 96, filter: Box()),
    sampler: (spp: 1),
    outputs: (bands: 0),
    shapes: [(shape: Cube, name: "cube", to_world: [{", ".join(steps)}])],
    emitters: [Constant(radiance: Constant(1))],
    aovs: ["position", "depth", "instance"],
)"""


def cube_to_world() -> np.ndarray:
    """The cube's transform composed independently of prism (scipy's rotations; right-handed,
    counter-clockwise about the axis, the list's first step acting first)."""
    from scipy.spatial.transform import Rotation

    m = np.eye(4)
    for op in CUBE_OPS:
        s = np.eye(4)
        if op[0] == "scale":
            s[:3, :3] *= op[1]
        elif op[0] == "rotate":
            ax = np.array(op[1], dtype=np.float64)
            s[:3, :3] = Rotation.from_rotvec(np.radians(op[2]) * ax / np.linalg.norm(ax)).as_matrix()
        else:
            s[:3, 3] = op[1]
        m = s @ m
    return m


def project(m: dict, pts: np.ndarray, dist: bool = True) -> np.ndarray:
    d = m["dist"] if dist else np.zeros(5)
    return cv2.projectPoints(np.asarray(pts, dtype=np.float64).reshape(-1, 3), m["rvec"], m["t"], m["K"], d)[0][:, 0, :]


@pytest.mark.parametrize("camera", [f"{CUBE_K}, {LOOK}", f"{CUBE_K}, {DIST}, {LOOK}"])
def test_cube_corners_on_their_pixels(render, camera):
    """The eight corners of a tilted cube, projected by cv2.projectPoints with the sidecar's K,
    dist, R, t, against the id, depth and position layers.

    Visibility from the depth layer: a corner is seen when the surface at its pixel is not in
    front of it (the hidden corner's pixel shows the cube's front, nearer by ~the cube's size).

    Where the layers put each seen corner: on every face that meets at it, the position layer
    gives, for each pixel centre near the corner, the point of that face (in the face's own 2D
    coordinates) the pixel sees. Undistorted by cv2.undistortPoints, pixel and face point are
    related by a plane homography exactly; fitted to the ≥ 10 pixels within 5 px of the corner
    it carries the face point (0, 0), the corner, to the render's image of it, which must be
    cv2's projection to 2e-3 px: positions are f32 (~1e-6 scene units here, ~1e-4 px) and the
    fit extrapolates at most a few pixels from its data (measured: 3.2e-4 px at worst over the
    11 faces, 5.8e-5 px with distortion).

    The id layer's edges: the cube's outline is the image of the convex hull of its projected
    corners (pinhole), each hull edge a 3D edge of the cube projected densely with distortion.
    Every pixel centre more than 0.01 px from that outline must be cube inside it and background
    outside it; the pixel centres between 0.01 and 0.05 px from it (≥ 5 of them) would be
    misclassified by an outline (or corner) 0.05 px off (moving cx by 0.02 px already
    misclassifies 1 and 3 of them). 0.01 px is ~50× the ray-cube intersection's f32 error and
    ~100× the polyline's chord error."""
    r = outputs.read(render(cube_scene(camera)))
    m = outputs.camera_matrices(r.sidecar)
    to_world = cube_to_world()
    assert np.allclose(np.array(r.sidecar["objects"][0]["to_world"]), to_world, atol=1e-6)
    signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=np.float64)
    corners = signs @ to_world[:3, :3].T + to_world[:3, 3]
    uv = project(m, corners)
    z = (corners @ m["R"].T + m["t"])[:, 2]
    ids, depth = r.layer("instance"), r.layer("depth")
    pos = r.layer("position").astype(np.float64)
    h, w = ids.shape
    assert np.all((uv > 2) & (uv < [w - 3, h - 3])), uv  # every corner inside the frame
    obj = (pos - to_world[:3, 3]) @ np.linalg.inv(to_world[:3, :3]).T  # cube's own frame
    grid = pixel_grid(h, w)
    crit = (cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS, 100, 1e-15)
    seen = []
    for k in range(8):
        i, j = np.round(uv[k]).astype(int)
        win = (slice(j - 1, j + 2), slice(i - 1, i + 2))
        cube_px = ids[win] == 1
        front = depth[win][cube_px]
        visible = front.size > 0 and front.max() > z[k] - 0.05
        if not visible:
            # Hidden by the cube itself: the surface it sees is well in front of the corner.
            assert front.size and front.max() < z[k] - 0.3, (k, front, z[k])
            continue
        seen.append(k)
        # The depth layer next to the corner is the corner's depth up to ~1.5 px of slope.
        assert np.abs(front - z[k]).min() < 0.05, (k, front, z[k])
        near = (ids == 1) & (np.linalg.norm(grid - uv[k], axis=-1) < 5)
        faces = 0
        for axis in range(3):
            on = near & (np.abs(obj[..., axis] - signs[k, axis]) < 1e-4)
            if on.sum() < 10:
                continue
            faces += 1
            others = [a for a in range(3) if a != axis]
            face_pts = (obj[on][:, others] - signs[k, others]).astype(np.float64)
            und = cv2.undistortPointsIter(grid[on].reshape(-1, 1, 2), m["K"], m["dist"], None, None, crit)[:, 0, :]
            hom, _ = cv2.findHomography(face_pts, und, 0)
            x0 = hom @ np.array([0.0, 0.0, 1.0])
            img = cv2.projectPoints(np.array([[x0[0] / x0[2], x0[1] / x0[2], 1.0]]), np.zeros(3), np.zeros(3), m["K"], m["dist"])[0][0, 0]
            assert np.linalg.norm(img - uv[k]) < 2e-3, (k, axis, img, uv[k])
        assert faces >= 1, k
    assert len(seen) == 7 and int(np.argmax(z)) not in seen, (seen, z)

    # The id layer's outline.
    hull = cv2.convexHull(project(m, corners, dist=False).astype(np.float32), returnPoints=False)[:, 0]
    assert len(hull) == 6
    s = np.linspace(0, 1, 400, endpoint=False)[:, None]
    outline = np.concatenate([project(m, corners[a] + s * (corners[b] - corners[a])) for a, b in zip(hull, np.roll(hull, -1))])
    poly = outline.astype(np.float32).reshape(-1, 1, 2)
    sd = np.array([[cv2.pointPolygonTest(poly, (float(x), float(y)), True) for x in range(w)] for y in range(h)])
    far = np.abs(sd) > 0.01
    assert np.array_equal((ids == 1)[far], (sd > 0)[far]), np.argwhere(far & ((ids == 1) != (sd > 0)))
    assert ((np.abs(sd) > 0.01) & (np.abs(sd) < 0.05)).sum() >= 5


def test_boxes_only_when_traced_or_asked(render):
    """A render without geometry or id AOVs traces no pixel-centre rays, so its sidecar has no
    boxes (never a stale or guessed one); `--boxes` (or `boxes: true`) adds them, equal to the
    boxes of a render that writes the instance layer; `alpha` and `stderr` alone need no hits."""
    text = scene(f"fov: 45, {LOOK}", aovs="")
    with_ids = outputs.read(render(scene(f"fov: 45, {LOOK}", aovs='"instance"'))).sidecar["objects"]
    for args in [(), ("--aovs", "alpha,stderr")]:
        objs = outputs.read(render(text, *args)).sidecar["objects"]
        assert all("bbox" not in o and "visible_pixels" not in o for o in objs)
        assert [o["name"] for o in objs] == [o["name"] for o in with_ids]
    for out in [render(text, "--boxes"), render(text.replace("aovs: [],", "aovs: [], boxes: true,"))]:
        objs = outputs.read(out).sidecar["objects"]
        assert [(o["bbox"], o["visible_pixels"]) for o in objs] == [(o["bbox"], o["visible_pixels"]) for o in with_ids]
    assert sum(o["visible_pixels"] > 0 for o in with_ids) == 4
