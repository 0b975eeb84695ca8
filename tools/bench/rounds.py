"""Interleaved rounds of renders, for a shared machine: every renderer renders once per round, in
an order rotated each round (A B C D, then B C D A, ...), so a drift of the machine's load hits
all alike; each renderer's figure is the median over rounds, and each pair's ratio is taken
round by round (the renders of one round ran minutes apart at most) and reported as median and
range. The 1-minute load average is recorded before every render.

Mitsuba 3 runs as a server process per variant (tools/bench/mitsuba_worker.py --serve): its scene
is loaded and its kernels compiled once, then it renders when asked, so its rounds cost render
time only, as prism's summary line reports render time only.

Also here: `agreement`, the check that two renderers' images estimate the same picture (so the
timings compare the same work).
"""

from __future__ import annotations

import json
import os
import pathlib
import statistics
import subprocess
import tempfile
import threading
from typing import Callable

import numpy as np

import common
from common import ROOT, log, show


class MitsubaServer:
    """One Mitsuba variant with its scene loaded (`scene` is an export folder or "cornell_box")."""

    def __init__(self, python: str, scene: str | pathlib.Path, variant: str, spp: int, threads: int | None,
                 save_exr: pathlib.Path | None = None, timeout: float = 1800.0):
        cmd = [python, str(ROOT / "tools/bench/mitsuba_worker.py"), str(scene), "--variant", variant,
               "--spp", str(spp), "--serve"]
        if threads:
            cmd += ["--threads", str(threads)]
        if save_exr:
            cmd += ["--save-exr", str(save_exr)]
        show(cmd)
        self.variant, self.spp, self.timeout, self.save_exr = variant, spp, timeout, save_exr
        self.err = tempfile.TemporaryFile("w+")
        self.p = subprocess.Popen(cmd, stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=self.err, text=True,
                                  env=common.mitsuba_env())
        self.info = self._reply()
        self.rss_mib = None

    def _reply(self) -> dict:
        """The next JSON line of the worker (Mitsuba's own log lines are skipped); a worker that
        dies or stays silent past `timeout` raises with its stderr's tail."""
        timer = threading.Timer(self.timeout, self.p.kill)
        timer.start()
        try:
            for line in self.p.stdout:
                if "{" in line:
                    return json.loads(line[line.index("{"):])
        finally:
            timer.cancel()
        self.err.seek(0)
        raise RuntimeError(common.llvm_error(self.variant, self.err.read().strip()[-400:] or "the worker exited"))

    def __call__(self, seed: int) -> dict:
        self.p.stdin.write(f"{seed}\n")
        self.p.stdin.flush()
        s = self._reply()["render_s"]
        w, h = self.info["width"], self.info["height"]
        return {"render_s": s, "msamples_per_s": w * h * self.spp / s / 1e6}

    def close(self) -> None:
        if self.p.poll() is None:
            self.p.stdin.close()
            _, _, ru = os.wait4(self.p.pid, 0)
            self.rss_mib = ru.ru_maxrss / 1024.0
        self.err.close()


def prism_runner(binary: pathlib.Path, scene: pathlib.Path, spp: int, threads: int | None, exr: pathlib.Path,
                 extra: list[str]) -> Callable[[int], dict]:
    def run(seed: int) -> dict:
        r = common.prism_render(binary, scene, spp, threads or os.cpu_count(), exr, [*extra, "--seed", str(seed)])
        if "error" in r:
            raise RuntimeError(r["error"])
        return r
    return run


def run_rounds(runners: dict[str, Callable[[int], dict]], rounds: int) -> dict[str, list[dict]]:
    """`rounds` rounds; round r (seed r + 1 for every renderer) starts at renderer r mod n."""
    names = list(runners)
    out: dict[str, list[dict]] = {n: [] for n in names}
    for r in range(rounds):
        k = r % len(names)
        for name in names[k:] + names[:k]:
            load = os.getloadavg()[0]
            res = runners[name](r + 1)
            res["load_1min"] = load
            res["round"] = r
            out[name].append(res)
            log(f"  round {r + 1}/{rounds} {name:24s} {res['msamples_per_s']:7.3f} Msamples/s "
                f"({res['render_s']:.2f} s; load {load:.1f})")
    return out


def summary(runs: dict[str, list[dict]], pairs: list[tuple[str, str]]) -> dict:
    """Median, min and max Msamples/s per renderer; per pair (a, b) the round-by-round ratios
    a / b; the load averages seen."""
    per = {}
    for name, rs in runs.items():
        v = [r["msamples_per_s"] for r in rs]
        per[name] = {"median": statistics.median(v), "min": min(v), "max": max(v), "n": len(v)}
    ratios = {}
    for a, b in pairs:
        if a in runs and b in runs:
            by_round = {r["round"]: r["msamples_per_s"] for r in runs[b]}
            q = [r["msamples_per_s"] / by_round[r["round"]] for r in runs[a] if r["round"] in by_round]
            if q:
                ratios[f"{a} / {b}"] = {"median": statistics.median(q), "min": min(q), "max": max(q), "all": q}
    loads = [r["load_1min"] for rs in runs.values() for r in rs]
    return {"renderers": per, "ratios": ratios,
            "load_1min": {"median": statistics.median(loads), "min": min(loads), "max": max(loads)} if loads else None}


def markdown(title: str, s: dict) -> list[str]:
    lo = s["load_1min"]
    lines = [f"### {title}", "",
             f"Load average (1 min) before each render: median {lo['median']:.1f}, range {lo['min']:.1f}–{lo['max']:.1f}.",
             "", "| renderer | Msamples/s, median | min–max | rounds |", "|---|---|---|---|"]
    lines += [f"| {n} | {r['median']:.3f} | {r['min']:.3f}–{r['max']:.3f} | {r['n']} |" for n, r in s["renderers"].items()]
    if s["ratios"]:
        lines += ["", "| pair ratio (same round) | median | min–max |", "|---|---|---|"]
        lines += [f"| {n} | {q['median']:.2f}× | {q['min']:.2f}–{q['max']:.2f} |" for n, q in s["ratios"].items()]
    return lines + [""]


def read_rgb(path: pathlib.Path) -> np.ndarray:
    import OpenImageIO as oiio

    inp = oiio.ImageInput.open(str(path))
    if inp is None:
        raise RuntimeError(f"cannot read {path}: {oiio.geterror()}")
    names = list(inp.spec().channelnames)
    data = inp.read_image("float")
    inp.close()
    return np.stack([data[..., names.index(c)] for c in "RGB"], axis=-1).astype(np.float64)


def agreement(a: np.ndarray, b: np.ndarray, block: int = 16) -> dict:
    """Do two independent renders (H×W×3) estimate the same image? Per pixel, d = a − b (mean over
    R, G, B) has expectation 0 if they do, and pixels are independent; so z = mean(d) / se(d)
    over the image, and per block of block×block pixels. Returns the ratio of the image means,
    z of the whole image and the largest |z| of a block: |z| ≲ 4 (image) and ≲ 5 (the worst of a
    few hundred blocks) is agreement within noise; a different picture gives tens."""
    d = (a - b).mean(axis=2)
    z = float(d.mean() / (d.std(ddof=1) / np.sqrt(d.size) + 1e-30))
    h, w = (d.shape[0] // block) * block, (d.shape[1] // block) * block
    blocks = d[:h, :w].reshape(h // block, block, w // block, block).transpose(0, 2, 1, 3).reshape(-1, block * block)
    zb = blocks.mean(axis=1) / (blocks.std(axis=1, ddof=1) / block + 1e-30)
    return {"mean_ratio": float(a.mean() / b.mean()), "z_image": z, "max_abs_z_block": float(np.abs(zb).max()),
            "blocks": int(blocks.shape[0])}
