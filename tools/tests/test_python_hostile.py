"""The `prism` module under hostile input: each class found by trying several hundred bad
arguments, files and call patterns (issue 27's classes, held to the Python module) raises a
Python exception naming the thing and the fix, and never crashes, hangs or leaves process-wide
state behind. The cases that once aborted or hung run in a child interpreter with a timeout, so
a regression fails the test instead of taking pytest down with it."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import textwrap
import time

import prism
import pytest
from test_python_module import small_cornell, tiny_dataset_config

# A child interpreter's bound: the cases take about a second; a hang runs into it.
CHILD_TIMEOUT = 60


def child(code: str, tmp_path) -> subprocess.CompletedProcess:
    """Runs `code` in a fresh interpreter (this one's path, so this one's `prism`), in
    `tmp_path`; a hang fails the test after CHILD_TIMEOUT seconds."""
    try:
        return subprocess.run(
            [sys.executable, "-c", "import prism, numpy as np, os, pathlib\n" + textwrap.dedent(code)],
            cwd=tmp_path,
            capture_output=True,
            text=True,
            timeout=CHILD_TIMEOUT,
            env=dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path)),
        )
    except subprocess.TimeoutExpired:
        pytest.fail(f"hung for {CHILD_TIMEOUT} s:\n{code}")


def raises_in_child(code: str, tmp_path, exc: str, *words: str) -> str:
    """Runs `code` (which must raise) in a child; checks it raised `exc` (a name such as
    "prism.SceneError") with each of `words` in its message, and returns the message."""
    wrapped = f"try:\n{textwrap.indent(textwrap.dedent(code), '    ')}\nexcept BaseException as e:\n" \
        "    import json\n    print(json.dumps([type(e).__module__ + '.' + type(e).__qualname__, str(e)]))\n" \
        "else:\n    print(json.dumps(['nothing', '']))\n"
    r = child(wrapped, tmp_path)
    assert r.returncode == 0, f"the interpreter died ({r.returncode}):\n{r.stderr[-2000:]}"
    name, msg = json.loads(r.stdout.strip().splitlines()[-1])
    assert name == exc, f"{name}: {msg}"
    for w in words:
        assert w in msg, f"{w!r} not in {msg!r}"
    return msg


def os_threads() -> int:
    return len(os.listdir("/proc/self/task"))


@pytest.mark.skipif(not hasattr(os, "fork") or not os.path.exists("/proc/self/task"), reason="needs fork and /proc")
def test_no_threads_left_behind_and_a_forked_child_renders(tmp_path):
    """Tolerance: none on the thread count once the calls' pools have ended (waited for up to
    10 s: a pool's threads leave after it is dropped); the child's 60 s bound only keeps a hang
    from blocking the run. Loading once built the BVH on rayon's global pool: its threads stayed
    for the process's life, and a forked child (a DataLoader's worker) inherited the pool
    without them, so its first load waited forever."""
    script = f"""
    import os, time
    def threads():
        return len(os.listdir("/proc/self/task"))
    before = threads()
    text = {small_cornell(width=16, height=12, spp=1)!r}
    s = prism.load_string(text)
    prism.render(s, spp=1, threads=2, progress=False)
    s.params["camera.fov"] = 30
    deadline = time.monotonic() + 10
    while threads() > before and time.monotonic() < deadline:
        time.sleep(0.05)
    print("threads", before, threads())
    pid = os.fork()
    if pid == 0:
        r = prism.render(prism.load_string(text), spp=1, threads=1, progress=False)
        os._exit(0 if r.channels["R"].shape == (12, 16) else 3)
    deadline = time.monotonic() + 30
    while time.monotonic() < deadline:
        done, status = os.waitpid(pid, os.WNOHANG)
        if done:
            print("child", os.waitstatus_to_exitcode(status))
            break
        time.sleep(0.05)
    else:
        os.kill(pid, 9)
        os.waitpid(pid, 0)
        print("child hung")
    """
    r = child(script, tmp_path)
    assert r.returncode == 0, r.stderr[-2000:]
    lines = dict(line.split(" ", 1) for line in r.stdout.splitlines())
    before, after = map(int, lines["threads"].split())
    assert after == before, f"{after - before} threads left behind"
    assert lines["child"] == "0", f"the forked child: {lines['child']}"


def test_sampler_stream_refuses_more_numbers_than_memory_holds(tmp_path):
    """Tolerance: none. count=10**12 aborted the interpreter (a failed allocation), 2**62
    raised a PanicException ("capacity overflow")."""
    for count in ("10**12", "2**62"):
        raises_in_child(f"prism.sampler_stream([0], [0], count={count})", tmp_path, "prism.SceneError", "count=", "fewer")
    assert prism.sampler_stream([0, 1], [0, 0], count=3).shape == (2, 3)


def test_thread_counts_past_the_limit_are_refused(tmp_path):
    """Tolerance: none. threads=10**6 started 65,535 threads per render (minutes, no way to
    interrupt it); now refused before any start, by render and run_dataset alike."""
    text = small_cornell(width=16, height=12, spp=1)
    raises_in_child(
        f"prism.render(prism.load_string({text!r}), threads=10**6, progress=False)",
        tmp_path, "prism.SceneError", "--threads 1000000", "at most 1024",
    )
    cfg = tiny_dataset_config(tmp_path, frames=1)
    raises_in_child(
        f"prism.run_dataset({str(cfg)!r}, 'out', threads=10**6, progress=False)",
        tmp_path, "prism.SceneError", "--threads", "at most 1024",
    )
    assert not (tmp_path / "out" / "frames").exists()


@pytest.mark.parametrize("rng", ["(1, 1e9)", "(1e20, 1e30)", "(0, 0)", "(830, 360)", "(float('nan'), 500)"])
def test_spectral_ranges_are_the_loaders(tmp_path, rng):
    """Tolerance: none. A range reaching 1e9 nm tabulated the spectrum nm by nm (a hang); an
    empty, reversed or NaN range gave values for nothing without a word. Both functions now
    take the ranges a scene's spectral.range may have."""
    raises_in_child(f"prism.spectrum(0.5, [500], range={rng})", tmp_path, "prism.SceneError", "range", "830")
    raises_in_child(f"prism.sample_wavelengths([0.5], range={rng})", tmp_path, "prism.SceneError", "range")


@pytest.fixture(scope="module")
def finished(tmp_path_factory):
    """A finished two-frame dataset (16x12 px, 2 spp), copied by each test that damages it."""
    d = tmp_path_factory.mktemp("hostile_ds")
    out = d / "out"
    prism.run_dataset(tiny_dataset_config(d, frames=2), out, threads=2, progress=False)
    return out


@pytest.fixture
def dataset(finished, tmp_path):
    out = tmp_path / "ds"
    shutil.copytree(finished, out)
    return out


@pytest.mark.parametrize("what", ["manifest.jsonl", "frames/000000.exr", "frames/000000.json"])
@pytest.mark.parametrize("kind", ["fifo", "/dev/zero"])
def test_dataset_reads_no_fifo_or_device(dataset, tmp_path, what, kind):
    """Tolerance: none. A FIFO in a dataset's place was waited on forever, /dev/zero read until
    memory ran out; now an OSError names the file and what it is."""
    target = dataset / what
    target.unlink()
    if kind == "fifo":
        os.mkfifo(target)
        noun = "FIFO"
    else:
        os.symlink(kind, target)
        noun = "device"
    code = f"ds = prism.Dataset({str(dataset)!r})\nds[0]"
    raises_in_child(code, tmp_path, "builtins.OSError", str(target), noun)


def test_dataset_frame_numbers_past_u32_are_not_wrapped(dataset):
    """Tolerance: none. Frame 2^32 was read as frame 0 (a u32 cast): the same frame twice, the
    second under the wrong number. A number no dataset has is skipped, as a torn line is."""
    m = dataset / "manifest.jsonl"
    m.write_text(m.read_text() + json.dumps({"frame": 2**32}) + "\n" + json.dumps({"frame": 2**64 - 1}) + "\n")
    ds = prism.Dataset(dataset)
    assert len(ds) == 2
    assert [ds[i]["frame"] for i in range(2)] == [0, 1]


def test_a_damaged_sidecar_names_its_file(dataset):
    """Tolerance: none. A missing sidecar raised a bare "No such file or directory", a garbage
    one json's JSONDecodeError: neither named the file nor the fix."""
    side = dataset / "frames/000001.json"
    ds = prism.Dataset(dataset)
    side.write_text("{garbage")
    with pytest.raises(OSError, match=r"000001\.json: the frame's sidecar is not valid JSON(.|\n)*rerun `prism dataset`"):
        ds[1]
    side.write_bytes(b"\xff\xfe")
    with pytest.raises(OSError, match=r"000001\.json: the frame's sidecar is not UTF-8"):
        ds[1]
    side.unlink()
    with pytest.raises(OSError, match=r"000001\.json` does not exist"):
        ds[1]
    assert ds[0]["frame"] == 0
