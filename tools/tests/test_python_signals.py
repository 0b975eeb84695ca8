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
