"""prism's `Principled` material against an independent numpy implementation of the glTF 2.0
metallic-roughness BRDF (glTF 2.0 specification, Appendix B "BRDF Implementation", with
KHR_materials_ior, KHR_materials_specular and KHR_materials_transmission's thin-walled BTDF),
written here from the specification's formulas:

    D   = α² χ⁺(N·H) / (π ((N·H)²(α² − 1) + 1)²),  α = roughness²
    V   = G / (4 |N·L| |N·V|),  G = G1(L) G1(V),  G1(X) = 2|N·X| χ⁺(H·X/N·X) / (|N·X| + √(α² + (1 − α²)(N·X)²))
    metal      = V D (f0 + (1 − f0)(1 − |V·H|)⁵),  f0 = baseColor
    dielectric = (1 − w·max(Fr)) · ((1 − T) baseColor/π + T baseColor V D(L mirrored)) + w Fr V D
    Fr         = f0d + (1 − f0d)(1 − |V·H|)⁵,  f0d = min(((ior − 1)/(ior + 1))² specularColor, 1)
    f          = (1 − metallic) dielectric + metallic metal

prism prints f·|N·L| through `prism probe-bsdf` for 400 random direction pairs per material
(reflection from above and below, and transmission); both sides are compared at 3 wavelengths
with a tabulated base colour. Tolerance: relative 2e-4 + absolute 1e-6 (prism evaluates in f32;
the reference in f64).
"""

from __future__ import annotations

import subprocess

import numpy as np
import pytest

MATERIALS = {
    "dielectric": dict(base=0.8, metallic=0.0, roughness=0.5, ior=1.5, specular=1.0, spec_color=1.0, transmission=0.0),
    "metal": dict(base=0.9, metallic=1.0, roughness=0.3, ior=1.5, specular=1.0, spec_color=1.0, transmission=0.0),
    "mixed": dict(base=0.6, metallic=0.4, roughness=0.8, ior=1.8, specular=0.6, spec_color=0.5, transmission=0.0),
    "glass": dict(base=0.9, metallic=0.1, roughness=0.35, ior=1.4, specular=0.8, spec_color=1.0, transmission=0.7),
    "smooth": dict(base=0.5, metallic=0.3, roughness=0.12, ior=1.5, specular=1.0, spec_color=1.0, transmission=0.2),
}
# A base colour that varies with wavelength: linear between (400 nm, 0.2) and (700 nm, 0.9).
TABULATED = "tabulated"
LAMBDAS = [450.0, 550.0, 650.0]


def base_at(m: dict, lam: float) -> float:
    if m["base"] == TABULATED:
        return 0.2 + 0.7 * (lam - 400.0) / 300.0
    return m["base"]


def scene_text() -> str:
    mats = []
    for name, m in {**MATERIALS, "tab": dict(MATERIALS["mixed"], base=TABULATED)}.items():
        base = "Tabulated([(400, 0.2), (700, 0.9)])" if m["base"] == TABULATED else f"Constant({m['base']})"
        mats.append(
            f'"{name}": Principled(base_color: {base}, metallic: {m["metallic"]}, roughness: {m["roughness"]}, '
            f'ior: {m["ior"]}, specular: {m["specular"]}, specular_color: Constant({m["spec_color"]}), '
            f'transmission: {m["transmission"]})'
        )
    return "(materials: {" + ", ".join(mats) + "}, shapes: [(shape: Rectangle)])"


def reference(m: dict, lam: float, wi: np.ndarray, wo: np.ndarray) -> np.ndarray:
    """f·|N·L| by the specification's formulas (V = wi, L = wo, N = +z)."""
    base = base_at(m, lam)
    a = m["roughness"] ** 2
    a2 = a * a
    # The material is the same from both sides: look from above.
    flip = wi[:, 2] < 0
    wi = np.where(flip[:, None], -wi, wi)
    wo = np.where(flip[:, None], -wo, wo)
    through = wo[:, 2] < 0
    # Thin-walled transmission: the BTDF is the BRDF at L mirrored through the surface.
    l = wo.copy()
    l[:, 2] = np.abs(wo[:, 2])
    h = wi + l
    h /= np.linalg.norm(h, axis=1)[:, None]
    nl, nv, nh = l[:, 2], wi[:, 2], h[:, 2]
    vh = np.abs(np.sum(wi * h, axis=1))
    hl = np.sum(h * l, axis=1)
    hv = np.sum(h * wi, axis=1)
    D = np.where(nh > 0, a2 / (np.pi * (nh * nh * (a2 - 1.0) + 1.0) ** 2), 0.0)

    def g1(nx, hx):
        return np.where(hx / nx > 0, 2 * np.abs(nx) / (np.abs(nx) + np.sqrt(a2 + (1 - a2) * nx * nx)), 0.0)

    Vis = g1(nl, hl) * g1(nv, hv) / (4 * np.abs(nl) * np.abs(nv))
    spec = Vis * D
    s5 = (1 - vh) ** 5
    metal = spec * (base + (1 - base) * s5)
    f0d = min(((m["ior"] - 1) / (m["ior"] + 1)) ** 2 * m["spec_color"], 1.0)
    fr = f0d + (1 - f0d) * s5  # specularColor is grey here, so max(Fr) = Fr
    w, t = m["specular"], m["transmission"]
    refl = (1 - w * fr) * (1 - t) * base / np.pi + w * fr * spec
    trans = (1 - w * fr) * t * base * spec
    diel = np.where(through, trans, refl)
    metal = np.where(through, 0.0, metal)
    f = (1 - m["metallic"]) * diel + m["metallic"] * metal
    return f * np.abs(nl)


def directions(rng: np.random.Generator, n: int) -> tuple[np.ndarray, np.ndarray]:
    def sphere(k):
        v = rng.normal(size=(k, 3))
        return v / np.linalg.norm(v, axis=1)[:, None]

    wi, wo = sphere(n), sphere(n)
    keep = (np.abs(wi[:, 2]) > 0.02) & (np.abs(wo[:, 2]) > 0.02)
    return wi[keep], wo[keep]


@pytest.mark.parametrize("name", [*MATERIALS, "tab"])
def test_principled_matches_spec(prism_bin, tmp_path, name):
    scene = tmp_path / "principled.ron"
    scene.write_text(scene_text())
    rng = np.random.default_rng([*MATERIALS, "tab"].index(name) + 1)
    wi, wo = directions(rng, 400)
    stdin = "\n".join(" ".join(f"{x:.9g}" for x in (*a, *b)) for a, b in zip(wi, wo))
    out = subprocess.run(
        [str(prism_bin), "probe-bsdf", str(scene), "--material", name, "--lambda", ",".join(map(str, LAMBDAS))],
        input=stdin, capture_output=True, text=True, check=True,
    ).stdout
    got = np.array([[float(x) for x in line.split()] for line in out.strip().splitlines()])
    assert got.shape == (len(wi), len(LAMBDAS) + 1)
    m = MATERIALS.get(name) or dict(MATERIALS["mixed"], base=TABULATED)
    for k, lam in enumerate(LAMBDAS):
        want = reference(m, lam, wi.copy(), wo.copy())
        err = np.abs(got[:, k] - want)
        tol = 2e-4 * np.abs(want) + 1e-6
        worst = int(np.argmax(err - tol))
        assert np.all(err <= tol), (
            f"{name} at {lam} nm: prism {got[worst, k]} vs spec {want[worst]} for wi {wi[worst]}, wo {wo[worst]}"
        )
    # Some pairs of each kind were compared, and the values are not all zero.
    assert np.sum(wi[:, 2] * wo[:, 2] < 0) > 50 and np.sum(wi[:, 2] * wo[:, 2] > 0) > 50
    assert np.count_nonzero(got[:, 0]) > 100
