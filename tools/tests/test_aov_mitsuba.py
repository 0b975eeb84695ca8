"""prism's AOV layers against Mitsuba 3's `aov` integrator on the exported scene, pixel by
pixel: depth (Mitsuba's `depth` is the hit's ray distance si.t, from the near plane), position,
uv, sh_normal, geo_normal and shape_index.

Mitsuba's AOVs are box-filtered averages over each pixel (random points in the pixel); prism's
are the values at the pixel centre. The two agree to second order in the pixel size where the
surface is smooth, so pixels are compared where all 3×3 neighbours see the same shape in both
renders and the same face of it (no silhouette or edge in the footprint), with the
tolerance stated in `check`.
"""

from __future__ import annotations

import json
import subprocess

import mitsuba as mi
import numpy as np

from prism_tools import mitsuba_scene as ms
from prism_tools import outputs

SPP = 64

SCENE = """(
    camera: (fov: 45, near_clip: 0.001, to_world: [LookAt(origin: (0.5, 1.2, 3.6), target: (0, 0.1, 0), up: (0, 1, 0))]),
    film: (width: 80, height: 60, filter: Box()),
    sampler: (spp: 1),
    outputs: (bands: 0),
    materials: {"a": Diffuse(reflectance: Constant(0.3)), "b": Diffuse(reflectance: Constant(0.6)), "c": Diffuse()},
    shapes: [
        (shape: Sphere(center: (-0.5, 0.3, 0), radius: 0.55), material: "a"),
        (shape: Cube, material: "b", to_world: [Scale((0.35, 0.35, 0.35)), Rotate(axis: (0, 1, 0), angle: 30), Translate((0.7, 0.05, 0.2))]),
        (shape: Rectangle, material: "c", to_world: [Scale((3, 3, 1)), Rotate(axis: (1, 0, 0), angle: -80), Translate((0, -0.3, 0))]),
    ],
    emitters: [Constant(radiance: Constant(1))],
    aovs: ["distance", "position", "uv", "normal", "geo_normal", "instance"],
)"""


def test_aovs_match_mitsuba(prism_bin, tmp_path):
    (tmp_path / "s.ron").write_text(SCENE)
    out = tmp_path / "o.exr"
    subprocess.run([str(prism_bin), "render", str(tmp_path / "s.ron"), "-o", str(out), "-q"], check=True)
    subprocess.run([str(prism_bin), "export", str(tmp_path / "s.ron"), "-o", str(tmp_path / "x")], check=True)
    r = outputs.read(out)
    exported = json.loads((tmp_path / "x" / "scene.json").read_text())
    mi.set_variant("scalar_spectral")
    d = ms.convert(exported, spp=SPP, seed=3)
    d["integrator"] = {"type": "aov", "aovs": "dd:depth,pp:position,uv:uv,sn:sh_normal,gn:geo_normal,si:shape_index"}
    img = np.array(mi.render(mi.load_dict(d)))
    # Channels: R, G, B (the inner integrator's... none here) then the AOVs in order.
    names = ["dd", "pp.x", "pp.y", "pp.z", "uv.u", "uv.v", "sn.x", "sn.y", "sn.z", "gn.x", "gn.y", "gn.z", "si"]
    m = dict(zip(names, np.moveaxis(img[..., -len(names):], -1, 0)))
    ids = r.layer("instance").astype(np.int64)
    # Mitsuba's shape order is its own (and it merges meshes that share a BSDF, hence one
    # material per shape here): map each Mitsuba index to prism's instance by vote.
    si = np.rint(m["si"]).astype(np.int64)
    hit = ids > 0
    mapping = {}
    for s in np.unique(si[hit]):
        vals, counts = np.unique(ids[hit & (si == s)], return_counts=True)
        mapping[s] = vals[np.argmax(counts)]
    assert sorted(mapping.values()) == [1, 2, 3]
    mid = np.vectorize(lambda s: mapping.get(s, -1))(si)
    # Mitsuba's shape_index is 0 on misses as well: use its depth to see misses.
    mid[m["dd"] <= 0] = 0
    same = np.ones_like(hit)
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            sh = lambda a: np.roll(np.roll(a, dy, 0), dx, 1)  # noqa: E731
            same &= (sh(ids) == ids) & (sh(mid) == ids)
            # ... and the same face (the cube's edges are inside one shape).
            same &= np.linalg.norm(sh(r.layer("geo_normal")) - r.layer("geo_normal"), axis=-1) < 0.2
    same[[0, -1], :] = False
    same[:, [0, -1]] = False
    inside = same & hit
    assert inside.sum() > 1500
    # Id agreement everywhere but on silhouettes (box-filtered ids there are a mixture).
    assert np.mean(mid[hit] == ids[hit]) > 0.97
    def check(theirs: np.ndarray, ours: np.ndarray, what: str, mask: np.ndarray | None = None) -> None:
        """Per pixel: |Mitsuba − prism| ≤ 5σ + |∇²f|/24 + 1e-5·(1 + |f|), where σ = |∇f|/√(12·spp)
        is the noise of a 64-sample mean of a field varying linearly across the pixel
        (gradient from prism's neighbouring pixel centres), |∇²f|/24 the pixel mean's
        second-order offset from the centre value, 1e-5 float32 rounding."""
        with np.errstate(invalid="ignore"):  # inf − inf at background pixels, never selected
            gy, gx = np.gradient(ours, axis=(0, 1))
            lap = np.abs(np.roll(ours, 1, 0) + np.roll(ours, -1, 0) + np.roll(ours, 1, 1) + np.roll(ours, -1, 1) - 4 * ours)
        tol = 5 * np.hypot(gx, gy) / np.sqrt(12 * SPP) + lap / 24 + 1e-5 * (1 + np.abs(ours))
        sel = inside if mask is None else inside & mask
        bad = np.abs(theirs - ours)[sel] > tol[sel]
        assert bad.sum() == 0, f"{what}: {bad.sum()} pixels, worst {np.max(np.abs(theirs - ours)[sel] - tol[sel])}"

    # Depth: Mitsuba's is the distance from the near plane, prism's from the camera centre.
    cam = outputs.camera_matrices(r.sidecar)
    p = r.layer("position").reshape(-1, 3).astype(np.float64)
    pc = (p @ cam["R"].T + cam["t"]).reshape(ids.shape + (3,))
    near_offset = 0.001 * np.linalg.norm(pc, axis=-1) / pc[..., 2]
    check(m["dd"] + near_offset, r.layer("distance").astype(np.float64), "distance")
    for c, axis in enumerate("xyz"):
        check(m[f"pp.{axis}"], r.layer("position")[..., c], f"position.{axis}")
        check(m[f"sn.{axis}"], r.layer("normal")[..., c], f"sh_normal.{axis}")
        check(m[f"gn.{axis}"], r.layer("geo_normal")[..., c], f"geo_normal.{axis}")
    # uv is compared away from the sphere's seam (u jumps from 1 to 0 there).
    uvl = r.layer("uv")
    smooth = np.ones_like(inside)
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            smooth &= np.abs(np.roll(np.roll(uvl, dy, 0), dx, 1) - uvl).max(axis=-1) < 0.2
    assert (inside & smooth).sum() > 0.9 * inside.sum()
    for c, axis in enumerate("uv"):
        check(m[f"uv.{axis}"], uvl[..., c], f"uv.{axis}", smooth)
