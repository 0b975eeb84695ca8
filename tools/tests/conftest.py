"""Shared fixtures: the prism binary and a helper that renders a scene text to an EXR."""

from __future__ import annotations

import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def prism_bin() -> pathlib.Path:
    path = pathlib.Path(os.environ.get("PRISM_BIN", ROOT / "target" / "release" / "prism"))
    if not path.exists():
        subprocess.run(["cargo", "build", "--release"], cwd=ROOT, check=True)
    return path


@pytest.fixture
def render(prism_bin, tmp_path):
    """render(scene_text, *args) -> path of the EXR prism wrote."""

    def run(scene_text: str, *args: str) -> pathlib.Path:
        scene = tmp_path / "scene.ron"
        scene.write_text(scene_text)
        out = tmp_path / "out.exr"
        subprocess.run([str(prism_bin), "render", str(scene), "-o", str(out), "-q", *args], check=True)
        return out

    return run
