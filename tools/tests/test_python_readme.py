"""The README's Python examples stay true: the ten-line example runs as written (in a folder
where `scenes/` is the checkout's, so what it writes lands there)."""

from __future__ import annotations

import pathlib
import re
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]


def python_blocks():
    text = (ROOT / "README.md").read_text()
    section = text.split("## Python", 1)[1].split("\n## ", 1)[0]
    return re.findall(r"```python\n(.*?)```", section, re.S)


def test_the_ten_line_example_runs(tmp_path):
    """Tolerance: none; it must run and write what it says (the Cornell box at 16 spp)."""
    first = python_blocks()[0]
    assert len(first.strip().splitlines()) <= 12, first
    (tmp_path / "scenes").symlink_to(ROOT / "scenes")
    script = first + "\nprint('cube', cube.shape)\n"
    done = subprocess.run([sys.executable, "-c", script], cwd=tmp_path, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "cornell.exr").exists() and (tmp_path / "cornell.json").exists()
    assert (tmp_path / "cornell.png").exists()
    assert re.search(r"cube \(64, 64, \d+\)", done.stdout), done.stdout
