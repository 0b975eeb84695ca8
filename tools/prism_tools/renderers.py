"""Running the two renderers: prism, and Mitsuba 3 (a spectral variant) on the conversion of
prism's own export of the same scene file.

prism renders through one of two backends, which give the same bits for the same scene, spp and
seed (tools/tests/test_python_backends.py):

- "module": the `prism` Python module (python/, README "Python"), in this process, the scene
  loaded once for all seeds; the default when `import prism` works and $PRISM_BIN is not set;
- "binary": `prism render` in a subprocess per render, files read back; chosen by naming a
  binary (an argument or $PRISM_BIN), for comparing builds, and by validate.py, whose report's
  inputs digest covers the sources a binary is built from. `prism export` (the scene Mitsuba
  gets) always runs the binary.
"""

from __future__ import annotations

import os
import pathlib
import subprocess
import tempfile

import numpy as np

from . import outputs
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


def backend(prism_bin: pathlib.Path | None = None) -> str:
    """The backend a render with `prism_bin` takes: "binary" when one is named (here or in
    $PRISM_BIN), else "module" when `import prism` works, else "binary" (this checkout's)."""
    if prism_bin is not None or os.environ.get("PRISM_BIN"):
        return "binary"
    try:
        import prism  # noqa: F401
    except ImportError:
        return "binary"
    return "module"


class PrismRenderer:
    """prism's renders of one scene file at any seed, through backend `via` ("module" or
    "binary"; None: `backend(prism_bin)`); `spp` overrides the scene's (None: its own)."""

    def __init__(self, scene: pathlib.Path, spp: int | None = None, prism_bin: pathlib.Path | None = None, via: str | None = None):
        self.backend = via or backend(prism_bin)
        if self.backend not in ("module", "binary"):
            raise ValueError(f"backend {self.backend!r}: use \"module\" or \"binary\"")
        self.scene_file = pathlib.Path(scene)
        self.spp = spp
        self.prism_bin = prism_bin or prism_binary()
        if self.backend == "module":
            import prism

            self._prism = prism
            self.scene = prism.load_file(self.scene_file)

    def channels(self, seed: int) -> dict[str, np.ndarray]:
        """Every channel of the render with `seed`, as the EXR holds it (float32, ids uint32)."""
        if self.backend == "module":
            return self._prism.render(self.scene, spp=self.spp, seed=seed, progress=False).channels
        with tempfile.TemporaryDirectory(prefix="prism-render-") as tmp:
            out = pathlib.Path(tmp) / "render.exr"
            cmd = [str(self.prism_bin), "render", str(self.scene_file), "-o", str(out), "-q", "--seed", str(seed)]
            if self.spp:
                cmd += ["--spp", str(self.spp)]
            _run(cmd)
            return outputs.read(out).channels

    def render(self, seed: int, names: list[str] = CHANNELS) -> np.ndarray:
        """(height, width, len(names)), channels `names` in order."""
        ch = self.channels(seed)
        return np.stack([ch[c] for c in names], axis=-1).astype(np.float64)


def render_prism(
    prism_bin: pathlib.Path | None, scene: pathlib.Path, seed: int, spp: int | None = None, names: list[str] = CHANNELS
) -> np.ndarray:
    """One prism render: (height, width, len(names)), channels `names` in order; through the
    binary `prism_bin`, or with None the default backend (`backend()`)."""
    return PrismRenderer(scene, spp, prism_bin).render(seed, names)


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
