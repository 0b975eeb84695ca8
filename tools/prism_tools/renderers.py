"""Running the two renderers: prism through its command line, Mitsuba 3 (a spectral variant) on
the conversion of prism's own export of the same scene file."""

from __future__ import annotations

import os
import pathlib
import subprocess
import tempfile

import numpy as np

from . import images
from . import mitsuba_scene as ms

ROOT = pathlib.Path(__file__).resolve().parents[2]
#: The Mitsuba variant the comparisons use: CPU, spectral, no JIT compilation to wait for.
VARIANT = "scalar_spectral"
#: Linear sRGB and CIE XYZ, as prism writes them.
CHANNELS = ["R", "G", "B", "X", "Y", "Z"]


def prism_binary() -> pathlib.Path:
    """$PRISM_BIN, or the release build in this checkout."""
    return pathlib.Path(os.environ.get("PRISM_BIN", ROOT / "target" / "release" / "prism"))


def export(prism_bin: pathlib.Path, scene: pathlib.Path, out_dir: pathlib.Path) -> dict:
    """`prism export`: the resolved scene as prism will render it."""
    _run([str(prism_bin), "export", str(scene), "-o", str(out_dir)])
    return ms.load(out_dir)


def channels(exported: dict) -> list[str]:
    """The channels of `CHANNELS` the scene writes (Mitsuba gives all of them)."""
    out = exported["outputs"]
    names = (["R", "G", "B"] if out["rgb"] else []) + (["X", "Y", "Z"] if out["xyz"] else [])
    if not names:
        raise ms.Unsupported("the scene writes neither RGB nor XYZ, the channels Mitsuba's film has")
    return names


def render_prism(
    prism_bin: pathlib.Path, scene: pathlib.Path, seed: int, spp: int | None = None, names: list[str] = CHANNELS
) -> np.ndarray:
    """One prism render: (height, width, len(names)), channels `names` in order."""
    with tempfile.TemporaryDirectory(prefix="prism-render-") as tmp:
        out = pathlib.Path(tmp) / "render.exr"
        cmd = [str(prism_bin), "render", str(scene), "-o", str(out), "-q", "--seed", str(seed)]
        if spp:
            cmd += ["--spp", str(spp)]
        _run(cmd)
        ch = images.read_channels(out)
    return np.stack([ch[c] for c in names], axis=-1).astype(np.float64)


class MitsubaRenderer:
    """Mitsuba's rendering of an exported prism scene (raises `ms.Unsupported` at construction
    for what Mitsuba cannot render the same way)."""

    def __init__(self, exported: dict, spp: int | None = None):
        import mitsuba as mi

        mi.set_variant(VARIANT)
        self._mi = mi
        self.spp = int(spp or exported["sampler"]["spp"])
        self.scene = mi.load_dict(ms.convert(exported, spp=self.spp))
        # XYZ from Mitsuba's linear sRGB, by the inverse of the matrix its film applies.
        self._srgb_to_xyz = np.linalg.inv(xyz_to_srgb_matrix())
        self._scale = ms.y_normalization_correction()

    def render(self, seed: int, names: list[str] = CHANNELS) -> np.ndarray:
        """(height, width, len(names)), channels `names` (of `CHANNELS`) in order."""
        rgb = self._scale * np.array(self._mi.render(self.scene, seed=seed, spp=self.spp), dtype=np.float64)[..., :3]
        all6 = np.concatenate([rgb, rgb @ self._srgb_to_xyz.T], axis=-1)
        return all6[..., [CHANNELS.index(n) for n in names]]


def xyz_to_srgb_matrix() -> np.ndarray:
    """The 3×3 matrix Mitsuba's films use from CIE XYZ to linear sRGB, read off Mitsuba itself."""
    import mitsuba as mi

    columns = [np.array(mi.xyz_to_srgb(mi.ScalarColor3f(*e))) for e in np.eye(3)]
    return np.stack(columns, axis=1)


def _run(cmd: list[str]) -> None:
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed ({done.returncode}):\n{done.stderr.strip()}")
