"""A path tracer in numpy, from prism's parts: at every vertex emitter sampling and BSDF
sampling combined by the power heuristic, Russian roulette from the scene's `rr_depth` on,
up to its `max_depth`: the estimator `prism render` runs, written out in Python.

    python examples/python/path_tracer.py scenes/cornell.ron 16

prints the image's mean Y. `estimate` returns the per-pixel mean and standard error of X, Y,
Z (tools/tests/test_python_examples.py compares them with prism's full render).
"""

from __future__ import annotations

import pathlib
import sys

import numpy as np
import prism

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from direct_illumination import bsdf_sampling, camera_samples, emitter_sampling, to_image  # noqa: E402


def estimate(scene, spp, seed=0, roulette=True, mis=True):
    integrator = scene.config["integrator"]
    max_depth = integrator["max_depth"] if integrator["max_depth"] >= 0 else 1 << 20
    rr_depth = integrator["rr_depth"]
    rng = np.random.default_rng(seed)
    o, d, lam, weight = camera_samples(scene, spp, rng)
    hits = scene.intersect(o, d)
    radiance = scene.emitter_eval(hits, lam) if max_depth >= 1 else np.zeros_like(lam)
    beta = np.ones_like(lam)  # throughput of each path; 0 once it has ended
    eta = np.ones(len(hits), np.float32)  # IOR ratio crossed, which roulette undoes
    depth = 1
    while depth < max_depth and beta.any():
        radiance += beta * emitter_sampling(scene, hits, lam, rng, mis)
        factor, hits, found, bs = bsdf_sampling(scene, hits, lam, rng, mis)
        radiance += beta * found
        beta = beta * factor * bs["valid"][:, None]
        eta *= np.where(bs["valid"], bs["eta"], 1.0)
        if roulette and depth >= rr_depth:
            q = np.minimum(beta.max(1) * eta * eta, 0.95)
            survive = rng.random(len(q)) < q
            beta = np.where(survive[:, None], beta / np.where(q > 0, q, 1)[:, None], 0.0)
        depth += 1
    return to_image(scene, spp, radiance, lam, weight)


if __name__ == "__main__":
    scene = prism.load_file(sys.argv[1])
    mean, err = estimate(scene, int(sys.argv[2]) if len(sys.argv) > 2 else 16)
    print(f"mean Y {mean[..., 1].mean():.6f} ± {np.sqrt((err[..., 1] ** 2).sum()) / err[..., 1].size:.6f}")
