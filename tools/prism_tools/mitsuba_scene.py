"""prism's exported scene (`prism export SCENE.ron -o DIR` → DIR/scene.json) as a Mitsuba 3 scene
dictionary at matched settings, for Mitsuba's spectral variants.

The export is the one source of truth: the world-space PLY meshes (rectangles and cubes
included), camera, pixel filter, integrator and prism's own tabulation of every spectrum
(as Mitsuba `irregular` spectra, so an RGB value is uplifted once, by prism). Mitsuba's film is an
`hdrfilm` with linear sRGB output, which is what prism's R, G, B channels hold, or (`convert(...,
spectral_film=True)`) a `specfilm` with one response curve per sensor channel (bands, filters,
camera RGB).

What Mitsuba cannot render the same way raises `Unsupported` (`Dispersive` for a
wavelength-dependent index of refraction), naming the part of the scene.

Conventions, checked by tools/tests/test_mitsuba_scene.py or by the scene comparisons:
- twosided: the first child is the front BSDF, the second the back one; blendbsdf: weight 0 is
  the first child. Children are keyed so that sorting the keys keeps that order either way.
- Meshes without normals get `face_normals` (Mitsuba would otherwise smooth them); prism bakes
  flip_normals into the exported meshes.
- The camera's field of view is along x (prism exports the x extent whatever fov_axis it had).
- The film samples a border around the image: prism's filter importance sampling reaches past
  the image edges, as Mitsuba does only with `sample_border`.
- Scalar checkerboards swap their values (Mitsuba's `eval_1` has the squares the other way
  round from its spectral `eval`, which prism follows); scalar bitmaps are the image's luminance,
  made by Mitsuba's own conversion.
- Colours: see `y_normalization_correction`.
"""

from __future__ import annotations

import functools
import json
import pathlib
from typing import Any

import mitsuba as mi
import numpy as np

#: Mitsuba's spectral variants integrate the CIE observer over this range (nm).
MITSUBA_RANGE = (360.0, 830.0)


class Unsupported(ValueError):
    """The scene uses something Mitsuba cannot render the same way."""


class Dispersive(Unsupported):
    """A wavelength-dependent index of refraction: Mitsuba's dielectrics take a single number."""


def load(path: str | pathlib.Path) -> dict[str, Any]:
    """The exported scene: DIR/scene.json (or DIR itself)."""
    path = pathlib.Path(path)
    if path.is_dir():
        path = path / "scene.json"
    scene = json.loads(path.read_text())
    if scene.get("format") != "prism-scene" or scene.get("version") != 1:
        raise Unsupported(f"{path}: not a version 1 prism scene export")
    return scene


@functools.cache
def y_normalization_correction() -> float:
    """Puts Mitsuba's colours on prism's (and colour-science's) scale, where a spectrum that is 1
    everywhere has Y = 1. Mitsuba divides by a constant, 1 / MI_CIE_Y_NORMALIZATION = 106.750,
    that is 0.1% smaller than the integral of its own ȳ over 360–830 nm (106.857), so its Y of
    that spectrum is 1.001. The factor is that ratio's inverse, from Mitsuba's own ȳ (piecewise
    linear between whole nanometres, so the trapezoid rule on a 0.25 nm grid is exact)."""
    nm = np.linspace(360.0, 830.0, 4 * 470 + 1)
    ybar = np.array([float(np.asarray(mi.cie1931_y(float(w))).ravel()[0]) for w in nm])
    return 1.0 / (np.trapezoid(ybar, nm) * mi.MI_CIE_Y_NORMALIZATION)


def _transform(rows: list[list[float]]) -> "mi.ScalarTransform4f":
    """A 4×4 row-major matrix as prism exports it."""
    return mi.ScalarTransform4f(mi.ScalarMatrix4f(rows))


def _to_uv(t: dict[str, Any]) -> "mi.ScalarTransform4f":
    # prism: texture uv = surface uv · uv_scale + uv_offset.
    (su, sv), (ou, ov) = t["uv_scale"], t["uv_offset"]
    return _transform([[su, 0, 0, ou], [0, sv, 0, ov], [0, 0, 1, 0], [0, 0, 0, 1]])


def spectrum(s: dict[str, Any]) -> dict[str, Any]:
    if s["type"] == "constant":
        return {"type": "uniform", "value": float(s["value"])}
    if s["type"] == "irregular":
        return {
            "type": "irregular",
            "wavelengths": ", ".join(repr(float(w)) for w in s["wavelengths"]),
            "values": ", ".join(repr(float(v)) for v in s["values"]),
        }
    raise Unsupported(f"spectrum type {s['type']!r}")


def _bitmap(t: dict[str, Any], scalar: bool = False) -> dict[str, Any]:
    if not t.get("filename"):
        raise Unsupported("a bitmap texture without a file (generated in memory)")
    d = {"type": "bitmap", "raw": bool(t["raw"]), "filter_type": t["filter"], "wrap_mode": t["wrap"], "to_uv": _to_uv(t)}
    if not scalar:
        d["filename"] = str(t["filename"])
        return d
    # A scalar texture is the image's luminance (prism, and Mitsuba's RGB variants). Mitsuba's
    # spectral variants cannot look up a scalar in a colour image, so Mitsuba's own conversion
    # (sRGB decoding unless raw, then luminance) makes a one-channel linear image for it.
    image = mi.Bitmap(str(t["filename"]))
    if t["raw"]:
        image.set_srgb_gamma(False)
    y = image.convert(mi.Bitmap.PixelFormat.Y, mi.Struct.Type.Float32, srgb_gamma=False)
    texels = np.array(y, dtype=np.float32)
    d.update(data=mi.TensorXf(texels.reshape(texels.shape[0], texels.shape[1], 1)), raw=True)
    return d


def _emission_bitmap(t: dict[str, Any]) -> dict[str, Any]:
    """A textured area light's radiance. Mitsuba 3.9's spectral variants uplift a bitmap's texels
    as bounded reflectances (RGB clamped to [0, 1]) and do not multiply an area light's bitmap by
    D65 themselves, so it goes inside a `d65` spectrum (which takes a nested texture and a
    scale). prism's illuminant uplift of the same RGB times D65 has the same colour, so an image
    in [0, 1] times a grey factor renders alike; other cases cannot be written for Mitsuba. The
    scale is undone by `y_normalization_correction`, as for environment maps."""
    f = [float(x) for x in t["factor"]]
    if max(f) - min(f) > 1e-6 * max(f):
        raise Unsupported(f"a textured area light times the coloured factor {f} (Mitsuba's d65 scale is grey)")
    image = mi.Bitmap(str(t["filename"]))
    if t["raw"]:
        image.set_srgb_gamma(False)
    rgb = np.array(image.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, srgb_gamma=False))
    if rgb.max() > 1.0 + 1e-6:
        raise Unsupported("a textured area light with texels above 1 (Mitsuba's bitmap clamps them)")
    return {"type": "d65", "nested": _bitmap(t), "scale": f[0] / y_normalization_correction()}


def texture(t: dict[str, Any]) -> dict[str, Any]:
    """A spectral texture (reflectance)."""
    if t["type"] == "checkerboard":
        return {"type": "checkerboard", "color0": texture(t["color0"]), "color1": texture(t["color1"]), "to_uv": _to_uv(t)}
    if t["type"] == "bitmap":
        return _bitmap(t)
    return spectrum(t)


def float_texture(t: dict[str, Any]) -> float | dict[str, Any]:
    """A scalar texture (weight, opacity, roughness)."""
    if t["type"] == "constant":
        return float(t["value"])
    if t["type"] == "checkerboard":
        # Mitsuba 3.9's checkerboard is value0 where frac(u) > ½ equals frac(v) > ½ in `eval`
        # (spectra) but the other way round in `eval_1` (the scalar lookup that weights,
        # opacities and roughnesses use); prism uses the first rule for both, so swap here.
        return {"type": "checkerboard", "color0": float(t["value1"]), "color1": float(t["value0"]), "to_uv": _to_uv(t)}
    if t["type"] == "bitmap":
        return _bitmap(t, scalar=True)
    raise Unsupported(f"float texture type {t['type']!r}")


def _ior(value: Any, what: str) -> float:
    """An index of refraction: a number, or a constant spectrum; a varying one is dispersive."""
    if isinstance(value, (int, float)):
        return float(value)
    if isinstance(value, dict) and value.get("type") == "constant":
        return float(value["value"])
    if isinstance(value, dict) and value.get("type") == "irregular" and len(set(value["values"])) == 1:
        return float(value["values"][0])
    raise Dispersive(f"{what} varies with wavelength (dispersion)")


def _optional(d: dict[str, Any], m: dict[str, Any], keys: tuple[str, ...], convert) -> None:
    for key in keys:
        if key in m:
            d[key] = convert(m[key])


def _roughness(d: dict[str, Any], m: dict[str, Any]) -> None:
    d["distribution"] = m["distribution"]
    if "alpha_u" in m:
        d["alpha_u"], d["alpha_v"] = float_texture(_as_texture(m["alpha_u"])), float_texture(_as_texture(m["alpha_v"]))
    else:
        d["alpha"] = float_texture(_as_texture(m["alpha"]))


def _as_texture(v: Any) -> dict[str, Any]:
    return {"type": "constant", "value": v} if isinstance(v, (int, float)) else v


def material(m: dict[str, Any]) -> dict[str, Any]:
    kind = m["type"]
    if kind == "diffuse":
        return {"type": "diffuse", "reflectance": texture(m["reflectance"])}
    if kind == "twosided":
        return {"type": "twosided", "bsdf_0_front": material(m["front"]), "bsdf_1_back": material(m["back"])}
    if kind == "blend":
        return {
            "type": "blendbsdf",
            "weight": float_texture(m["weight"]),
            "bsdf_0": material(m["bsdf0"]),
            "bsdf_1": material(m["bsdf1"]),
        }
    if kind == "mask":
        return {"type": "mask", "opacity": float_texture(m["opacity"]), "bsdf": material(m["bsdf"])}
    if kind in ("conductor", "roughconductor"):
        d = {
            "type": kind,
            "eta": spectrum(m["eta"]),
            "k": spectrum(m["k"]),
            "specular_reflectance": texture(m["specular_reflectance"]),
        }
        if kind == "roughconductor":
            _roughness(d, m)
        return d
    if kind in ("plastic", "roughplastic"):
        d = {
            "type": kind,
            "diffuse_reflectance": texture(m["diffuse_reflectance"]),
            "specular_reflectance": texture(m["specular_reflectance"]),
            "int_ior": _ior(m["int_ior"], f"{kind} int_ior"),
            "ext_ior": _ior(m["ext_ior"], f"{kind} ext_ior"),
            "nonlinear": bool(m["nonlinear"]),
        }
        if kind == "roughplastic":
            d.update(distribution=m["distribution"], alpha=float(m["alpha"]))
        return d
    if kind in ("dielectric", "thindielectric", "roughdielectric"):
        if m.get("dispersive"):
            raise Dispersive(f"{kind} with a wavelength-dependent index of refraction (dispersion)")
        d = {"type": kind, "int_ior": _ior(m["int_ior"], f"{kind} int_ior"), "ext_ior": _ior(m["ext_ior"], f"{kind} ext_ior")}
        _optional(d, m, ("specular_reflectance", "specular_transmittance"), texture)
        if kind == "roughdielectric":
            _roughness(d, m)
        return d
    raise Unsupported(f"material type {kind!r}")


def emitter(e: dict[str, Any]) -> dict[str, Any]:
    kind = e["type"]
    if kind == "area":
        if e["radiance"]["type"] == "bitmap":
            return {"type": "area", "radiance": _emission_bitmap(e["radiance"])}
        return {"type": "area", "radiance": spectrum(e["radiance"])}
    if kind == "point":
        return {"type": "point", "position": [float(x) for x in e["position"]], "intensity": spectrum(e["intensity"])}
    if kind == "constant":
        return {"type": "constant", "radiance": spectrum(e["radiance"])}
    if kind == "spot":
        d = {"type": "spot", "intensity": spectrum(e["intensity"]), "to_world": _transform(e["to_world"])}
        _optional(d, e, ("cutoff_angle", "beam_width"), float)
        return d
    if kind == "directional":
        d = {"type": "directional", "irradiance": spectrum(e["irradiance"])}
        if "to_world" in e:
            d["to_world"] = _transform(e["to_world"])
        else:
            d["direction"] = [float(x) for x in e["direction"]]
        return d
    if kind == "envmap":
        if not e.get("filename"):
            raise Unsupported("an environment map not read from a file")
        # Mitsuba uplifts the texels itself, with a D65 normalised on its own colour scale, so
        # the rendered RGB reproduces the texels before `y_normalization_correction`; undo that
        # factor here (prism's texels reproduce exactly on the corrected scale).
        scale = float(e.get("scale", 1.0)) / y_normalization_correction()
        d = {"type": "envmap", "filename": str(e["filename"]), "scale": scale}
        if "to_world" in e:
            d["to_world"] = _transform(e["to_world"])
        return d
    raise Unsupported(f"emitter type {kind!r}")


def shape(s: dict[str, Any]) -> dict[str, Any]:
    kind = s["type"]
    if kind == "mesh":
        # prism bakes flip_normals into the mesh (reversed winding, negated normals).
        return {"type": "ply", "filename": str(s["filename"]), "face_normals": not s["has_normals"]}
    flip = bool(s.get("flip_normals", False))
    if kind == "sphere":
        return {"type": "sphere", "center": [float(x) for x in s["center"]], "radius": float(s["radius"]), "flip_normals": flip}
    if kind in ("disk", "rectangle", "cube"):
        return {"type": kind, "to_world": _transform(s["to_world"]), "flip_normals": flip}
    raise Unsupported(f"shape type {kind!r}")


def _film(scene: dict[str, Any]) -> dict[str, Any]:
    film, f = scene["film"], scene["film"]["filter"]
    if f["type"] == "box":
        if abs(float(f["radius"]) - 0.5) > 1e-6:
            raise Unsupported(f"box filter of radius {f['radius']} (Mitsuba's box has radius 0.5)")
        rfilter = {"type": "box"}
    elif f["type"] == "gaussian":
        rfilter = {"type": "gaussian", "stddev": float(f["stddev"])}
    else:
        raise Unsupported(f"pixel filter {f['type']!r}")
    return {
        "type": "hdrfilm",
        "width": int(film["width"]),
        "height": int(film["height"]),
        "rfilter": rfilter,
        "pixel_format": "rgb",
        "component_format": "float32",
        "sample_border": True,
    }


def specfilm(scene: dict[str, Any]) -> tuple[dict[str, Any], list[str], np.ndarray]:
    """Mitsuba's `specfilm` recording prism's sensor channels (the export's `sensor.channels`:
    src/sensor/export.rs), with the channels' prism names and gains: prism's channel k is
    `gains[k]` times the film's channel k (∫ L·srf dλ; the film samples λ from the sum of the
    curves, so bands past 830 nm render too). XYZ and RGB channels are not among them."""
    channels = scene.get("sensor", {}).get("channels", [])
    if not channels:
        raise Unsupported("the sensor has no spectral channels (bands, filters or a camera) for a specfilm")
    film = _film(scene)
    film["type"] = "specfilm"
    del film["pixel_format"]
    # Zero-padded keys: the film's channels come out in this order, which is also sorted order.
    for k, ch in enumerate(channels):
        film[f"srf_{k:03d}"] = spectrum(ch["srf"])
    return film, [ch["name"] for ch in channels], np.array([float(ch["gain"]) for ch in channels])


def check_spectral(scene: dict[str, Any]) -> None:
    lo, hi = map(float, scene["spectral"]["range"])
    if lo > MITSUBA_RANGE[0] or hi < MITSUBA_RANGE[1]:
        raise Unsupported(f"prism renders {lo}–{hi} nm; Mitsuba's RGB integrates 360–830 nm")


def convert(scene: dict[str, Any], spp: int | None = None, seed: int = 0, spectral_film: bool = False) -> dict[str, Any]:
    """A Mitsuba scene dict for the exported prism scene (`spp` overrides the scene's); with
    `spectral_film`, the film is the `specfilm` of prism's sensor channels (see `specfilm`)."""
    if not spectral_film:
        check_spectral(scene)
    cam, integ = scene["camera"], scene["integrator"]
    if integ["type"] != "path":
        raise Unsupported(f"integrator {integ['type']!r}")
    if cam.get("model", "pinhole") != "pinhole":
        raise Unsupported(f"the {cam['model']} camera (the converter writes Mitsuba's perspective camera)")
    if any(abs(float(v)) > 1e-6 for v in cam.get("principal_point_offset_px", [0, 0])):
        raise Unsupported("an off-centre principal point (intrinsics with cx, cy away from the image centre)")
    if "fov_y_deg" in cam:
        w, h = scene["film"]["width"], scene["film"]["height"]
        tx, ty = (np.tan(np.radians(float(cam[k])) / 2) for k in ("fov_x_deg", "fov_y_deg"))
        if abs(ty - tx * h / w) > 1e-5 * tx:
            raise Unsupported("non-square pixels (intrinsics with fx ≠ fy)")
    if integ.get("clamp") is not None:
        raise Unsupported(f"the integrator clamps radiance at {integ['clamp']} (biased; Mitsuba's path integrator does not clamp)")
    # prism's caustic light tracing estimates paths its path tracer then leaves out: the same
    # expected image as Mitsuba's path integrator, except for the caustics of directional
    # lights, which no path tracer can reach (Mitsuba's image lacks them).
    if integ.get("caustics") is not None and any(e.get("type") == "directional" for e in scene.get("emitters", [])):
        raise Unsupported("caustic light tracing adds directional lights' caustics, which Mitsuba's path integrator cannot render")
    out: dict[str, Any] = {
        "type": "scene",
        "integrator": {
            "type": "path",
            "max_depth": int(integ["max_depth"]),
            "rr_depth": int(integ["rr_depth"]),
            "hide_emitters": bool(integ["hide_emitters"]),
        },
        "sensor": {
            "type": "perspective",
            "fov": float(cam["fov_x_deg"]),
            "fov_axis": "x",
            "near_clip": float(cam["near_clip"]),
            "far_clip": float(cam["far_clip"]),
            "to_world": _transform(cam["to_world"]),
            # Any unbiased sampler estimates the same image; prism's Sobol has no Mitsuba twin.
            "sampler": {"type": "independent", "sample_count": int(spp or scene["sampler"]["spp"]), "seed": int(seed)},
            "film": specfilm(scene)[0] if spectral_film else _film(scene),
        },
    }
    materials = scene["materials"]
    emitters = scene["emitters"]
    for i, s in enumerate(scene["shapes"]):
        d = shape(s)
        d["bsdf"] = material(materials[s["material"]])
        if s.get("emitter") is not None:
            e = emitters[s["emitter"]]
            if e["type"] != "area" or e["shape"] != i:
                raise Unsupported(f"shape {i} names emitter {s['emitter']}, which is not its area light")
            d["emitter"] = emitter(e)
        out[f"shape_{i:04d}"] = d
    for j, e in enumerate(emitters):
        if e["type"] != "area":
            out[f"emitter_{j:03d}"] = emitter(e)
    return out
