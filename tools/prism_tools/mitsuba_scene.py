"""prism's exported scene (`prism export SCENE.ron -o DIR` → DIR/scene.json) as a Mitsuba 3 scene
dictionary at matched settings: same world-space geometry (the exported PLY meshes), camera,
pixel filter, sampler, integrator, and the same spectra (prism's own tabulation, so RGB is not
uplifted twice), materials and emitters.

Only Mitsuba's fixed spectral range (360–830 nm, visible sampling) can be matched; `convert`
refuses scenes that ask for anything else.
"""

from __future__ import annotations

import json
import pathlib
from typing import Any

import mitsuba as mi


class Unsupported(ValueError):
    """The scene uses something Mitsuba cannot render the same way."""


def load(path: str | pathlib.Path) -> dict[str, Any]:
    return json.loads(pathlib.Path(path).read_text())


def _matrix(rows: list[list[float]]) -> "mi.ScalarTransform4f":
    return mi.ScalarTransform4f(rows)


def _uv_transform(scale: list[float], offset: list[float]) -> "mi.ScalarTransform4f":
    # prism: uv' = uv · scale + offset.
    return mi.ScalarTransform4f().translate([offset[0], offset[1], 0.0]) @ mi.ScalarTransform4f().scale([scale[0], scale[1], 1.0])


def spectrum(s: dict[str, Any]) -> dict[str, Any]:
    if s["type"] == "constant":
        return {"type": "uniform", "value": float(s["value"])}
    if s["type"] == "irregular":
        return {
            "type": "irregular",
            "wavelengths": ", ".join(f"{w:.6g}" for w in s["wavelengths"]),
            "values": ", ".join(f"{v:.9g}" for v in s["values"]),
        }
    raise Unsupported(f"spectrum type {s['type']}")


def texture(t: dict[str, Any]) -> dict[str, Any]:
    if t["type"] == "checkerboard":
        return {"type": "checkerboard", "color0": texture(t["color0"]), "color1": texture(t["color1"]), "to_uv": _uv_transform(t["uv_scale"], t["uv_offset"])}
    if t["type"] == "bitmap":
        return {
            "type": "bitmap",
            "filename": str(t["filename"]),
            "raw": bool(t["raw"]),
            "filter_type": t["filter"],
            "wrap_mode": t["wrap"],
            "to_uv": _uv_transform(t["uv_scale"], t["uv_offset"]),
        }
    return spectrum(t)


def float_texture(t: dict[str, Any]) -> Any:
    if t["type"] == "constant":
        return float(t["value"])
    if t["type"] == "checkerboard":
        return {"type": "checkerboard", "color0": float(t["value0"]), "color1": float(t["value1"]), "to_uv": _uv_transform(t["uv_scale"], t["uv_offset"])}
    if t["type"] == "bitmap":
        return {"type": "bitmap", "filename": str(t["filename"]), "raw": bool(t["raw"]), "filter_type": t["filter"], "wrap_mode": t["wrap"], "to_uv": _uv_transform(t["uv_scale"], t["uv_offset"])}
    raise Unsupported(f"float texture type {t['type']}")


def material(m: dict[str, Any]) -> dict[str, Any]:
    kind = m["type"]
    if kind == "diffuse":
        return {"type": "diffuse", "reflectance": texture(m["reflectance"])}
    if kind == "twosided":
        # Mitsuba's twosided takes the front BSDF first, the back second.
        return {"type": "twosided", "a_front": material(m["front"]), "b_back": material(m["back"])}
    if kind == "blend":
        return {"type": "blendbsdf", "weight": float_texture(m["weight"]), "a_bsdf0": material(m["bsdf0"]), "b_bsdf1": material(m["bsdf1"])}
    if kind == "mask":
        return {"type": "mask", "opacity": float_texture(m["opacity"]), "bsdf": material(m["bsdf"])}
    if kind in ("plastic", "roughplastic"):
        d = {
            "type": kind,
            "diffuse_reflectance": texture(m["diffuse_reflectance"]),
            "specular_reflectance": texture(m["specular_reflectance"]),
            "int_ior": float(m["int_ior"]),
            "ext_ior": float(m["ext_ior"]),
            "nonlinear": bool(m["nonlinear"]),
        }
        if kind == "roughplastic":
            d.update(distribution=m["distribution"], alpha=float(m["alpha"]))
        return d
    raise Unsupported(f"material type {kind}")


def emitter(e: dict[str, Any]) -> dict[str, Any]:
    kind = e["type"]
    if kind == "area":
        return {"type": "area", "radiance": spectrum(e["radiance"])}
    if kind == "point":
        return {"type": "point", "position": e["position"], "intensity": spectrum(e["intensity"])}
    if kind == "constant":
        return {"type": "constant", "radiance": spectrum(e["radiance"])}
    if kind == "spot":
        return {
            "type": "spot",
            "intensity": spectrum(e["intensity"]),
            "cutoff_angle": float(e["cutoff_angle"]),
            "beam_width": float(e["beam_width"]),
            "to_world": _matrix(e["to_world"]),
        }
    if kind == "directional":
        return {"type": "directional", "direction": [float(c) for c in e["direction"]], "irradiance": spectrum(e["irradiance"])}
    if kind == "envmap":
        if e["filename"] is None:
            raise Unsupported("an environment map not read from a file")
        return {"type": "envmap", "filename": str(e["filename"]), "scale": float(e["scale"]), "to_world": _matrix(e["to_world"])}
    raise Unsupported(f"emitter type {kind}")


def convert(scene: dict[str, Any], spp: int | None = None, seed: int = 0) -> dict[str, Any]:
    """A Mitsuba scene dict for the exported prism scene (Mitsuba's spectral variants)."""
    sp = scene["spectral"]
    if list(map(float, sp["range"])) != [360.0, 830.0] or sp["sampling"] != "visible":
        raise Unsupported("Mitsuba renders 360–830 nm with visible-importance sampling only")
    cam, film = scene["camera"], scene["film"]
    rfilter = {"type": "box"} if film["filter"]["type"] == "box" else {"type": "gaussian", "stddev": film["filter"]["stddev"]}
    if film["filter"]["type"] == "box" and abs(film["filter"]["radius"] - 0.5) > 1e-6:
        raise Unsupported("Mitsuba's box filter has radius 0.5")
    integ = scene["integrator"]
    out: dict[str, Any] = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": int(integ["max_depth"]), "rr_depth": int(integ["rr_depth"]), "hide_emitters": bool(integ["hide_emitters"])},
        "sensor": {
            "type": "perspective",
            "fov": float(cam["fov_x_deg"]),
            "fov_axis": "x",
            "near_clip": float(cam["near_clip"]),
            "far_clip": float(cam["far_clip"]),
            "to_world": _matrix(cam["to_world"]),
            "sampler": {"type": "independent", "sample_count": int(spp or scene["sampler"]["spp"]), "seed": seed},
            "film": {"type": "hdrfilm", "width": film["width"], "height": film["height"], "rfilter": rfilter, "pixel_format": "rgb", "component_format": "float32"},
        },
    }
    materials = scene["materials"]
    area = {e["shape"]: e for e in scene["emitters"] if e["type"] == "area"}
    for i, s in enumerate(scene["shapes"]):
        if s["type"] == "mesh":
            d = {"type": "ply", "filename": str(s["filename"]), "face_normals": not s["has_normals"]}
        elif s["type"] == "sphere":
            d = {"type": "sphere", "center": s["center"], "radius": float(s["radius"]), "flip_normals": bool(s["flip_normals"])}
        elif s["type"] == "disk":
            d = {"type": "disk", "to_world": _matrix(s["to_world"]), "flip_normals": bool(s["flip_normals"])}
        else:
            raise Unsupported(f"shape type {s['type']}")
        d["bsdf"] = material(materials[s["material"]])
        if i in area:
            d["emitter"] = emitter(area[i])
        out[f"shape_{i:04d}"] = d
    for j, e in enumerate(scene["emitters"]):
        if e["type"] != "area":
            out[f"emitter_{j:03d}"] = emitter(e)
    return out
