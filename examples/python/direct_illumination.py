"""Direct illumination in numpy, from prism's parts (the course's third homework): at each
camera ray's first hit, one emitter sample and one BSDF sample, combined by the power
heuristic; plus the emitters the camera sees. It estimates what `prism render` gives with
`integrator: (max_depth: 2)`.

    python examples/python/direct_illumination.py scenes/cornell.ron 64

prints the image's mean Y and writes nothing. `estimate` returns the per-pixel mean and
standard error of X, Y, Z (tools/tests/test_python_examples.py compares them with prism's).
"""

from __future__ import annotations

import sys

import numpy as np
import prism


def power_heuristic(a, b):
    """w = a² / (a² + b²), 0 where both densities are 0."""
    a2, b2 = a * a, b * b
    s = a2 + b2
    return np.divide(a2, s, out=np.zeros_like(s), where=s > 0)


def camera_samples(scene, spp, rng):
    """spp camera rays per pixel (pixel-major), their wavelengths and lane weights 1/(N p).
    The lens samples make a thin-lens camera's depth of field (other cameras ignore them)."""
    w, h = scene.size
    ys, xs = np.mgrid[0:h, 0:w]
    pixel = np.repeat(np.stack([xs.ravel(), ys.ravel()], 1), spp, axis=0)
    m = len(pixel)
    o, d = scene.camera_rays(pixel, rng.random((m, 2)), u_lens=rng.random((m, 2)))
    lam, pdf = scene.sample_wavelengths(rng.random(m))
    weight = np.divide(1.0, lam.shape[1] * pdf, out=np.zeros_like(pdf), where=pdf > 0)
    return o, d, lam, weight


def emitter_sampling(scene, hits, lam, rng, mis=True):
    """Light from one emitter sample at each hit, weighted by MIS against BSDF sampling."""
    m = len(hits)
    es = scene.emitter_sample(hits, rng.random(m), rng.random((m, 2)), lam)
    f = scene.bsdf_eval(hits, es["wi"], lam)
    w = power_heuristic(es["pdf"], scene.bsdf_pdf(hits, es["wi"], lam)) if mis else np.ones(m)
    w = np.where(es["delta"], 1.0, w)
    inv = np.divide(w, es["pdf"], out=np.zeros(m, np.float32), where=es["pdf"] > 0)
    return f * es["radiance"] * inv[:, None]


def bsdf_sampling(scene, hits, lam, rng, mis=True):
    """One BSDF sample at each hit: (its throughput factor, the next hits, the light it finds
    on an emitter weighted by MIS against emitter sampling, whether it was specular)."""
    m = len(hits)
    bs = scene.bsdf_sample(hits, rng.random(m), rng.random((m, 2)), lam)
    nxt = scene.intersect_from(hits, bs["wo"])
    le = scene.emitter_eval(nxt, lam)
    w = power_heuristic(bs["pdf"], scene.emitter_pdf(nxt)) if mis else np.ones(m)
    w = np.where(bs["delta"], 1.0, w)
    return bs["weight"], nxt, bs["weight"] * le * w[:, None], bs


def to_image(scene, spp, radiance, lam, weight):
    """Per-pixel mean and standard error of X, Y, Z from each sample's lanes (the sensor's
    weights, as prism's film adds them)."""
    xyz = np.einsum("mn,mnc->mc", radiance * weight, prism.cie_xyz(lam))
    w, h = scene.size
    xyz = xyz.reshape(h, w, spp, 3).astype(np.float64)
    return xyz.mean(2), xyz.std(2, ddof=1) / np.sqrt(spp)


def estimate(scene, spp, seed=0, mis=True):
    rng = np.random.default_rng(seed)
    o, d, lam, weight = camera_samples(scene, spp, rng)
    hits = scene.intersect(o, d)
    radiance = scene.emitter_eval(hits, lam)  # emitters seen directly (depth 1)
    radiance += emitter_sampling(scene, hits, lam, rng, mis)
    radiance += bsdf_sampling(scene, hits, lam, rng, mis)[2]
    return to_image(scene, spp, radiance, lam, weight)


if __name__ == "__main__":
    scene = prism.load_file(sys.argv[1])
    mean, err = estimate(scene, int(sys.argv[2]) if len(sys.argv) > 2 else 16)
    print(f"mean Y {mean[..., 1].mean():.6f} ± {np.sqrt((err[..., 1] ** 2).sum()) / err[..., 1].size:.6f}")
