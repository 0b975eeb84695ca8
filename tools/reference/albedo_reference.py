"""Directional albedos of Mitsuba 3.9.1 BSDFs, pinned by tests/bsdf.rs (albedos_match_mitsuba).

    tools/.venv/bin/python tools/reference/albedo_reference.py   # needs mitsuba==3.9.1, ~1 min

The albedo a(θi) = E[weight] of `bsdf.sample` (scalar_spectral, 550 nm) with 200 000 independent
uniform samples (numpy PCG64, seed 19), printed with its standard error, for wi = (0.8 sin θ, 0.6 sin θ,
cos θ) as tests/bsdf.rs's `dir`. Mitsuba's roughconductor without a `material` is a perfect
mirror in F (η = 0, k = 1), prism's default too, so these are its microfacet model's energy
loss alone (single scattering: light that would bounce between facets or leave below the
horizon is lost). roughplastic: default indices 1.49 / 1.000277, diffuse 0.5, nonlinear false.
"""

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_spectral")

N = 200_000
ANGLES = [0.0, 60.0, 80.0]


def configs():
    for dist, name in [("beckmann", "Beckmann"), ("ggx", "Ggx")]:
        for alpha in [0.05, 0.2, 0.6]:
            yield (
                f"RoughConductor(distribution: {name}, alpha: {alpha})",
                {"type": "roughconductor", "distribution": dist, "alpha": alpha},
            )
    for alpha in [0.1, 0.4]:
        yield (
            f"RoughPlastic(distribution: Ggx, alpha: {alpha}, diffuse_reflectance: Constant(0.5))",
            {
                "type": "roughplastic",
                "distribution": "ggx",
                "alpha": alpha,
                "diffuse_reflectance": {"type": "uniform", "value": 0.5},
            },
        )


def albedo(bsdf, theta: float, rng: np.random.Generator) -> tuple[float, float]:
    t = np.radians(theta)
    si = mi.SurfaceInteraction3f()
    si.wavelengths = [550.0] * 4
    si.wi = mi.Vector3f(0.8 * np.sin(t), 0.6 * np.sin(t), np.cos(t))
    ctx = mi.BSDFContext()
    u = rng.random((N, 3))
    w = np.empty(N)
    for i in range(N):
        _, weight = bsdf.sample(ctx, si, float(u[i, 0]), mi.Point2f(float(u[i, 1]), float(u[i, 2])))
        w[i] = float(weight[0])
    return float(w.mean()), float(w.std(ddof=1) / np.sqrt(N))


def main() -> None:
    rng = np.random.default_rng(19)
    for cfg, params in configs():
        bsdf = mi.load_dict(params)
        vals = [albedo(bsdf, th, rng) for th in ANGLES]
        body = ", ".join(f"({th:.0f}.0, {a:.5f}, {se:.5f})" for th, (a, se) in zip(ANGLES, vals))
        print(f'("{cfg}", [{body}]),'.replace('"R', 'r#"R').replace(')", [', ')"#, ['))


if __name__ == "__main__":
    main()
