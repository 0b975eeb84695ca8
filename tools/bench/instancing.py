"""Render speed and memory of instancing against flattening, on one scene.

    tools/.venv/bin/python tools/bench/instancing.py [--count 16] [--triangles 100000] [--runs 4] [--spp 16]

`--count` uses of a `--triangles` bumpy sphere (tools/bench/make_mesh.py, written to
out/bench/) on a 4-wide grid over a floor, under an area light, rendered twice per run:
instanced (the default for a mesh used more than once) and flattened (`flatten: true`, every
use copied into world space, one BVH over all triangles). Runs alternate (instanced, flattened,
...) so drifts of a shared machine hit both. Reports each one's render throughput (Msamples/s
from prism's summary line: render time only), the ratio instanced / flattened with a 95%
confidence interval (t distribution on the per-pair ratios), the wall time (with loading and
BVH builds) and the peak resident memory (os.wait4's ru_maxrss).
"""

from __future__ import annotations

import argparse
import os
import pathlib
import re
import statistics
import subprocess
import sys
import tempfile
import time

from scipy import stats

ROOT = pathlib.Path(__file__).resolve().parents[2]


def scene(mesh: pathlib.Path, count: int, flatten: bool) -> str:
    shapes = []
    for k in range(count):
        x, z = (k % 4) * 2.2 - 3.3, (k // 4) * 2.2
        shapes.append(
            f'(shape: Mesh(path: "{mesh}"), material: "clay", '
            f"to_world: [Rotate(axis: (0, 1, 0), angle: {k * 37 % 360}), Translate(({x}, 1, {-z}))]),"
        )
    depth = (count + 3) // 4 * 2.2
    return f"""(
    camera: (fov: 45, to_world: [LookAt(origin: (0, 4, 5), target: (0, 0.5, {-depth / 2}), up: (0, 1, 0))]),
    film: (width: 160, height: 120, filter: Box()),
    integrator: (max_depth: 6),
    flatten: {"true" if flatten else "false"},
    materials: {{"clay": Diffuse(reflectance: Rgb(0.7, 0.55, 0.4)), "floor": Diffuse(reflectance: Constant(0.5))}},
    shapes: [
        {chr(10).join(shapes)}
        (shape: Rectangle, material: "floor", to_world: [Scale((20, 20, 1)), Rotate(axis: (1, 0, 0), angle: -90)]),
        (shape: Rectangle, emitter: (radiance: Scaled(6, Named("D65"))),
         to_world: [Scale((2, 2, 1)), Rotate(axis: (1, 0, 0), angle: 90), Translate((1, 6, 0))]),
    ],
    emitters: [Constant(radiance: Scaled(0.3, Named("D65")))],
)"""


def run(binary: str, scene_file: pathlib.Path, spp: int, out: str) -> tuple[float, float, float]:
    """(Msamples/s, wall seconds, peak RSS MiB) of one render."""
    cmd = [binary, "render", str(scene_file), "-o", out, "-q", "--spp", str(spp)]
    start = time.perf_counter()
    p = subprocess.Popen(cmd, stderr=subprocess.PIPE, stdout=subprocess.DEVNULL, text=True)
    err = p.stderr.read()
    _, status, ru = os.wait4(p.pid, 0)
    wall = time.perf_counter() - start
    p.returncode = os.waitstatus_to_exitcode(status)
    if p.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed:\n{err}")
    rate = float(re.search(r"\(([0-9.]+) Msamples/s", err).group(1))
    return rate, wall, ru.ru_maxrss / 1024


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--binary", default=str(ROOT / "target/release/prism"))
    ap.add_argument("--count", type=int, default=16)
    ap.add_argument("--triangles", type=int, default=100_000)
    ap.add_argument("--runs", type=int, default=4)
    ap.add_argument("--spp", type=int, default=16)
    args = ap.parse_args()
    mesh = ROOT / f"out/bench/mesh_{args.triangles}.ply"
    if not mesh.exists():
        subprocess.run(
            [sys.executable, str(ROOT / "tools/bench/make_mesh.py"), "--triangles", str(args.triangles), "-o", str(mesh)],
            check=True,
        )
    with tempfile.TemporaryDirectory() as tmp:
        files = {}
        for name, flatten in [("instanced", False), ("flattened", True)]:
            files[name] = pathlib.Path(tmp) / f"{name}.ron"
            files[name].write_text(scene(mesh, args.count, flatten))
        res: dict[str, list[tuple[float, float, float]]] = {"instanced": [], "flattened": []}
        for r in range(args.runs):
            for name in res:
                res[name].append(run(args.binary, files[name], args.spp, f"{tmp}/{name}{r}.exr"))
    print(f"{args.count} uses of a {args.triangles}-triangle mesh, 160x120, {args.spp} spp, {args.runs} runs each")
    for name, rs in res.items():
        rates = [x[0] for x in rs]
        se = statistics.stdev(rates) / len(rates) ** 0.5 if len(rates) > 1 else float("nan")
        print(
            f"  {name}: {statistics.mean(rates):.3f} ± {se:.3f} Msamples/s, "
            f"wall {statistics.mean(x[1] for x in rs):.2f} s, peak RSS {max(x[2] for x in rs):.0f} MiB"
        )
    ratios = [a[0] / b[0] for a, b in zip(res["instanced"], res["flattened"])]
    m = statistics.mean(ratios)
    if len(ratios) > 1:
        half = stats.t.ppf(0.975, len(ratios) - 1) * statistics.stdev(ratios) / len(ratios) ** 0.5
        print(f"  throughput instanced / flattened: {m:.3f} (95% CI {m - half:.3f} .. {m + half:.3f})")
    else:
        print(f"  throughput instanced / flattened: {m:.3f}")


if __name__ == "__main__":
    main()
