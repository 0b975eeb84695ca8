"""Shared by the benchmark scripts: building prism, running a renderer as a measured child process
(peak RSS from wait4), parsing prism's summary line, running the Mitsuba worker, and printing
every command as it runs so a reader can repeat any figure by hand."""

from __future__ import annotations

import json
import os
import pathlib
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
import threading
import time

ROOT = pathlib.Path(__file__).resolve().parents[2]
LLVM19 = pathlib.Path("/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1")
SCENES = {
    "cornell": ROOT / "scenes/cornell.ron",
    "materials": ROOT / "scenes/bench/materials.ron",
    "mesh": ROOT / "scenes/bench/mesh.ron",
    # Issue 26's kept-back-like scenes: three spheres on a floor, a blackbody light, a D65 sky.
    "metals": ROOT / "scenes/bench/metals.ron",
    "glass": ROOT / "scenes/bench/glass.ron",
    "plastics": ROOT / "scenes/bench/plastics.ron",
}
MESH_PLY = ROOT / "out/bench/mesh_1m.ply"
MITSUBA_VARIANTS = ("scalar_spectral", "llvm_ad_spectral")


def log(msg: str) -> None:
    print(msg, flush=True)


def show(cmd: list[str]) -> None:
    log("$ " + shlex.join(str(c) for c in cmd))


def embree_available() -> bool:
    """Embree 3's shared library is installed (Debian: libembree-dev)."""
    out = subprocess.run(["ldconfig", "-p"], capture_output=True, text=True).stdout
    return "libembree3.so " in out


def build_prism() -> pathlib.Path:
    """The default (pure-Rust) release build, the binary users get: its BVH rows are measured
    with it. A build with the `embree` feature compiles the BVH path differently (9% slower on
    the Cornell box, measured), so that build serves only the Embree rows."""
    cmd = ["cargo", "build", "--release", "--quiet"]
    show(cmd)
    subprocess.run(cmd, cwd=ROOT, check=True)
    return ROOT / "target/release/prism"


def build_prism_embree() -> pathlib.Path:
    """A release build with the `embree` feature, in target/embree (beside the default build)."""
    cmd = ["cargo", "build", "--release", "--quiet", "--features", "embree", "--target-dir", "target/embree"]
    show(cmd)
    subprocess.run(cmd, cwd=ROOT, check=True)
    return ROOT / "target/embree/release/prism"


def ensure_mesh(python: str) -> None:
    if not MESH_PLY.exists():
        cmd = [python, str(ROOT / "tools/bench/make_mesh.py"), "-o", str(MESH_PLY)]
        show(cmd)
        subprocess.run(cmd, check=True)


def mitsuba_env() -> dict[str, str]:
    """The environment for Mitsuba's LLVM variant: libLLVM >= 19 (Debian's default 15 fails)."""
    env = dict(os.environ)
    if "DRJIT_LIBLLVM_PATH" not in env and LLVM19.exists():
        env["DRJIT_LIBLLVM_PATH"] = str(LLVM19)
    return env


def llvm_error(variant: str, error: str) -> str:
    """`error` of a failed Mitsuba run, with the likely cause first when the LLVM variant failed
    without libLLVM 19 (its own message is an LLVM code-generation dump that does not say so)."""
    if variant.startswith("llvm") and "DRJIT_LIBLLVM_PATH" not in os.environ and not LLVM19.exists():
        return (f"{LLVM19} is missing: Mitsuba's LLVM variants need libLLVM >= 19 "
                f"(Debian: apt-get install -y libllvm19; tools/bench/run_all.sh installs it). {error}")
    return error


def measured(
    cmd: list[str], env: dict[str, str] | None = None, timeout: float = 1800.0
) -> tuple[int, str, str, float, float]:
    """Runs `cmd`; returns (exit code, stdout, stderr, peak RSS in MiB, wall seconds). The peak
    RSS is this child's own (wait4), not the maximum over all children so far. A child still
    running after `timeout` seconds is killed (a hung renderer must not stall the whole run);
    its stderr then says so."""
    show(cmd)
    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        t = time.perf_counter()
        p = subprocess.Popen([str(c) for c in cmd], stdout=out, stderr=err, env=env)
        timer = threading.Timer(timeout, p.kill)
        timer.start()
        try:
            _, status, rusage = os.wait4(p.pid, 0)
        finally:
            timer.cancel()
        wall = time.perf_counter() - t
        p.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0)
        err.seek(0)
        stderr = err.read()
        if wall >= timeout:
            stderr += f"\nkilled after {timeout:.0f} s"
        return p.returncode, out.read(), stderr, rusage.ru_maxrss / 1024.0, wall


SUMMARY = re.compile(
    r"rendered (\d+)x(\d+) at (\d+|Adaptive\(.*?\)) spp \(([0-9.]+) Msamples\) in ([0-9.]+) s "
    r"\(([0-9.]+) Msamples/s, (\d+) threads?\); scene load ([0-9.]+) s"
)


def prism_render(
    binary: pathlib.Path,
    scene: pathlib.Path,
    spp: int | None,
    threads: int,
    out_exr: pathlib.Path,
    extra: list[str] = (),
) -> dict:
    """One prism render; timings from its summary line (render and scene load, which includes
    the acceleration build), peak RSS from wait4. `spp` None: the scene's or `extra`'s own
    (`--rel-error`: adaptive sampling, whose "spp" is then the mean over the pixels)."""
    cmd = [binary, "render", scene, "-o", out_exr, "-q", *(["--spp", str(spp)] if spp else []),
           "--threads", str(threads), *extra]
    code, _, err, rss, wall = measured(cmd)
    m = SUMMARY.search(err)
    if code != 0 or not m:
        return {"error": err.strip()[-400:], "cmd": shlex.join(map(str, cmd))}
    w, h, render_s, rate = int(m.group(1)), int(m.group(2)), float(m.group(5)), float(m.group(6))
    # Adaptive: the mean spp from the rate and time (3 significant digits each; informative only).
    s = int(m.group(3)) if m.group(3).isdigit() else round(rate * render_s * 1e6 / (w * h), 1)
    return {
        "cmd": shlex.join(map(str, cmd)),
        "width": w,
        "height": h,
        "spp": s,
        "threads": int(m.group(7)),
        "render_s": render_s,
        "load_s": float(m.group(8)),
        "msamples_per_s": w * h * s / render_s / 1e6,
        "peak_rss_mib": rss,
        "wall_s": wall,
    }


def export_scene(binary: pathlib.Path, scene: pathlib.Path, out_dir: pathlib.Path) -> None:
    if out_dir.exists():
        shutil.rmtree(out_dir)
    cmd = [binary, "export", scene, "-o", out_dir]
    show(cmd)
    subprocess.run([str(c) for c in cmd], check=True)


def mitsuba_render(
    python: str,
    export_dir: pathlib.Path,
    variant: str,
    spp: int,
    threads: int,
    repeats: int,
    seed: int = 1,
    save_exr: pathlib.Path | None = None,
) -> dict:
    """Mitsuba 3 in a fresh worker process (tools/bench/mitsuba_worker.py)."""
    cmd = [python, ROOT / "tools/bench/mitsuba_worker.py", export_dir, "--variant", variant, "--spp", str(spp),
           "--threads", str(threads), "--repeats", str(repeats), "--seed", str(seed)]
    if save_exr:
        cmd += ["--save-exr", save_exr]
    code, out, err, rss, wall = measured(cmd, env=mitsuba_env())
    try:
        res = worker_json(out)
    except (IndexError, json.JSONDecodeError):
        return {"error": llvm_error(variant, (err.strip() or out.strip())[-400:]), "cmd": shlex.join(map(str, cmd))}
    best = min(res["render_s"])
    res.update(
        cmd=shlex.join(map(str, cmd)),
        best_render_s=best,
        msamples_per_s=res["width"] * res["height"] * spp / best / 1e6,
        peak_rss_mib=rss,
        wall_s=wall,
    )
    return res


def machine_info() -> dict:
    info = {"cpus": os.cpu_count(), "load_average": os.getloadavg(), "python": sys.version.split()[0]}
    try:
        model = next(l for l in pathlib.Path("/proc/cpuinfo").read_text().splitlines() if l.startswith("model name"))
        info["cpu"] = model.split(":", 1)[1].strip()
    except (OSError, StopIteration):
        pass
    return info


def worker_json(out: str) -> dict:
    """The JSON line a worker prints last. Mitsuba's coloured log output can leave an ANSI reset
    sequence in front of it on the same line."""
    line = out.strip().splitlines()[-1]
    return json.loads(line[line.index("{"):] if "{" in line else line)


def mitsuba_ladder(
    python: str,
    export_dir: pathlib.Path,
    variant: str,
    spps: list[int],
    threads: int,
    save_dir: pathlib.Path,
    seed: int = 1,
    warmup: bool = True,
    sampler: str | None = None,
) -> dict:
    """One timed Mitsuba render per spp of `spps`, images in save_dir/spp_N.exr; render_s is
    keyed by str(spp). `warmup` False skips the untimed warm-ups (for references); `sampler`
    replaces the export's sampler plugin."""
    cmd = [python, ROOT / "tools/bench/mitsuba_worker.py", export_dir, "--variant", variant,
           "--ladder", ",".join(map(str, spps)), "--save-dir", save_dir, "--threads", str(threads), "--seed", str(seed)]
    if not warmup:
        cmd.append("--no-warmup")
    if sampler:
        cmd += ["--sampler", sampler]
    code, out, err, _, _ = measured(cmd, env=mitsuba_env())
    try:
        return worker_json(out)
    except (IndexError, json.JSONDecodeError):
        return {"error": llvm_error(variant, (err.strip() or out.strip())[-400:] or f"exit code {code}")}
