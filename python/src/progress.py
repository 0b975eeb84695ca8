"""How `prism.render(progress=...)` shows its progress (module `prism._progress`, compiled into
the extension from python/src/progress.py). The render's workers add finished samples to an
atomic counter without the GIL; the calling thread, which wakes every 50 ms to look for Ctrl-C,
reads it and hands (done, total) to the reporter made here.

progress=True: a bar wherever someone watches. In a notebook (an IPython kernel: Jupyter,
VS Code) tqdm.auto's bar when tqdm is installed, else an ipywidgets progress bar, else a text
line on stdout; in a terminal (stderr a tty) tqdm's bar, else a text line on stderr; elsewhere
(a pipe, a log file, CI) nothing. False: nothing (None is the default, True). A callable: called as f(done, total)
each time the count moves (total is the film's pixels times spp; done ends at total once a
render of fixed spp finishes, below it for an adaptive one), and an exception it raises stops
the render as Ctrl-C does.
"""

import sys

DESC = "prism"


def in_notebook():
    """Whether this runs in an IPython kernel, whose stderr is no terminal but draws bars."""
    if "ipykernel" not in sys.modules:
        return False
    ipython = sys.modules.get("IPython")
    shell = ipython.get_ipython() if ipython is not None else None
    return shell is not None and getattr(shell, "kernel", None) is not None


def reporter(progress):
    """The reporter for `progress` (None: show nothing): `update(done, total)` and
    `close(finished)`."""
    if progress is False:
        return None
    if progress is True or progress is None:
        if in_notebook():
            return Lazy(notebook_bar)
        stream = sys.stderr
        if stream is not None and stream.isatty():
            return Lazy(lambda total: terminal_bar(total, stream))
        return None
    if callable(progress):
        return Callback(progress)
    raise TypeError(f"progress must be True, False or a callable f(done, total), not {progress!r}")


def notebook_bar(total):
    try:
        from tqdm.auto import tqdm
    except ImportError:
        pass
    else:
        return Tqdm(tqdm(total=total, desc=DESC, unit="sample", unit_scale=True, leave=False))
    try:
        import ipywidgets
        from IPython.display import display
    except ImportError:
        return Text(total, sys.stdout)
    return Widget(ipywidgets, display, total)


def terminal_bar(total, stream):
    try:
        from tqdm import tqdm
    except ImportError:
        return Text(total, stream)
    return Tqdm(tqdm(total=total, desc=DESC, unit="sample", unit_scale=True, leave=False, file=stream))


class Lazy:
    """A bar made at the first count: the total is known once the scene is built (on the
    render's thread, after any rebuild for spp, seed or aovs)."""

    def __init__(self, make):
        self.make = make
        self.bar = None

    def update(self, done, total):
        if self.bar is None:
            self.bar = self.make(total)
        self.bar.update(done, total)

    def close(self, finished):
        if self.bar is not None:
            self.bar.close(finished)


class Callback:
    def __init__(self, f):
        self.f = f

    def update(self, done, total):
        self.f(done, total)

    def close(self, finished):
        pass


class Tqdm:
    def __init__(self, bar):
        self.bar = bar

    def update(self, done, total):
        self.bar.update(done - self.bar.n)

    def close(self, finished):
        if finished:
            self.bar.update(self.bar.total - self.bar.n)
        self.bar.close()


class Widget:
    """An ipywidgets bar (a notebook without tqdm)."""

    def __init__(self, ipywidgets, display, total):
        self.bar = ipywidgets.IntProgress(value=0, min=0, max=total, description=DESC)
        display(self.bar)

    def update(self, done, total):
        self.bar.value = done

    def close(self, finished):
        if finished:
            self.bar.value = self.bar.max
        self.bar.bar_style = "success" if finished else "danger"


class Text:
    """One line redrawn in place ('\\r') when the whole percentage moves; a newline at the end."""

    WIDTH = 30

    def __init__(self, total, stream):
        self.total = max(total, 1)
        self.stream = stream
        self.shown = None

    def update(self, done, total):
        pct = min(100, done * 100 // self.total)
        if pct != self.shown:
            self.shown = pct
            full = pct * self.WIDTH // 100
            self.stream.write(f"\r{DESC} |{'#' * full}{'.' * (self.WIDTH - full)}| {pct:3d}%")
            self.stream.flush()

    def close(self, finished):
        if finished:
            self.update(self.total, self.total)
        if self.shown is not None:
            self.stream.write("\n")
            self.stream.flush()
