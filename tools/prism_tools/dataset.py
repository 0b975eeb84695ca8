"""Datasets written by `prism dataset`: open one lazily as frames of numpy arrays, draw a contact
sheet, and run one on a Ray cluster.

    from prism_tools import dataset
    ds = dataset.open_dataset("out/tabletop")
    f = ds[3]                      # nothing read yet
    wl, cube = f.spectral()        # wavelengths (nm, increasing) and an H x W x N radiance cube
    rgb = f.layer("RGB")           # H x W x 3 linear sRGB, float32
    ids = f.layer("instance")      # H x W uint32 (ids stay integers; outputs.read's types)
    loader = DataLoader(dataset.FrameDataset("out/tabletop", layers=("RGB", "label")))
    f.params["camera"]["fov"]      # the frame's sampled parameters
    dataset.contact_sheet(ds, "sheet.png")

    dataset.run_on_ray("configs/datasets/smoke.ron", "out/smoke", address=None)  # or "ray://..."

Command line: `python -m prism_tools.dataset sheet OUT sheet.png` and
`python -m prism_tools.dataset ray CONFIG OUT [--address ADDR]`.

Frames are the ones the manifest lists (finished and checksummed by prism). EXRs are read with
OpenImageIO; spectral channels follow Fichet et al. 2021 (`S0.<nm>nm`, comma decimal separator).
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import signal
import subprocess
import sys
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from . import outputs


def _prism_bin(prism_bin: str | os.PathLike | None = None) -> str:
    if prism_bin:
        return str(prism_bin)
    env = os.environ.get("PRISM_BIN")
    if env:
        return env
    local = pathlib.Path(__file__).resolve().parents[2] / "target" / "release" / "prism"
    return str(local) if local.exists() else "prism"


@dataclass
class Frame:
    """One finished frame; its files are read on first use."""

    index: int
    root: pathlib.Path
    files: list[str]

    @property
    def exr_path(self) -> pathlib.Path:
        return self.root / f"frames/{self.index:06d}.exr"

    @property
    def preview_path(self) -> pathlib.Path | None:
        p = self.root / f"frames/{self.index:06d}.png"
        return p if p.exists() else None

    @cached_property
    def sidecar(self) -> dict:
        """The frame's JSON: the render's sidecar (docs/sidecar.md: camera, sensor, objects)
        with the frame's sampled parameters under `frame`."""
        return json.loads((self.root / f"frames/{self.index:06d}.json").read_text())

    @property
    def params(self) -> dict:
        """The frame's sampled parameters."""
        return self.sidecar["frame"]

    @cached_property
    def render(self) -> outputs.Render:
        """The frame's EXR and JSON through `outputs.read`, the one reader of prism's files."""
        return outputs.read(self.exr_path)

    @property
    def channels(self) -> list[str]:
        return list(self.render.channels)

    @property
    def metadata(self) -> dict:
        """The EXR header's attributes (prism:seed, prism:spp, spectralLayoutVersion, ...)."""
        return self.render.metadata

    def channel(self, name: str) -> np.ndarray:
        """One channel: float32 (H, W), or uint32 for an id channel (`instance.ID`)."""
        return self.render.channels[name]

    def spectral(self) -> tuple[np.ndarray, np.ndarray]:
        """(wavelengths in nm, increasing; H x W x N spectral radiance, W m^-2 sr^-1 nm^-1)."""
        r = self.render
        if r.spectral is None:
            raise KeyError(
                f"{self.exr_path} has no spectral channels (S0.<nm>nm): its sensor writes {self.layers()}; "
                "give the base scene's sensor `bands` for a spectral dataset (configs/README.md)"
            )
        return r.wavelengths, r.spectral

    def layers(self) -> list[str]:
        """Layer names: `RGB`, `XYZ`, `S0` (spectral) and every `layer.channel` prefix (AOVs)."""
        return self.render.layers()

    def layer(self, name: str) -> np.ndarray:
        """As `outputs.Render.layer`: `RGB`, `XYZ` (H, W, 3), `S0` (the spectral cube, by
        wavelength) or an AOV layer, (H, W) for one channel else (H, W, C); floats float32,
        ids uint32."""
        return self.render.layer(name)


@dataclass
class Dataset:
    """A `prism dataset` output folder: `info` is its dataset.json; frames are indexed by frame
    number and read lazily."""

    root: pathlib.Path
    info: dict
    entries: dict[int, dict] = field(repr=False)

    def __len__(self) -> int:
        return len(self.entries)

    def indices(self) -> list[int]:
        return sorted(self.entries)

    def __getitem__(self, i: int) -> Frame:
        e = self.entries[i]
        return Frame(i, self.root, [f["path"] for f in e["files"]])

    def __iter__(self):
        return (self[i] for i in self.indices())


class FrameDataset:
    """A map-style dataset over a `prism dataset` folder, for `torch.utils.data.DataLoader`
    (which needs only `__len__` and `__getitem__`; torch is not imported here): item k is the
    k-th finished frame in frame order as {layer: array for each of `layers`, "frame": its
    index}, arrays as `Frame.layer` gives them (float32; ids uint32, (H, W)). `transform`, if
    given, maps that dict to what the loader should see (e.g. ids to int64 for older torch)."""

    def __init__(self, root: str | os.PathLike, layers=("RGB",), transform=None):
        self.dataset = open_dataset(root)
        self.frames = self.dataset.indices()
        self.layers = tuple(layers)
        self.transform = transform

    def __len__(self) -> int:
        return len(self.frames)

    def __getitem__(self, k: int) -> dict:
        if not -len(self) <= k < len(self):
            raise IndexError(f"item {k} of {len(self)}")
        f = self.dataset[self.frames[k]]
        item = {name: f.layer(name) for name in self.layers}
        item["frame"] = f.index
        return self.transform(item) if self.transform else item


def read_manifest(root: str | os.PathLike) -> list[dict]:
    """Every manifest line that parses, in order (a torn last line after a crash is skipped)."""
    out = []
    p = pathlib.Path(root) / "manifest.jsonl"
    if p.exists():
        for line in p.read_text().splitlines():
            try:
                out.append(json.loads(line))
            except json.JSONDecodeError:
                pass
    return out


def open_dataset(root: str | os.PathLike) -> Dataset:
    root = pathlib.Path(root)
    info = json.loads((root / "dataset.json").read_text())
    entries: dict[int, dict] = {}
    for e in read_manifest(root):
        entries.setdefault(int(e["frame"]), e)
    return Dataset(root, info, entries)


def _tonemap(rgb: np.ndarray) -> np.ndarray:
    c = np.clip(rgb, 0.0, 1.0)
    s = np.where(c <= 0.0031308, 12.92 * c, 1.055 * np.power(c, 1 / 2.4) - 0.055)
    return (s * 255 + 0.5).astype(np.uint8)


def contact_sheet(ds: Dataset, out: str | os.PathLike, columns: int = 6, width: int = 160) -> pathlib.Path:
    """A PNG grid of the frames (their previews, else their RGB), each labelled with its index."""
    import cv2

    tiles = []
    for f in ds:
        if f.preview_path is not None:
            img = cv2.imread(str(f.preview_path), cv2.IMREAD_COLOR)
        else:
            img = cv2.cvtColor(_tonemap(f.layer("RGB")), cv2.COLOR_RGB2BGR)
        h = round(img.shape[0] * width / img.shape[1])
        img = cv2.resize(img, (width, h), interpolation=cv2.INTER_AREA)
        cv2.putText(img, str(f.index), (4, 14), cv2.FONT_HERSHEY_SIMPLEX, 0.45, (255, 255, 255), 1, cv2.LINE_AA)
        tiles.append(img)
    if not tiles:
        raise ValueError(f"{ds.root}: no finished frames")
    h = max(t.shape[0] for t in tiles)
    blank = np.zeros((h, width, 3), np.uint8)
    tiles = [np.vstack([t, blank[: h - t.shape[0]]]) for t in tiles]
    tiles += [blank] * (-len(tiles) % columns)
    rows = [np.hstack(tiles[i : i + columns]) for i in range(0, len(tiles), columns)]
    out = pathlib.Path(out)
    cv2.imwrite(str(out), np.vstack(rows))
    return out


def _die_with_parent() -> None:
    """In the child: SIGKILL when the parent (a Ray worker) dies, so no orphan keeps writing."""
    try:
        import ctypes

        ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
    except OSError:
        pass


def render_frame(prism: str, config: str, out: str, frame: int, threads: int | None, log: str | None) -> int:
    """One frame through the prism binary (`--frames i`); the manifest, under prism's lock file,
    lists it once however many tasks render it. Raises on failure so Ray retries."""
    if log:
        with open(log, "a") as f:
            f.write(f"{frame} {os.getpid()}\n")
    cmd = [prism, "dataset", config, "-o", out, "--frames", str(frame), "--quiet"]
    if threads:
        cmd += ["--threads", str(threads)]
    r = subprocess.run(cmd, capture_output=True, text=True, preexec_fn=_die_with_parent)
    if r.returncode != 0:
        raise RuntimeError(f"prism dataset --frames {frame} exited {r.returncode}: {r.stderr.strip()}")
    return frame


def frame_task(ray, num_cpus: float = 1, max_retries: int = 3):
    """`render_frame` as a Ray task, retried on worker or node death and on failure. Workers
    import prism_tools from this checkout (the nodes share its file system, as they share OUT)."""
    here = str(pathlib.Path(__file__).resolve().parents[1])
    path = os.pathsep.join(p for p in (here, os.environ.get("PYTHONPATH")) if p)
    return ray.remote(
        num_cpus=num_cpus,
        max_retries=max_retries,
        retry_exceptions=True,
        runtime_env={"env_vars": {"PYTHONPATH": path}},
    )(render_frame)


def run_on_ray(
    config: str | os.PathLike,
    out: str | os.PathLike,
    address: str | None = None,
    prism_bin: str | os.PathLike | None = None,
    max_retries: int = 3,
    num_cpus: float = 1,
    threads: int | None = None,
    attempt_log: str | os.PathLike | None = None,
) -> list[int]:
    """Renders the dataset's missing frames on Ray, one task per frame (each calls
    `prism dataset CONFIG -o OUT --frames i`), retried up to `max_retries` times when a worker or
    node dies or prism fails. `address`: a running cluster (`"auto"`, `"ray://host:10001"`); None
    starts a local one unless Ray is already initialised. Every node must see `out` at the same
    path (a shared file system) and have the prism binary. Returns the frames rendered."""
    import ray

    prism = _prism_bin(prism_bin)
    config, out = str(pathlib.Path(config).resolve()), str(pathlib.Path(out).resolve())
    # Checks the config and claims the folder once, before any task (bad input: exit 2 here).
    r = subprocess.run([prism, "dataset", config, "-o", out, "--check"], capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"prism dataset --check exited {r.returncode}: {r.stderr.strip()}")
    todo = json.loads(r.stdout)["todo"]
    if not ray.is_initialized():
        ray.init(address=address, include_dashboard=False, log_to_driver=False)
    task = frame_task(ray, num_cpus, max_retries)
    log = str(attempt_log) if attempt_log else None
    return sorted(ray.get([task.remote(prism, config, out, i, threads, log) for i in todo]))


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m prism_tools.dataset", description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    s = sub.add_parser("sheet", help="write a contact sheet of a dataset")
    s.add_argument("out")
    s.add_argument("png")
    s.add_argument("--columns", type=int, default=6)
    s.add_argument("--width", type=int, default=160)
    r = sub.add_parser("ray", help="render a dataset on a Ray cluster")
    r.add_argument("config")
    r.add_argument("out")
    r.add_argument("--address", default=None)
    r.add_argument("--max-retries", type=int, default=3)
    r.add_argument("--threads", type=int, default=None)
    a = ap.parse_args(argv)
    if a.cmd == "sheet":
        print(contact_sheet(open_dataset(a.out), a.png, a.columns, a.width))
    else:
        done = run_on_ray(a.config, a.out, a.address, max_retries=a.max_retries, threads=a.threads)
        print(f"{len(done)} frame(s) rendered")
    return 0


if __name__ == "__main__":
    sys.exit(main())
