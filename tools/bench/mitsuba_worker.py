"""Renders one prism-exported scene with Mitsuba 3 in a fresh process and prints timings as JSON.

    python tools/bench/mitsuba_worker.py EXPORT_DIR --variant llvm_ad_spectral --spp 16 \
        [--threads 2] [--repeats 3] [--seed 1] [--save-exr OUT.exr]
    python tools/bench/mitsuba_worker.py EXPORT_DIR --variant scalar_spectral --ladder 1,2,4 --save-dir DIR

The second form renders once at each spp of the ladder (each after its own warm-up) and writes
DIR/spp_N.exr: the error-against-time curves of error_time.py.

    python tools/bench/mitsuba_worker.py EXPORT_DIR|cornell_box --variant V --spp 16 --serve

The third form loads the scene, renders one warm-up, prints a JSON line ("ready"), then renders
once per line read from stdin (the line is the seed) and prints each render's seconds as a JSON
line: the interleaved rounds of common.Interleaved, where Mitsuba's renders alternate with
prism's while its scene stays loaded and its kernels compiled. `cornell_box` instead of a folder
is Mitsuba's own `mi.cornell_box()` with a box filter (tools/bench/cornell_throughput.py).

Run by bench.py and error_time.py, one process per (variant, thread count): Dr.Jit fixes its
backend per process, and a fresh process makes the peak RSS that the caller reads with wait4()
this render's own. EXPORT_DIR is `prism export SCENE.ron -o EXPORT_DIR`; the scene dict comes from
tools/prism_tools/mitsuba_scene.py (imported, not copied), so both renderers see the same
geometry, camera, spectra, film and integrator settings.

Timings: `load_s` is mi.load_dict (scene construction including Mitsuba's acceleration build,
on all cores whatever --threads says: see below);
then one untimed warm-up render at the same spp (the LLVM variant compiles its kernels there;
Dr.Jit also caches them on disk), then `repeats` timed renders whose image is copied to host
memory inside the timer, so lazily evaluated JIT work is counted.
"""

from __future__ import annotations

import argparse
import json
import pathlib
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("export_dir", type=pathlib.Path)
    ap.add_argument("--variant", required=True)
    ap.add_argument("--spp", type=int, help="spp of the timed renders (or give --ladder)")
    ap.add_argument("--ladder", help="comma-separated spp list: one timed render at each")
    ap.add_argument("--save-dir", type=pathlib.Path, help="with --ladder: write spp_N.exr here")
    ap.add_argument("--no-warmup", action="store_true", help="with --ladder: no warm-up renders (for untimed references)")
    ap.add_argument("--threads", type=int)
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--sampler", help="Mitsuba sampler plugin instead of the export's (e.g. ldsampler)")
    ap.add_argument("--save-exr", type=pathlib.Path, help="write the last render's RGB here")
    ap.add_argument("--serve", action="store_true", help="render once per seed read from stdin (see above)")
    args = ap.parse_args()

    import drjit as dr
    import mitsuba as mi
    import numpy as np

    mi.set_variant(args.variant)
    from prism_tools.mitsuba_scene import convert, load

    ladder = [int(x) for x in args.ladder.split(",")] if args.ladder else None
    if not ladder and not args.spp:
        ap.error("give --spp or --ladder")
    t0 = time.perf_counter()
    if str(args.export_dir) == "cornell_box":
        scene_dict = mi.cornell_box()
        scene_dict["sensor"]["film"]["rfilter"] = {"type": "box"}
        scene_dict["sensor"]["sampler"]["sample_count"] = args.spp or ladder[0]
    else:
        scene_dict = convert(load(args.export_dir / "scene.json"), spp=args.spp or ladder[0], seed=args.seed)
    if args.sampler:
        scene_dict["sensor"]["sampler"]["type"] = args.sampler
    scene = mi.load_dict(scene_dict)
    dr.sync_thread()
    load_s = time.perf_counter() - t0
    if args.threads:
        # Mitsuba 3 runs its render loop (scalar) and its JIT kernels (LLVM) on Dr.Jit's pool.
        # Set only after loading: mi.load_dict of a scene with an environment map never returns
        # with a pool of one thread (Mitsuba 3.9.1 scalar_spectral), so loading always uses the
        # default pool, one thread per core.
        dr.set_thread_count(args.threads)
    if ladder:
        args.save_dir.mkdir(parents=True, exist_ok=True)
        times, actual = {}, {}
        for spp in ladder:
            if not args.no_warmup:
                np.asarray(mi.render(scene, spp=spp, seed=args.seed + 1000))  # warm-up (LLVM compiles)
            t = time.perf_counter()
            img = np.asarray(mi.render(scene, spp=spp, seed=args.seed))
            times[spp] = time.perf_counter() - t
            # Some samplers round the count (Mitsuba's ldsampler to a power of four).
            actual[spp] = scene.sensors()[0].sampler().sample_count()
            mi.Bitmap(img[..., :3]).write(str(args.save_dir / f"spp_{spp}.exr"))
        print(json.dumps({"variant": args.variant, "threads": dr.thread_count(), "load_s": load_s, "render_s": times,
                          "spp_rendered": actual}))
        return

    np.asarray(mi.render(scene, spp=args.spp, seed=args.seed + 1000))  # warm-up
    film = scene.sensors()[0].film().size()
    if args.serve:
        serve(scene, args, dr.thread_count(), (int(film[0]), int(film[1])), load_s)
        return
    times = []
    img = None
    for k in range(args.repeats):
        t = time.perf_counter()
        img = np.asarray(mi.render(scene, spp=args.spp, seed=args.seed + k))
        times.append(time.perf_counter() - t)
    if args.save_exr:
        mi.Bitmap(img[..., :3]).write(str(args.save_exr))
    print(json.dumps({
        "variant": args.variant,
        "threads": dr.thread_count(),
        "width": int(film[0]),
        "height": int(film[1]),
        "spp": args.spp,
        "load_s": load_s,
        "render_s": times,
    }))


def serve(scene, args, threads: int, size: tuple[int, int], load_s: float) -> None:
    """The `--serve` loop: one timed render per stdin line (a seed); with --save-exr, each
    render's RGB overwrites that file (the caller compares the last one)."""
    import mitsuba as mi
    import numpy as np

    print(json.dumps({"ready": True, "variant": args.variant, "threads": threads, "width": size[0],
                      "height": size[1], "spp": args.spp, "load_s": load_s}), flush=True)
    for line in sys.stdin:
        seed = int(line)
        t = time.perf_counter()
        img = np.asarray(mi.render(scene, spp=args.spp, seed=seed))
        seconds = time.perf_counter() - t
        if args.save_exr:
            mi.Bitmap(img[..., :3]).write(str(args.save_exr))
        print(json.dumps({"render_s": seconds, "seed": seed}), flush=True)


if __name__ == "__main__":
    main()
