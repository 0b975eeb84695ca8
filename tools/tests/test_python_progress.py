"""`prism.render(progress=...)`: the workers count samples into an atomic without the GIL and
the calling thread hands (done, total) to a reporter (python/src/progress.py): a callable, a
tqdm bar, an ipywidgets bar or a text line, in a terminal or a (stubbed) Jupyter kernel. The
count is monotone and ends at pixels × spp; an exception from the reporter, like Ctrl-C, stops
the render and leaves the interpreter ready to render again."""

from __future__ import annotations

import io
import signal
import subprocess
import sys
import time
import types

import numpy as np
import prism
import pytest
from test_python_module import CORNELL, small_cornell

# 96 x 64 px (24 tiles of 16²) at 32 spp on one thread: some tenths of a second, so several of
# the 50 ms polls fall inside the render.
W, H, SPP = 96, 64, 32


@pytest.fixture(scope="module")
def scene():
    return prism.load_string(small_cornell(W, H, SPP))


def render(scene, progress):
    return prism.render(scene, threads=1, seed=3, progress=progress)


def check_counts(seen, total=W * H * SPP):
    """Monotone, every total the film's samples, and the last count all of them."""
    assert seen, "the reporter was never called"
    done = [d for d, _ in seen]
    assert all(t == total for _, t in seen), seen
    assert done == sorted(done), done
    assert done[-1] == total, seen


def test_a_callable_sees_every_sample_counted(scene):
    """Tolerance: none (counts are integers). The callable gets (done, total) from the
    calling thread: monotone, ending at 96·64·32; a render longer than four polls shows counts
    between 0 and the end too. The render's bits do not depend on the reporter."""
    seen = []
    r = render(scene, lambda done, total: seen.append((done, total)))
    check_counts(seen)
    if r.stats[2] > 0.25:
        assert any(0 < d < W * H * SPP for d, _ in seen), (r.stats, seen)
    quiet = render(scene, False)
    for name, a in r.channels.items():
        np.testing.assert_array_equal(a, quiet.channels[name], err_msg=name)


class FakeTqdm:
    """tqdm's interface as prism uses it; records what it was told."""

    made: list["FakeTqdm"] = []

    def __init__(self, total, **kw):
        self.total, self.n, self.kw, self.ns, self.closed = total, 0, kw, [], False
        FakeTqdm.made.append(self)

    def update(self, k):
        assert k >= 0
        self.n += k
        self.ns.append(self.n)

    def close(self):
        self.closed = True


@pytest.fixture
def notebook(monkeypatch):
    """A Jupyter kernel as prism sees one: ipykernel imported, IPython.get_ipython() a shell
    with a kernel, and IPython.display.display recording what it shows."""
    shown = []
    ipython = types.ModuleType("IPython")
    ipython.get_ipython = lambda: types.SimpleNamespace(kernel=object())
    display = types.ModuleType("IPython.display")
    display.display = shown.append
    ipython.display = display
    monkeypatch.setitem(sys.modules, "ipykernel", types.ModuleType("ipykernel"))
    monkeypatch.setitem(sys.modules, "IPython", ipython)
    monkeypatch.setitem(sys.modules, "IPython.display", display)
    assert prism._progress.in_notebook()
    return shown


def test_notebook_draws_with_tqdm_auto(scene, notebook, monkeypatch):
    """Tolerance: none. In a kernel, progress=True draws tqdm.auto's bar (the notebook widget
    where ipywidgets is installed): made once with the total, advanced monotonically to it,
    closed."""
    auto = types.ModuleType("tqdm.auto")
    auto.tqdm = FakeTqdm
    monkeypatch.setitem(sys.modules, "tqdm", types.ModuleType("tqdm"))
    monkeypatch.setitem(sys.modules, "tqdm.auto", auto)
    FakeTqdm.made = []
    render(scene, True)
    (bar,) = FakeTqdm.made
    assert bar.total == W * H * SPP and bar.closed
    assert bar.ns == sorted(bar.ns) and bar.ns[-1] == bar.total


def test_notebook_without_tqdm_uses_ipywidgets(scene, notebook, monkeypatch):
    """Tolerance: none. No tqdm: an ipywidgets IntProgress, displayed once, its value
    monotone up to its max (the total), green at the end."""
    values = []

    class IntProgress:
        def __init__(self, value, min, max, description):
            self.max, self._value, self.bar_style = max, value, ""

        @property
        def value(self):
            return self._value

        @value.setter
        def value(self, v):
            values.append(v)
            self._value = v

    widgets = types.ModuleType("ipywidgets")
    widgets.IntProgress = IntProgress
    monkeypatch.setitem(sys.modules, "tqdm", None)
    monkeypatch.setitem(sys.modules, "tqdm.auto", None)
    monkeypatch.setitem(sys.modules, "ipywidgets", widgets)
    render(scene, True)
    (bar,) = notebook
    assert bar.max == W * H * SPP and bar.bar_style == "success"
    assert values == sorted(values) and values[-1] == bar.max


def percents(text):
    """The percentages of a '\\r'-redrawn text line, in order."""
    return [int(part.rsplit("|", 1)[1].strip().rstrip("%")) for part in text.split("\r") if "|" in part]


def test_notebook_without_libraries_prints_a_line(scene, notebook, monkeypatch, capsys):
    """Tolerance: none. Neither tqdm nor ipywidgets: a text line on stdout (what a cell
    shows), redrawn in place with rising percentages up to 100, then a newline."""
    for name in ("tqdm", "tqdm.auto", "ipywidgets"):
        monkeypatch.setitem(sys.modules, name, None)
    render(scene, True)
    out = capsys.readouterr().out
    p = percents(out)
    assert p == sorted(p) and p[-1] == 100 and out.endswith("\n"), repr(out)


class Terminal(io.StringIO):
    def isatty(self):
        return True


def test_terminal_draws_a_bar_and_a_pipe_none(scene, monkeypatch, capsys):
    """Tolerance: none. stderr a terminal: tqdm's bar where tqdm imports, else a text line
    rising to 100%; stderr not a terminal (a log, CI): nothing is written."""
    for name in ("ipykernel", "tqdm", "tqdm.auto"):
        monkeypatch.delitem(sys.modules, name, raising=False)
    tty = Terminal()
    monkeypatch.setattr(sys, "stderr", tty)
    render(scene, True)
    if _has_tqdm():
        # tqdm's bar, cleared at the end (leave=False) as `prism render` clears its own.
        assert tty.getvalue().startswith("\rprism:") and tty.getvalue().endswith("\r"), repr(tty.getvalue())
    monkeypatch.setitem(sys.modules, "tqdm", None)
    tty = Terminal()
    monkeypatch.setattr(sys, "stderr", tty)
    render(scene, True)
    p = percents(tty.getvalue())
    assert p == sorted(p) and p[-1] == 100, repr(tty.getvalue())
    pipe = io.StringIO()
    monkeypatch.setattr(sys, "stderr", pipe)
    render(scene, True)
    assert pipe.getvalue() == "" and capsys.readouterr().out == ""


def _has_tqdm():
    try:
        import tqdm  # noqa: F401
    except ImportError:
        return False
    return True


def test_a_raising_reporter_stops_the_render():
    """A render of minutes (1024² px at 1024 spp) whose reporter raises at its first call
    (50 ms in): the exception comes back within 30 s (a tile takes well under a second even on
    a loaded machine), and the same interpreter renders again."""
    text = CORNELL.replace("film: (width: 256, height: 256", "film: (width: 1024, height: 1024")
    text = text.replace("sampler: (kind: Independent, spp: 256)", "sampler: (kind: Independent, spp: 1024)")
    big = prism.load_string(text)

    def stop(done, total):
        raise ValueError(f"stopped at {done} of {total}")

    t = time.monotonic()
    with pytest.raises(ValueError, match="stopped at"):
        prism.render(big, threads=2, progress=stop)
    assert time.monotonic() - t < 30
    seen = []
    prism.render(prism.load_string(small_cornell()), spp=1, threads=1, progress=lambda d, t: seen.append(d))
    assert seen[-1] == 24 * 16


def test_bad_progress_is_refused(scene):
    with pytest.raises(TypeError, match=r"progress must be True, False or a callable f\(done, total\)"):
        prism.render(scene, progress="yes")


def test_ctrl_c_with_a_notebook_bar(tmp_path):
    """Ctrl-C (SIGINT 1 s into a render of minutes) in a stubbed kernel with a tqdm.auto bar:
    KeyboardInterrupt within 30 s, the bar closed where it stopped (below its total), and the
    interpreter renders again with a bar that fills."""
    text = CORNELL.replace("film: (width: 256, height: 256", "film: (width: 1024, height: 1024")
    text = text.replace("sampler: (kind: Independent, spp: 256)", "sampler: (kind: Independent, spp: 1024)")
    script = tmp_path / "notebook.py"
    script.write_text(
        "import sys, time, types\n"
        "bars = []\n"
        "class Bar:\n"
        "    def __init__(self, total, **kw):\n"
        "        self.total, self.n, self.closed = total, 0, False\n"
        "        bars.append(self)\n"
        "    def update(self, k): self.n += k\n"
        "    def close(self): self.closed = True\n"
        "ip = types.ModuleType('IPython'); ip.get_ipython = lambda: types.SimpleNamespace(kernel=1)\n"
        "auto = types.ModuleType('tqdm.auto'); auto.tqdm = Bar\n"
        "sys.modules.update({'ipykernel': types.ModuleType('ipykernel'), 'IPython': ip,\n"
        "                    'tqdm': types.ModuleType('tqdm'), 'tqdm.auto': auto})\n"
        "import prism\n"
        f"s = prism.load_string({text!r})\n"
        "print('ready', flush=True)\n"
        "try:\n"
        "    prism.render(s, threads=2)\n"
        "    print('finished')\n"
        "except KeyboardInterrupt:\n"
        "    print('interrupted at %.3f' % time.time(), flush=True)\n"
        "b = bars[-1]\n"
        "print('stopped bar', b.closed, b.n < b.total, flush=True)\n"
        f"prism.render(prism.load_string({small_cornell()!r}), spp=1, threads=1)\n"
        "b = bars[-1]\n"
        "print('again bar', b.closed, b.n == b.total == 24 * 16, flush=True)\n"
    )
    p = subprocess.Popen([sys.executable, str(script)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert p.stdout.readline().strip() == "ready"
    time.sleep(1.0)
    sent = time.time()
    p.send_signal(signal.SIGINT)
    try:
        out, err = p.communicate(timeout=120)
    except subprocess.TimeoutExpired:
        p.kill()
        pytest.fail("the render went on for 120 s after SIGINT")
    assert p.returncode == 0, err
    assert "interrupted at" in out, out + err
    assert float(out.split("interrupted at ")[1].split()[0]) - sent < 30.0, out
    assert "stopped bar True True" in out and "again bar True True" in out, out + err
