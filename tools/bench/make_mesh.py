"""Writes the benchmark's large mesh: a bumpy sphere of about a million triangles, as binary PLY.

    python3 tools/bench/make_mesh.py [--triangles 1000000] [-o out/bench/mesh_1m.ply]

The mesh is generated, not committed (out/ is gitignored); tools/bench/bench.py runs this when
the file is missing. A latitude-longitude grid of the unit sphere, displaced along the normal by
a few sine octaves so neighbouring triangles face different ways (a smooth sphere would let
both renderers' BVHs look better than on scanned geometry). Deterministic: same arguments, same
bytes. Needs only numpy.
"""

from __future__ import annotations

import argparse
import math
import pathlib

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]


def bumpy_sphere(triangles: int) -> tuple[np.ndarray, np.ndarray]:
    # A grid of nu × nv quads (two triangles each, one in the rows at the poles) with nu = 2 nv.
    nv = max(4, math.ceil(math.sqrt(triangles / 4)) + 1)  # at least `triangles` after the poles
    nu = 2 * nv
    theta = np.linspace(0.0, math.pi, nv + 1)
    phi = np.linspace(0.0, 2 * math.pi, nu, endpoint=False)
    th, ph = np.meshgrid(theta, phi, indexing="ij")
    n = np.stack([np.sin(th) * np.cos(ph), np.cos(th), np.sin(th) * np.sin(ph)], axis=-1)
    # Scaled by sin θ so the bumps vanish at the poles, where each grid row's vertices coincide:
    # the surface stays closed there.
    bump = np.sin(th) * (
        0.06 * np.sin(7 * th) * np.cos(5 * ph)
        + 0.03 * np.sin(23 * th + 1.0) * np.sin(19 * ph)
        + 0.012 * np.cos(71 * th) * np.sin(67 * ph + 0.5)
    )
    pos = n * (1.0 + bump)[..., None]
    pos[0], pos[-1] = (0.0, 1.0, 0.0), (0.0, -1.0, 0.0)  # exact poles (sin π is not 0 in floats)
    pos = pos.reshape(-1, 3).astype("<f4")
    i = np.arange(nv)[:, None]
    j = np.arange(nu)[None, :]
    a = i * nu + j
    b = i * nu + (j + 1) % nu
    c = (i + 1) * nu + j
    d = (i + 1) * nu + (j + 1) % nu
    upper = np.stack([a, b, c], axis=-1)[1:].reshape(-1, 3)  # row 0 touches the north pole
    lower = np.stack([b, d, c], axis=-1)[:-1].reshape(-1, 3)  # the last row the south pole
    faces = np.concatenate([upper, lower]).astype("<i4")  # counter-clockwise seen from outside
    return pos, faces


def write_ply(path: pathlib.Path, pos: np.ndarray, faces: np.ndarray) -> None:
    header = (
        "ply\nformat binary_little_endian 1.0\n"
        "comment prism benchmark mesh (tools/bench/make_mesh.py)\n"
        f"element vertex {len(pos)}\nproperty float x\nproperty float y\nproperty float z\n"
        f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n"
    )
    rec = np.empty(len(faces), dtype=[("n", "u1"), ("i", "<i4", (3,))])
    rec["n"] = 3
    rec["i"] = faces
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".tmp")
    with open(tmp, "wb") as f:
        f.write(header.encode("ascii"))
        f.write(pos.tobytes())
        f.write(rec.tobytes())
    tmp.replace(path)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--triangles", type=int, default=1_000_000)
    ap.add_argument("-o", "--output", type=pathlib.Path, default=ROOT / "out/bench/mesh_1m.ply")
    args = ap.parse_args()
    pos, faces = bumpy_sphere(args.triangles)
    write_ply(args.output, pos, faces)
    print(f"wrote {args.output}: {len(pos)} vertices, {len(faces)} triangles")


if __name__ == "__main__":
    main()
