"""Writes features.gltf, the fuzzer's glTF seed that exercises what the Khronos sample files in
tests/data/gltf/ do not: every material extension prism reads (KHR_materials_ior,
_transmission, _emissive_strength, _specular, _volume, _dispersion), KHR_texture_transform,
textures in every slot (base colour, metallic-roughness, normal, emissive, occlusion), alpha MASK
and BLEND, KHR_lights_punctual (point, spot, directional), a perspective and an orthographic
camera, TANGENT and TEXCOORD_1 attributes, a node hierarchy with a mesh used twice (one node
mirrored). Everything is embedded (data: URIs), so one file is one case.

Run: python3 examples/fuzz/seeds/make_features_gltf.py (standard library only).
"""

import base64
import json
import pathlib
import struct
import zlib


def png_rgba(w: int, h: int, texel) -> bytes:
    rows = b"".join(b"\x00" + b"".join(bytes(texel(x, y)) for x in range(w)) for y in range(h))

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    ihdr = struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b"")


def uri(mime: str, data: bytes) -> str:
    return f"data:{mime};base64,{base64.b64encode(data).decode()}"


# A unit quad in the xy plane, facing +z: two triangles.
pos = [(-0.5, -0.5, 0), (0.5, -0.5, 0), (0.5, 0.5, 0), (-0.5, 0.5, 0)]
nrm = [(0, 0, 1)] * 4
tan = [(1, 0, 0, 1)] * 4
uv0 = [(0, 1), (1, 1), (1, 0), (0, 0)]
uv1 = [(0, 0), (2, 0), (2, 2), (0, 2)]
idx = [0, 1, 2, 0, 2, 3]
blobs = [
    b"".join(struct.pack("<3f", *p) for p in pos),
    b"".join(struct.pack("<3f", *n) for n in nrm),
    b"".join(struct.pack("<4f", *t) for t in tan),
    b"".join(struct.pack("<2f", *t) for t in uv0),
    b"".join(struct.pack("<2f", *t) for t in uv1),
    b"".join(struct.pack("<H", i) for i in idx) + b"\x00\x00",
]
buf, views = b"", []
for b in blobs:
    views.append({"buffer": 0, "byteOffset": len(buf), "byteLength": len(b)})
    buf += b
views[-1]["byteLength"] -= 2
views[-1]["target"] = 34963
acc = [
    {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-0.5, -0.5, 0], "max": [0.5, 0.5, 0]},
    {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
    {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC4"},
    {"bufferView": 3, "componentType": 5126, "count": 4, "type": "VEC2"},
    {"bufferView": 4, "componentType": 5126, "count": 4, "type": "VEC2"},
    {"bufferView": 5, "componentType": 5123, "count": 6, "type": "SCALAR"},
]
checker = png_rgba(4, 4, lambda x, y: (200, 60, 30, 255) if (x + y) % 2 else (30, 90, 200, 128))
normal = png_rgba(4, 4, lambda x, y: (128 + 20 * (x - 2), 128 + 20 * (y - 2), 240, 255))
mr = png_rgba(4, 4, lambda x, y: (255, 40 * x + 20, 60 * y, 255))
emit = png_rgba(4, 4, lambda x, y: (255, 200, 80, 255) if x == y else (0, 0, 0, 255))
images = [{"uri": uri("image/png", d)} for d in (checker, normal, mr, emit)]
tt = {"KHR_texture_transform": {"offset": [0.1, 0.2], "rotation": 0.3, "scale": [2, 2]}}
materials = [
    {
        "name": "Textured",
        "pbrMetallicRoughness": {
            "baseColorTexture": {"index": 0, "extensions": tt},
            "metallicRoughnessTexture": {"index": 2},
            "metallicFactor": 0.7,
            "roughnessFactor": 0.4,
        },
        "normalTexture": {"index": 1, "scale": 0.8},
        "occlusionTexture": {"index": 2, "strength": 0.5},
        "alphaMode": "MASK",
        "alphaCutoff": 0.4,
        "doubleSided": True,
    },
    {
        "name": "Glass",
        "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.95, 1, 1], "metallicFactor": 0, "roughnessFactor": 0.05},
        "extensions": {
            "KHR_materials_ior": {"ior": 1.6},
            "KHR_materials_transmission": {"transmissionFactor": 1},
            "KHR_materials_volume": {"thicknessFactor": 0.2, "attenuationDistance": 2, "attenuationColor": [1, 0.9, 0.8]},
            "KHR_materials_dispersion": {"dispersion": 0.5},
            "KHR_materials_specular": {"specularFactor": 0.8, "specularColorFactor": [1, 0.9, 0.9]},
        },
    },
    {
        "name": "Lamp",
        "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.2, 0.2, 0.6]},
        "emissiveFactor": [1, 0.8, 0.5],
        "emissiveTexture": {"index": 3, "texCoord": 1},
        "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4}},
        "alphaMode": "BLEND",
    },
]
attrs = {"POSITION": 0, "NORMAL": 1, "TANGENT": 2, "TEXCOORD_0": 3, "TEXCOORD_1": 4}
meshes = [
    {"name": "quad", "primitives": [{"attributes": attrs, "indices": 5, "material": 0}]},
    {"name": "glass", "primitives": [{"attributes": attrs, "indices": 5, "material": 1}]},
    {"name": "lamp", "primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_1": 4}, "indices": 5, "material": 2}]},
]
nodes = [
    {"name": "root", "children": [1, 2, 3, 4, 5, 6, 7, 8], "rotation": [0, 0.0998, 0, 0.995]},
    {"name": "quad A", "mesh": 0, "translation": [-0.6, 0, 0]},
    {"name": "quad B (mirrored)", "mesh": 0, "translation": [0.6, 0, 0], "scale": [-1, 1, 1]},
    {"name": "pane", "mesh": 1, "translation": [0, 0, 0.5], "scale": [1.5, 1.5, 1]},
    {"name": "lamp", "mesh": 2, "matrix": [1, 0, 0, 0, 0, 0, -1, 0, 0, 1, 0, 0, 0, 1.2, 0, 1]},
    {"name": "bulb", "translation": [0, 1, 1], "extensions": {"KHR_lights_punctual": {"light": 0}}},
    {"name": "spot", "translation": [1, 1, 2], "rotation": [-0.2, 0.2, 0, 0.96], "extensions": {"KHR_lights_punctual": {"light": 1}}},
    {"name": "sun", "rotation": [-0.38, 0, 0, 0.92], "extensions": {"KHR_lights_punctual": {"light": 2}}},
    {"name": "eye", "translation": [0, 0, 3], "camera": 0},
    {"name": "plan", "translation": [0, 0, 4], "camera": 1},
]
nodes[0]["children"].append(9)
doc = {
    "asset": {"version": "2.0", "generator": "prism examples/fuzz/seeds/make_features_gltf.py"},
    "extensionsUsed": [
        "KHR_lights_punctual", "KHR_materials_ior", "KHR_materials_transmission", "KHR_materials_volume",
        "KHR_materials_dispersion", "KHR_materials_specular", "KHR_materials_emissive_strength", "KHR_texture_transform",
    ],
    "extensions": {"KHR_lights_punctual": {"lights": [
        {"type": "point", "color": [1, 0.9, 0.8], "intensity": 20, "range": 10},
        {"type": "spot", "intensity": 40, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}},
        {"type": "directional", "color": [1, 1, 0.95], "intensity": 3},
    ]}},
    "scene": 0,
    "scenes": [{"nodes": [0]}],
    "nodes": nodes,
    "cameras": [
        {"type": "perspective", "perspective": {"yfov": 0.8, "aspectRatio": 1.333, "znear": 0.01, "zfar": 100}},
        {"type": "orthographic", "orthographic": {"xmag": 1.5, "ymag": 1.1, "znear": 0.01, "zfar": 100}},
    ],
    "meshes": meshes,
    "materials": materials,
    "textures": [{"source": i, "sampler": 0} for i in range(4)],
    "samplers": [{"magFilter": 9729, "minFilter": 9987, "wrapS": 33648, "wrapT": 10497}],
    "images": images,
    "accessors": acc,
    "bufferViews": views,
    "buffers": [{"byteLength": len(buf), "uri": uri("application/octet-stream", buf)}],
}
out = pathlib.Path(__file__).with_name("features.gltf")
out.write_text(json.dumps(doc, indent=1) + "\n")
print(f"wrote {out} ({out.stat().st_size} bytes)")
