"""Mitsuba 3.9.1 `roughplastic` BSDF values pinned by tests/bsdf.rs (rough_plastic_matches_mitsuba).

    python tools/reference/roughplastic_reference.py   # needs mitsuba==3.9.1

Prints f·cos θo (`eval`) of Mitsuba's scalar_spectral roughplastic (GGX, alpha 0.2, default
indices 1.49 / 1.000277, diffuse 0.5, specular 0 or 1) at 550 nm for incident angles 0°, 40°,
70° (in the xz plane) and outgoing angles 0°, 30°, 60°, 80° (azimuth atan2(0.8, −0.6)).
"""

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_spectral")
si = mi.SurfaceInteraction3f()
si.wavelengths = [550, 550, 550, 550]
ctx = mi.BSDFContext()
for spec in [0.0, 1.0]:
    bsdf = mi.load_dict({
        "type": "roughplastic", "distribution": "ggx", "alpha": 0.2,
        "diffuse_reflectance": {"type": "uniform", "value": 0.5},
        "specular_reflectance": {"type": "uniform", "value": spec},
    })
    for ti in [0, 40, 70]:
        si.wi = mi.Vector3f(np.sin(np.radians(ti)), 0, np.cos(np.radians(ti)))
        row = []
        for to in [0, 30, 60, 80]:
            s = np.sin(np.radians(to))
            wo = mi.Vector3f(-0.6 * s, 0.8 * s, np.cos(np.radians(to)))
            row.append(round(float(bsdf.eval(ctx, si, wo)[0]), 6))
        print(f"({spec}, {ti}, {row}),")
