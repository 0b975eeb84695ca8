#!/usr/bin/env python3
"""Make the Mitsuba 3 reference values for prism's spot, directional and envmap emitters.

Every number comes from Mitsuba 3.9.1's own emitter plugins in the scalar_spectral variant,
queried through its Python API (`eval`, `sample_direction`) at chosen directions, points and
wavelengths; nothing is rendered, so the values carry no Monte Carlo noise.

Writes two files, used by `tests/emitters_mitsuba.rs`:

`tests/data/envmap_grey_16x8.exr`
    A 16x8 latitude-longitude map of random greys (float32 RGB, seeded). Grey
    texels isolate geometry from colour: Mitsuba uplifts a texel rgb as
    scale = 2·max(rgb) times the sigmoid of rgb/scale, so every grey texel has
    the same sigmoid (that of 0.5 grey) and differs only in its scale. Mitsuba's
    envmap interpolates the sigmoid values and the scales bilinearly, each on
    its own, so for a grey map

        eval(map, d) / eval(white map, d) = (bilinear interpolation of the texel values)(d)

    exactly, whichever RGB-to-spectrum table is used. That ratio is what the
    JSON records: it pins down which direction maps to which pixel, where texel
    centres lie and how they are interpolated (Mitsuba's rows are vertex-centred
    in θ: row j sits at θ = π j / (H − 1); columns are texel-centred in φ).

`tests/data/emitters_mitsuba.json`
    - envmap: unit directions (world space, pointing from the scene towards the
      sky) and the ratio above at each, for to_world = identity and for a
      rotation (given as axis and angle in degrees, as prism's `Rotate`).
    - envmap "uplift": eval() of uniform maps of a few linear RGB colours, with
      scale 2, at wavelengths 360-830 nm: the absolute radiance, which pins down
      the illuminant uplift (2·max(rgb) times the Jakob-Hanika sigmoid of
      rgb / (2·max(rgb)), times D65 at unit luminance) and the `scale` factor.
    - spot: for a spot at height h looking straight down, the falloff factor
      L·r²/I at angles θ from its axis, for Mitsuba's defaults (cutoff 20°,
      beam width 15°) and for cutoff 30°, beam width 20°; and the default
      intensity (D65) as L·r² on the axis, at the same wavelengths.
    - directional: the direction sample_direction() returns (towards the light)
      and its weight (the irradiance), for a light given by `direction` with the
      default irradiance (D65), at the same wavelengths, and for one given by a
      `to_world` look-at with a uniform irradiance.

Usage (from the repository root)::

    tools/.venv/bin/python tools/reference/emitters_reference.py

(or any Python with the pinned mitsuba==3.9.1, numpy and OpenImageIO of
tools/requirements.txt).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import mitsuba as mi
import numpy as np
import OpenImageIO as oiio

REPO_ROOT = Path(__file__).resolve().parents[2]
EXR = REPO_ROOT / "tests/data/envmap_grey_16x8.exr"
JSON = REPO_ROOT / "tests/data/emitters_mitsuba.json"
WIDTH, HEIGHT = 16, 8
ROTATION = {"axis": [1.0, 2.0, 0.5], "angle": 35.0}
WAVELENGTH = 550.0
WAVELENGTHS = [float(w) for w in range(360, 831, 10)]
# Linear sRGB colours for the uplift check: grey, saturated primaries, an orange brighter than 1.
COLOURS = [[1.0, 1.0, 1.0], [0.8, 0.1, 0.1], [0.05, 0.1, 0.4], [0.2, 0.9, 0.3], [3.0, 1.5, 0.2]]
UPLIFT_SCALE = 2.0
UPLIFT_DIRECTION = [0.3, 0.5, -0.8]
DIRECTIONAL_DIRECTION = [0.3, -1.0, 0.2]
DIRECTIONAL_TARGET = [0.6, -0.64, -0.48]
DIRECTIONAL_IRRADIANCE = 2.5


def write_exr(path: Path, pixels: np.ndarray) -> None:
    out = oiio.ImageOutput.create(str(path))
    spec = oiio.ImageSpec(pixels.shape[1], pixels.shape[0], 3, oiio.FLOAT)
    spec.attribute("compression", "zip")
    if not out.open(str(path), spec):
        raise RuntimeError(oiio.geterror())
    out.write_image(np.ascontiguousarray(pixels, dtype=np.float32))
    out.close()


def directions(rng: np.random.Generator, count: int) -> np.ndarray:
    """Random unit vectors, plus a few on the seam (−z), near the poles and on the horizon."""
    v = rng.normal(size=(count, 3))
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    extra = np.array(
        [
            [0.0, 0.0, -1.0],
            [1e-3, 0.0, -1.0],
            [-1e-3, 0.0, -1.0],
            [0.05, 0.998, 0.02],
            [-0.03, -0.999, 0.01],
            [1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0],
        ]
    )
    extra /= np.linalg.norm(extra, axis=1, keepdims=True)
    return np.concatenate([v, extra])


def envmap_ratios(dirs: np.ndarray, to_world) -> list[float]:
    def emitter(filename: str):
        d = {"type": "envmap", "filename": filename}
        if to_world is not None:
            d["to_world"] = to_world
        return mi.load_dict(d)

    grey = emitter(str(EXR))
    white_path = EXR.with_name("_white_tmp.exr")
    write_exr(white_path, np.ones((HEIGHT, WIDTH, 3)))
    white = emitter(str(white_path))
    white_path.unlink()
    out = []
    for d in dirs:
        si = mi.SurfaceInteraction3f()
        si.wi = mi.Vector3f(-d)  # eval looks up the direction −wi
        si.wavelengths = [WAVELENGTH] * 4
        out.append(float(grey.eval(si)[0]) / float(white.eval(si)[0]))
    return out


def spot_falloff(cutoff: float | None, beam: float | None, angles: list[float]) -> list[float]:
    h, intensity = 2.0, 3.0
    d = {
        "type": "spot",
        "intensity": {"type": "uniform", "value": intensity},
        "to_world": mi.ScalarTransform4f().look_at(origin=[0, h, 0], target=[0, 0, 0], up=[0, 0, 1]),
    }
    if cutoff is not None:
        d["cutoff_angle"] = cutoff
    if beam is not None:
        d["beam_width"] = beam
    em = mi.load_dict(d)
    out = []
    for deg in angles:
        x = h * math.tan(math.radians(deg))
        it = mi.Interaction3f()
        it.p = mi.Point3f(x, 0.0, 0.0)
        it.wavelengths = [WAVELENGTH] * 4
        _, weight = em.sample_direction(it, [0.5, 0.5])
        out.append(float(weight[0]) * (h * h + x * x) / intensity)
    return out


def per_wavelength(f) -> list[float]:
    """f(wavelength) for each of WAVELENGTHS (Mitsuba evaluates 4 lanes; all get the same one)."""
    return [f(w) for w in WAVELENGTHS]


def envmap_uplift(rgb: list[float]) -> list[float]:
    path = EXR.with_name("_uplift_tmp.exr")
    write_exr(path, np.tile(np.array(rgb), (4, 8, 1)))
    em = mi.load_dict({"type": "envmap", "filename": str(path), "scale": UPLIFT_SCALE})
    path.unlink()
    d = np.array(UPLIFT_DIRECTION) / np.linalg.norm(UPLIFT_DIRECTION)

    def at(w: float) -> float:
        si = mi.SurfaceInteraction3f()
        si.wi = mi.Vector3f(-d)
        si.wavelengths = [w] * 4
        return float(em.eval(si)[0])

    return per_wavelength(at)


def spot_default_intensity() -> list[float]:
    h = 2.0
    em = mi.load_dict(
        {"type": "spot", "to_world": mi.ScalarTransform4f().look_at(origin=[0, h, 0], target=[0, 0, 0], up=[0, 0, 1])}
    )

    def at(w: float) -> float:
        it = mi.Interaction3f()
        it.p = mi.Point3f(0.0, 0.0, 0.0)
        it.wavelengths = [w] * 4
        _, weight = em.sample_direction(it, [0.5, 0.5])
        return float(weight[0]) * h * h

    return per_wavelength(at)


def directional(d: dict) -> dict:
    em = mi.load_dict(d)
    it = mi.Interaction3f()
    it.p = mi.Point3f(0.3, 0.1, -0.2)
    it.wavelengths = [WAVELENGTH] * 4
    ds, _ = em.sample_direction(it, [0.5, 0.5])
    assert ds.delta and ds.pdf == 1.0

    def at(w: float) -> float:
        it.wavelengths = [w] * 4
        return float(em.sample_direction(it, [0.5, 0.5])[1][0])

    return {"to_light": [float(c) for c in ds.d], "irradiance": per_wavelength(at)}


def main() -> None:
    mi.set_variant("scalar_spectral")
    rng = np.random.default_rng(20240611)
    write_exr(EXR, np.repeat(rng.uniform(0.05, 2.0, size=(HEIGHT, WIDTH, 1)), 3, axis=2))
    dirs = directions(rng, 96)
    # Mitsuba's Python `rotate` does not normalise its axis (prism's `Rotate` does).
    axis = np.array(ROTATION["axis"]) / np.linalg.norm(ROTATION["axis"])
    rot = mi.ScalarTransform4f().rotate(axis=axis.tolist(), angle=ROTATION["angle"])
    angles = [0.0, 5.0, 14.9, 15.5, 17.5, 19.0, 19.9, 20.5, 22.0, 25.0, 28.0, 29.5, 31.0, 45.0]
    result = {
        "description": (
            "Mitsuba 3.9.1 scalar_spectral references for prism's emitters, made by "
            "tools/reference/emitters_reference.py. envmap: ratio of eval() on "
            "tests/data/envmap_grey_16x8.exr to eval() on a white map of the same size, at "
            f"{WAVELENGTH} nm, for world directions d (from the scene towards the sky); "
            "'rotated' uses to_world = Rotate(axis, angle in degrees). spot: L·r²/I at angle θ "
            "(degrees) from the axis of a spot at height 2 looking down; default_intensity: L·r² on "
            "its axis at 'wavelengths'. envmap.uplift: eval() of uniform maps of 'colours' with "
            "'scale' at 'wavelengths'. directional: sample_direction()'s direction (towards the "
            "light) and weight (irradiance) at 'wavelengths'."
        ),
        "mitsuba": mi.__version__,
        "wavelengths": WAVELENGTHS,
        "envmap": {
            "file": "envmap_grey_16x8.exr",
            "directions": [[float(c) for c in d] for d in dirs],
            "identity": envmap_ratios(dirs, None),
            "rotation": ROTATION,
            "rotated": envmap_ratios(dirs, rot),
            "uplift": {
                "scale": UPLIFT_SCALE,
                "direction": UPLIFT_DIRECTION,
                "colours": COLOURS,
                "values": [envmap_uplift(c) for c in COLOURS],
            },
        },
        "spot": {
            "angles": angles,
            "default": {"cutoff_angle": 20.0, "beam_width": 15.0, "falloff": spot_falloff(None, None, angles)},
            "custom": {"cutoff_angle": 30.0, "beam_width": 20.0, "falloff": spot_falloff(30.0, 20.0, angles)},
            "default_intensity": spot_default_intensity(),
        },
        "directional": {
            "direction": {
                "direction": DIRECTIONAL_DIRECTION,
                **directional({"type": "directional", "direction": DIRECTIONAL_DIRECTION}),
            },
            "to_world": {
                "look_at_target": DIRECTIONAL_TARGET,
                "irradiance_value": DIRECTIONAL_IRRADIANCE,
                **directional(
                    {
                        "type": "directional",
                        "irradiance": {"type": "uniform", "value": DIRECTIONAL_IRRADIANCE},
                        "to_world": mi.ScalarTransform4f().look_at(
                            origin=[0, 0, 0], target=DIRECTIONAL_TARGET, up=[0, 1, 0]
                        ),
                    }
                ),
            },
        },
    }
    JSON.write_text(json.dumps(result, indent=1) + "\n")
    print(f"wrote {EXR.relative_to(REPO_ROOT)} and {JSON.relative_to(REPO_ROOT)}")


if __name__ == "__main__":
    main()
