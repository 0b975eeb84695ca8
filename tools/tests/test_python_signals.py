"""The Python module leaves its host's signals alone: `prism.run_dataset` installs no process-wide
SIGINT/SIGTERM handler (the CLI's handler once did, so Ctrl-C ended the interpreter and a
DataLoader's forked workers could no longer be terminated, which hung `Pool.terminate`), and
Ctrl-C stops a run with KeyboardInterrupt before its next frame, the frames done kept."""

from __future__ import annotations

import json
import os
import signal
import threading
import time

import prism
import pytest
from test_python_module import tiny_dataset_config


def caught_signals() -> int:
    """The process's caught-signal mask from /proc (bit n-1 for signal n)."""
    for line in open("/proc/self/status"):
        if line.startswith("SigCgt:"):
            return int(line.split()[1], 16)
    raise AssertionError("no SigCgt line in /proc/self/status")


@pytest.mark.skipif(not os.path.exists("/proc/self/status"), reason="needs Linux /proc")
def test_run_dataset_installs_no_signal_handler(tmp_path):
    """Tolerance: none. After a run, SIGTERM is not caught, and a child forked from this
    process dies of a SIGTERM within 10 s (the bound only keeps a broken build from hanging;
    a default SIGTERM kills at once)."""
    before = caught_signals()
    prism.run_dataset(tiny_dataset_config(tmp_path, frames=1), tmp_path / "out", threads=2, progress=False)
    assert caught_signals() == before, f"SigCgt {before:x} -> {caught_signals():x}"
    assert not caught_signals() & (1 << (signal.SIGTERM - 1))

    pid = os.fork()
    if pid == 0:
        time.sleep(30)
        os._exit(0)
    os.kill(pid, signal.SIGTERM)
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline:
        done, status = os.waitpid(pid, os.WNOHANG)
        if done:
            break
        time.sleep(0.02)
    else:
        os.kill(pid, signal.SIGKILL)
        os.waitpid(pid, 0)
        pytest.fail("a forked child ignored SIGTERM for 10 s")
    assert os.WIFSIGNALED(status) and os.WTERMSIG(status) == signal.SIGTERM, status


def finished(out) -> int:
    m = out / "manifest.jsonl"
    if not m.exists():
        return 0
    return sum(1 for line in m.read_text().splitlines() if line.strip().startswith("{"))


def test_ctrl_c_stops_run_dataset_and_a_rerun_resumes(tmp_path):
    """Tolerance: none. SIGINT once the first frame is listed raises KeyboardInterrupt before
    all 40 frames are done (the interpreter lives on); the listed frames are whole and a rerun
    renders only the rest, to 40."""
    cfg = tiny_dataset_config(tmp_path, frames=40)
    out = tmp_path / "out"

    def interrupt():
        deadline = time.monotonic() + 120
        while finished(out) < 1 and time.monotonic() < deadline:
            time.sleep(0.005)
        os.kill(os.getpid(), signal.SIGINT)

    t = threading.Thread(target=interrupt)
    t.start()
    with pytest.raises(KeyboardInterrupt):
        prism.run_dataset(cfg, out, threads=2, progress=False)
    t.join()
    done = finished(out)
    assert 1 <= done < 40, done
    kept = {json.loads(line)["frame"] for line in (out / "manifest.jsonl").read_text().splitlines()}

    prism.run_dataset(cfg, out, threads=2, progress=False)
    assert finished(out) == 40
    assert len(prism.Dataset(out)) == 40
    assert kept <= set(range(40))


@pytest.mark.parametrize(
    "spp",
    [
        # The packet kernel (the default path).
        "4194304",
        # The scalar integrator (adaptive sampling does not run in packets): its pilot, then
        # the full count, as the target cannot be met.
        "Adaptive(rel_error: 0.000001, min: 16, max: 4194304)",
    ],
)
def test_ctrl_c_stops_a_render_inside_its_one_tile(tmp_path, spp):
    """Tolerance: 10 s from the SIGINT to KeyboardInterrupt (the check runs every 4096 samples
    of a pixel, milliseconds apart; the bound leaves room for a loaded machine). A 16×12 film is
    one tile, and at 2^22 spp it renders for minutes: before, Ctrl-C waited for the tile's end.
    Run in a child with a 90 s bound, so a broken build fails instead of hanging."""
    import subprocess
    import sys

    from test_python_module import small_cornell

    scene = tmp_path / "s.ron"
    scene.write_text(small_cornell(16, 12, spp=spp))
    code = f"""
import os, signal, threading, time, prism
s = prism.load_file({str(scene)!r})
threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT)).start()
t0 = time.monotonic()
try:
    prism.render(s, threads=2, progress=False)
    print("finished")
except KeyboardInterrupt:
    print("stopped", time.monotonic() - t0 - 0.5)
"""
    try:
        r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=90)
    except subprocess.TimeoutExpired:
        pytest.fail("Ctrl-C did not stop a one-tile render within 90 s")
    assert r.returncode == 0, r.stderr
    word, *rest = r.stdout.split()
    assert word == "stopped", r.stdout
    assert float(rest[0]) < 10, f"stopped {rest[0]} s after the SIGINT"
