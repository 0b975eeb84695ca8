"""Shared fixtures: the prism binary and a helper that renders a scene text to an EXR."""

from __future__ import annotations

import os
import pathlib
import signal
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]

# The Ctrl-C tests send SIGINT to this process or to children it starts. A shell without job
# control starts a background command (`./tools/run_tests.sh &`, nohup) with SIGINT ignored,
# which every child inherits and Python then leaves ignored: those tests would test the
# launcher. A handler set here is reset to the default in each exec'd child.
if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)


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
