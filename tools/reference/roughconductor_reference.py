"""Mitsuba 3.9.1 `roughconductor` BSDF values pinned by tests/bsdf.rs (rough_conductor_matches_mitsuba).

    tools/.venv/bin/python tools/reference/roughconductor_reference.py   # needs mitsuba==3.9.1

Prints `eval` (f·cos θo) at λ = 450, 550, 650, 700 nm and `pdf` of Mitsuba's scalar_spectral
roughconductor for wi ∝ (0.3, −0.2, 0.9), wo ∝ (−0.5, 0.1, 0.7) (local shading frame), with
Mitsuba's own measured metal data (`material`: its data/ior/<name>.spd tables) and its default
distribution (Beckmann) unless one is named; sample_visible is Mitsuba's default (true), so the
pdf is that of visible-normal sampling, as prism's.
"""

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_spectral")

CASES = [
    ('RoughConductor(material: "Au", alpha: 0.3)', {"material": "Au", "alpha": 0.3}),
    (
        'RoughConductor(material: "Cu", distribution: Ggx, alpha_u: 0.2, alpha_v: 0.5)',
        {"material": "Cu", "distribution": "ggx", "alpha_u": 0.2, "alpha_v": 0.5},
    ),
    ('RoughConductor(material: "Cr", distribution: Ggx, alpha: 0.4)', {"material": "Cr", "distribution": "ggx", "alpha": 0.4}),
]


def unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


def main() -> None:
    si = mi.SurfaceInteraction3f()
    si.wavelengths = [450, 550, 650, 700]
    si.wi = mi.Vector3f(*unit([0.3, -0.2, 0.9]))
    wo = mi.Vector3f(*unit([-0.5, 0.1, 0.7]))
    ctx = mi.BSDFContext()
    for prism_cfg, params in CASES:
        bsdf = mi.load_dict({"type": "roughconductor", **params})
        f = bsdf.eval(ctx, si, wo)
        pdf = bsdf.pdf(ctx, si, wo)
        values = ", ".join(f"{float(f[i]):.6f}" for i in range(4))
        print(f"{prism_cfg}: [{values}], pdf {float(pdf):.8f}")


if __name__ == "__main__":
    main()
