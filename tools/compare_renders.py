#!/usr/bin/env python3
"""Renders every scene under scenes/ with two prism binaries and compares the EXR pixel data
bit for bit (every channel in its own type: float bits, uint32 ids and raw DN).

    tools/.venv/bin/python tools/compare_renders.py OLD_PRISM NEW_PRISM [--spp 1] [--out DIR]

Both binaries get the same scene, `--spp`, `--seed 1` and `--threads 2` (renders are
deterministic at any thread count, docs/reliability.md). Scenes keep their own film size: the
command line has no resolution override, so the sample count is kept small instead. Headers are
not compared (they carry the render time, and `prism dataset` frames gained the render's keys in
issue 25). Exit code 0 when every scene rendered by both is identical, 1 otherwise.
"""
from __future__ import annotations

import argparse
import pathlib
import subprocess
import sys
import tempfile

import numpy as np
import OpenImageIO as oiio

ROOT = pathlib.Path(__file__).resolve().parent.parent


def channels(path: pathlib.Path) -> dict[str, np.ndarray]:
    """Each channel of an EXR in its stored type, by name."""
    inp = oiio.ImageInput.open(str(path))
    if inp is None:
        raise OSError(f"cannot open {path}: {oiio.geterror()}")
    spec = inp.spec()
    out = {}
    for i, name in enumerate(spec.channelnames):
        fmt = spec.channelformat(i)
        out[name] = np.asarray(inp.read_image(0, 0, i, i + 1, fmt)).copy()
    inp.close()
    return out


def render(binary: str, scene: pathlib.Path, out: pathlib.Path, spp: int) -> str | None:
    cmd = [binary, "render", str(scene), "-o", str(out), "--spp", str(spp), "--seed", "1",
           "--threads", "2", "--quiet"]
    r = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT)
    return None if r.returncode == 0 else f"exit {r.returncode}: {r.stderr.strip()[-300:]}"


def same(a: dict[str, np.ndarray], b: dict[str, np.ndarray]) -> str | None:
    if list(a) != list(b):
        return f"channels differ: {sorted(set(a) ^ set(b))}"
    for name in a:
        x, y = a[name], b[name]
        if x.dtype != y.dtype or x.shape != y.shape:
            return f"{name}: {x.dtype}{x.shape} vs {y.dtype}{y.shape}"
        if x.tobytes() != y.tobytes():  # bits, so NaN payloads and -0 count too
            return f"{name}: {int(np.sum(x.view(np.uint8) != y.view(np.uint8)))} bytes differ"
    return None


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("--spp", type=int, default=1)
    ap.add_argument("--out", type=pathlib.Path, default=None)
    args = ap.parse_args()
    out = args.out or pathlib.Path(tempfile.mkdtemp(prefix="compare_renders_"))
    scenes = sorted((ROOT / "scenes").rglob("*.ron"))
    compared = identical = 0
    failed = []
    for scene in scenes:
        rel = scene.relative_to(ROOT / "scenes")
        stem = str(rel.with_suffix("")).replace("/", "__")
        a, b = out / f"{stem}.old.exr", out / f"{stem}.new.exr"
        ea, eb = render(args.old, scene, a, args.spp), render(args.new, scene, b, args.spp)
        if ea or eb:
            status = "both refuse" if ea and eb else "one refuses"
            print(f"{rel}: {status} (old: {ea}; new: {eb})")
            if bool(ea) != bool(eb):
                failed.append(str(rel))
            continue
        compared += 1
        diff = same(channels(a), channels(b))
        if diff is None:
            identical += 1
            print(f"{rel}: identical")
        else:
            failed.append(str(rel))
            print(f"{rel}: DIFFERS: {diff}")
    print(f"{compared} scenes compared, {identical} identical, {len(failed)} failed; files in {out}")
    return 0 if not failed else 1


if __name__ == "__main__":
    sys.exit(main())
