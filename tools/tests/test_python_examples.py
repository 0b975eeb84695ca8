"""The path tracer's parts from Python (python/src/parts.rs, bsdfs.rs, spectra.rs) and the two
estimators written with them (examples/python/): direct illumination against prism's render
at max depth 2, the path tracer against its full render, compared tile by tile."""

from __future__ import annotations

import pathlib
import sys

import numpy as np
import prism
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "examples" / "python"))
import direct_illumination  # noqa: E402
import path_tracer  # noqa: E402

CORNELL = (ROOT / "scenes" / "cornell.ron").read_text()


def cornell(max_depth=8, size=16):
    text = CORNELL.replace("film: (width: 256, height: 256", f"film: (width: {size}, height: {size}")
    text = text.replace("integrator: (max_depth: 8)", f"integrator: (max_depth: {max_depth})")
    text = text.replace("spectral: (wavelengths: 4),", 'spectral: (wavelengths: 4), aovs: ["stderr"],')
    return prism.load_string(text)


def tile_z(mean, err, y, y_err, k=4):
    """z of each k×k tile's mean Y: the difference over the two standard errors combined (each
    pixel's error from its own samples' spread; pixels independent)."""

    def tiles(a):
        h, w = a.shape
        return a.reshape(h // k, k, w // k, k).swapaxes(1, 2).reshape(h // k, w // k, k * k)

    n = k * k
    a, b = tiles(mean).mean(-1), tiles(y.astype(np.float64)).mean(-1)
    sa = np.sqrt((tiles(err) ** 2).sum(-1)) / n
    sb = np.sqrt((tiles(y_err.astype(np.float64)) ** 2).sum(-1)) / n
    return (a - b) / np.sqrt(sa**2 + sb**2)


# 16 tiles, two-sided: |z| < 4.5 has a false alarm rate of 1e-4 for the whole image under
# normality; the margin is for the light's edge pixels, whose samples are 0 or ~20.
Z_MAX = 4.5
SPP = 256


@pytest.mark.parametrize("example, depth", [(direct_illumination, 2), (path_tracer, 8)], ids=["direct", "path"])
def test_the_numpy_estimators_agree_with_prism(example, depth):
    """Tolerance: |z| < 4.5 per 4×4 tile of Y at 256 spp each (prism's standard error from its
    `stderr` layer). Without MIS weights (both strategies counted in full) the same estimator
    falls outside it, so the comparison can tell."""
    scene = cornell(max_depth=depth)
    r = prism.render(scene, spp=SPP, seed=1, threads=2, progress=False).channels
    mean, err = example.estimate(scene, SPP, seed=2)
    z = tile_z(mean[..., 1], err[..., 1], r["Y"], r["stderr.Y"])
    assert np.abs(z).max() < Z_MAX, np.round(z, 2)
    wrong, wrong_err = example.estimate(scene, SPP, seed=2, mis=False)
    z = tile_z(wrong[..., 1], wrong_err[..., 1], r["Y"], r["stderr.Y"])
    assert np.abs(z).max() > Z_MAX, np.round(z, 2)


def test_intersect_finds_the_walls():
    """Tolerance: 1e-5 (float32 rounding of a unit-size scene). Rays from (0, 0.5, 0), above
    both boxes: along −z the back wall at z = −1, along −x the red wall (material "red", index
    1 in name order: green, red, white), up the light at y = 0.99 (its emitter 0), out of the
    open front a miss."""
    scene = cornell()
    o = np.tile([0, 0.5, 0], (4, 1))
    d = np.array([[0, 0, -1], [-2, 0, 0], [0, 1, 0], [0, 0, 1]], np.float32)
    h = scene.intersect(o, d)
    assert list(h.valid) == [True, True, True, False]
    np.testing.assert_allclose(h.t[:3], [1, 1, 0.49], atol=1e-5)
    assert h.t[3] == np.inf
    np.testing.assert_allclose(h.p[0], [0, 0.5, -1], atol=1e-5)
    np.testing.assert_allclose(h.n[0], [0, 0, 1], atol=1e-5)
    np.testing.assert_allclose(h.d[1], [-1, 0, 0])
    assert list(h.material) == [2, 1, 2, -1]
    assert list(h.emitter) == [-1, -1, 0, -1]
    assert h.shape[3] == -1
    assert h.uv.shape == (4, 2) and h.ns.shape == (4, 3)
    with pytest.raises(prism.SceneError, match=r"d must be an \(M, 3\) array, got shape \[4, 2\]"):
        scene.intersect(o, d[:, :2])
    with pytest.raises(prism.SceneError, match="d has 3 rows, but there are 4 rays"):
        scene.intersect(o, d[:3])


def test_diffuse_bsdf_and_light_from_python():
    """Tolerance: 1e-5 relative (float32). At the back wall (white, diffuse) seen head on:
    bsdf_eval = R(λ) cos θ / π with R from prism.spectrum of the scene's RGB, bsdf_pdf =
    cos θ / π, a sample's weight R(λ); the light's radiance from emitter_eval equals
    prism.spectrum of its RGB as an emission; 3 wavelengths per ray are refused."""
    scene = cornell()
    m = 8
    u = (np.arange(m) + 0.5) / m
    lam, pdf = scene.sample_wavelengths(u)
    assert lam.shape == pdf.shape == (m, 4) and (pdf > 0).all()
    o = np.tile([0, 0.5, 0], (m, 1))
    h = scene.intersect(o, np.tile([0, 0, -1.0], (m, 1)))
    wo = np.tile([0, 0.6, 0.8], (m, 1))
    white = prism.spectrum({"Rgb": [0.885809, 0.698859, 0.666422]}, lam)
    np.testing.assert_allclose(scene.bsdf_eval(h, wo, lam), white * 0.8 / np.pi, rtol=1e-5)
    np.testing.assert_allclose(scene.bsdf_pdf(h, wo, lam), np.full(m, 0.8 / np.pi), rtol=1e-5)
    s = scene.bsdf_sample(h, u, np.stack([u, u[::-1]], 1), lam)
    assert s["valid"].all() and not s["delta"].any()
    np.testing.assert_allclose(s["weight"], white, rtol=1e-5)
    np.testing.assert_allclose(np.linalg.norm(s["wo"], axis=1), 1, rtol=1e-5)
    up = scene.intersect(o, np.tile([0, 1.0, 0], (m, 1)))
    light = prism.spectrum({"Rgb": [18.387, 13.9873, 6.75357]}, lam, role="emission")
    np.testing.assert_allclose(scene.emitter_eval(up, lam), light, rtol=1e-5)
    with pytest.raises(prism.SceneError, match="3 wavelengths per ray is not supported"):
        scene.bsdf_eval(h, wo, lam[:, :3])


def test_wavelengths_spectra_and_streams():
    """Tolerance: none for what is computed the same way twice; 1e-6 for a constant. The
    module-level sampler with the scene's settings draws the scene's wavelengths; spectra take
    every RON form and refuse bad ones with the loader's message; the sampler's streams are
    the same numbers for the same (seed, pixel, sample) and others for another seed."""
    scene = cornell()
    u = np.linspace(0, 0.999, 50)
    a, pa = scene.sample_wavelengths(u)
    b, pb = prism.sample_wavelengths(u, lanes=4, range=(360, 830), sampling="Visible")
    np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(pa, pb)
    assert ((a >= 360) & (a <= 830)).all()
    np.testing.assert_allclose(prism.spectrum(0.25, a), 0.25, rtol=1e-6)
    assert prism.spectrum({"Blackbody": 5000}, a, role="emission").shape == a.shape
    assert prism.spectrum({"Named": "D65"}, np.array([560.0]), role="emission")[0] > 0
    with pytest.raises(prism.SceneError, match="a reflectance must lie in \\[0, 1\\]"):
        prism.spectrum(2.0, a)
    with pytest.raises(prism.SceneError, match="unknown variant `Rbg`"):
        prism.spectrum({"Rbg": [1, 0, 0]}, a)
    with pytest.raises(prism.SceneError, match='unknown sampling "Sideways"'):
        prism.sample_wavelengths(u, sampling="Sideways")
    s1 = prism.sampler_stream([0, 1, 2], [0, 0, 5], start=4, count=8, seed=7)
    s2 = prism.sampler_stream([0, 1, 2], [0, 0, 5], start=4, count=8, seed=7)
    s3 = prism.sampler_stream([0, 1, 2], [0, 0, 5], start=4, count=8, seed=8)
    assert s1.shape == (3, 8) and ((s1 >= 0) & (s1 < 1)).all()
    np.testing.assert_array_equal(s1, s2)
    assert not np.array_equal(s1, s3)
    sobol = prism.sampler_stream([3] * 64, list(range(64)), count=2, kind="Sobol", seed=1)
    # Owen-scrambled Sobol: the first 64 points put one in each of 64 cells of 1/64 in x.
    assert sorted((sobol[:, 0] * 64).astype(int)) == list(range(64))


def test_bad_arrays_raise_and_never_crash():
    """Each mistake raises SceneError naming the argument: hits of another scene, uniforms
    outside [0, 1], wavelengths that are not positive nm, a non-finite pixel; a ray of NaN or
    zero direction misses instead of reaching the accelerator."""
    scene, other = cornell(), cornell()
    o = np.tile([0, 0.5, 0], (2, 1))
    h = scene.intersect(o, np.array([[0, 0, -1], [0, 1, 0]], np.float32))
    lam, _ = scene.sample_wavelengths(np.array([0.1, 0.6]))
    wo = np.tile([0, 0.6, 0.8], (2, 1))
    with pytest.raises(prism.SceneError, match="traced in another scene"):
        other.bsdf_eval(h, wo, lam)
    with pytest.raises(prism.SceneError, match="traced in another scene"):
        other.intersect_from(h, wo)
    with pytest.raises(prism.SceneError, match=r"u_lobe holds 1.5; uniform numbers must lie in \[0, 1\]"):
        scene.bsdf_sample(h, np.array([1.5, 0.2]), np.full((2, 2), 0.5), lam)
    with pytest.raises(prism.SceneError, match="u holds NaN"):
        scene.emitter_sample(h, np.array([0.1, 0.2]), np.array([[np.nan, 0], [0, 0]]), lam)
    with pytest.raises(prism.SceneError, match="wavelengths holds -5; wavelengths are in nm"):
        scene.bsdf_eval(h, wo, np.where(lam > 0, -5.0, lam))
    with pytest.raises(prism.SceneError, match="pixel holds"):
        scene.camera_rays(np.array([[np.nan, 0]]), np.full((1, 2), 0.5))
    miss = scene.intersect(np.array([[np.nan, 0, 0], [0, 0.5, 0]]), np.array([[0, 0, -1], [0, 0, 0]]))
    assert list(miss.valid) == [False, False]
    assert list(scene.intersect_from(h, np.zeros((2, 3))).valid) == [False, False]
