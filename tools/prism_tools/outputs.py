"""Read a prism render into numpy: the spectral cube with its wavelengths (sorted), the colour
channels, every AOV layer by name and the sidecar (docs/sidecar.md).

    r = outputs.read("out.exr")
    r.wavelengths, r.spectral          # (N,), (H, W, N), sorted by wavelength
    r.layer("depth")                   # float32 (H, W); r.layer("normal") -> (H, W, 3) X, Y, Z
    r.layer("instance")                # uint32 (H, W): ids are integers, never floats
    r.layer("RGB"), r.layer("XYZ")     # float32 (H, W, 3); r.layer("S0") is the spectral cube
    r.metadata["prism:seed"]           # the EXR header's attributes
    r.sidecar["camera"]["K"]

`prism_tools.dataset.Frame` reads its EXR with this reader: the same layers, shapes and types.
"""

from __future__ import annotations

import dataclasses
import json
import pathlib
import re

import numpy as np
import OpenImageIO as oiio

_SPECTRAL = re.compile(r"^S0\.(\d+)(?:,(\d+))?nm$")
# Channel order within a layer (EXR stores them sorted by name).
_ORDER = ["R", "G", "B", "X", "Y", "Z", "U", "V", "A", "ID"]


@dataclasses.dataclass
class Render:
    channels: dict[str, np.ndarray]
    wavelengths: np.ndarray
    spectral: np.ndarray | None
    sidecar: dict | None
    metadata: dict = dataclasses.field(default_factory=dict)
    path: pathlib.Path | None = None

    def layers(self) -> list[str]:
        """Layer names: `RGB`, `XYZ`, `S0` (spectral) where present, then every other
        `layer.channel` prefix (AOVs, camera channels) in file order."""
        out = [n for n in ("RGB", "XYZ") if all(c in self.channels for c in n)]
        if self.spectral is not None:
            out.append("S0")
        for c in self.channels:
            layer = c.split(".", 1)[0]
            if "." in c and layer != "S0" and layer not in out:
                out.append(layer)
        return out

    def layer(self, name: str) -> np.ndarray:
        """Layer `name`: "RGB" / "XYZ" (H, W, 3), "S0" (the spectral cube, H, W, N by
        wavelength), or an AOV / camera layer ("depth", "normal", "instance", "camera"):
        (H, W) for one channel, else (H, W, C) in R, G, B / X, Y, Z / U, V order. Float layers
        are float32, id layers uint32."""
        if name in ("RGB", "XYZ") and all(c in self.channels for c in name):
            return np.stack([self.channels[c] for c in name], axis=-1)
        if name == "S0" and self.spectral is not None:
            return self.spectral
        names = [c for c in self.channels if c.split(".", 1)[0] == name and "." in c]
        if not names:
            where = f"{self.path} has" if self.path else "the render has"
            raise KeyError(f"no layer {name!r}: {where} {self.layers()}")
        names.sort(key=lambda c: _ORDER.index(c.split(".", 1)[1]) if c.split(".", 1)[1] in _ORDER else 99)
        if len(names) == 1:
            return self.channels[names[0]]
        return np.stack([self.channels[n] for n in names], axis=-1)

    def rgb(self) -> np.ndarray:
        return self.layer("RGB")


def read(path: str | pathlib.Path) -> Render:
    """Reads `path` (an EXR prism wrote) and its sidecar (same name, .json) if present."""
    path = pathlib.Path(path)
    inp = oiio.ImageInput.open(str(path))
    if inp is None:
        raise OSError(f"cannot open {path}: {oiio.geterror()}")
    spec = inp.spec()
    metadata = {a.name: a.value for a in spec.extra_attribs}
    names = list(spec.channelnames)
    formats = [str(f) for f in spec.channelformats] or [str(spec.format)] * len(names)
    channels: dict[str, np.ndarray] = {}
    floats = inp.read_image(0, 0, 0, len(names), "float")
    for i, n in enumerate(names):
        if formats[i] == "uint":
            # Ids are 32-bit: read them natively (float32 holds only 24 bits exactly).
            channels[n] = np.asarray(inp.read_image(0, 0, i, i + 1, "uint"))[..., 0].astype(np.uint32)
        else:
            channels[n] = np.asarray(floats[..., i], dtype=np.float32)
    inp.close()
    bands = []
    for n in channels:
        m = _SPECTRAL.match(n)
        if m:
            bands.append((float(f"{m.group(1)}.{m.group(2) or 0}"), n))
    bands.sort()
    wavelengths = np.array([b[0] for b in bands])
    spectral = np.stack([channels[b[1]] for b in bands], axis=-1) if bands else None
    side = path.with_suffix(".json")
    sidecar = json.loads(side.read_text()) if side.exists() else None
    return Render(channels, wavelengths, spectral, sidecar, metadata, path)


def camera_matrices(sidecar: dict) -> dict[str, np.ndarray]:
    """The sidecar's camera as numpy arrays: K, dist, R, t, rvec (Rodrigues, for
    cv2.projectPoints), world_to_camera (OpenCV), camera_to_world_opengl."""
    cam = sidecar["camera"]
    r = np.array(cam["R"], dtype=np.float64)
    if "rvec" in cam:
        rvec = np.array(cam["rvec"], dtype=np.float64)
    else:
        # Sidecars before rvec: OpenCV's own conversion, exact near 180° (where the skew part
        # of R vanishes and angle / (2 sin angle) · skew loses the axis).
        import cv2

        rvec = cv2.Rodrigues(r)[0][:, 0]
    return {
        "K": np.array(cam["K"], dtype=np.float64),
        "dist": np.array(cam["dist"], dtype=np.float64),
        "R": r,
        "t": np.array(cam["t"], dtype=np.float64),
        "rvec": rvec,
        "world_to_camera": np.array(cam["world_to_camera_opencv"], dtype=np.float64),
        "camera_to_world_opengl": np.array(cam["camera_to_world_opengl"], dtype=np.float64),
    }
