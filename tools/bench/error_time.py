"""Error against time: relMSE at increasing spp, plotted against render seconds, for prism (and
its sampler and wavelength variants) and Mitsuba 3, on the benchmark scenes.

    tools/.venv/bin/python tools/bench/error_time.py            # full: docs/bench/error_time.*
    tools/.venv/bin/python tools/bench/error_time.py --quick    # smoke check: out/bench/quick/

Curves (one render per spp of a doubling ladder, render time only, scene loading excluded):
- prism, BVH, at its defaults (padded Owen-scrambled Sobol sampler, 8 wavelengths per path,
  visible-importance wavelength sampling): `prism`;
- prism variants, one change each: `--simd off` (the scalar integrator instead of the packet
  kernel: `prism scalar`), `--sampler independent` (Mitsuba's default sampler),
  `--wavelengths 4` (Mitsuba's count), `--wavelengths 1`, `--wavelength-sampling uniform`,
  and, on the scenes whose file turns caustic light tracing on (materials), `--caustics off`;
  and with Mitsuba's settings (independent, 4 wavelengths, no light tracing): `prism as
  Mitsuba`;
- prism with adaptive sampling (`prism adaptive`: a ladder of `--rel-error` targets, the
  adaptive defaults min 16, max 4096, Y; caustic light tracing as the scene file sets it, its
  light paths per camera sample of the estimates), its "spp" the mean over the pixels; and,
  on the materials scene, `prism adaptive without caustics`;
- Mitsuba 3.9.1 `scalar_spectral` and `llvm_ad_spectral` on the exported scene, each with its
  default `independent` sampler and with its low-discrepancy `ldsampler` (each spp after a
  warm-up render, so the LLVM variant's kernel compilation is not counted).

relMSE = mean over pixels and R, G, B of (x − ref)² / (ref² + 0.01). Each renderer is measured
against its own high-spp reference (prism's: its defaults; Mitsuba's: llvm_ad_spectral), so
the curves show variance against time, not the small bias between the two renderers (that is
validated elsewhere); the relMSE between the two references is printed and stored as a check.
Equal-error speedups: each curve gets a least-squares power law log relMSE = a + b log t; the
time each needs to reach the error that `prism` reaches at the middle of its ladder is read off
the fits, and speedup = that time for the curve / the time for `prism` (> 1: prism is faster;
for a prism variant, < 1 means the variant beats the default settings).
Writes error_time.csv (every point), error_time_speedups.csv/.md and error_time.png.
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import os
import pathlib
import sys
import tempfile

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import common  # noqa: E402
from common import ROOT, SCENES, log  # noqa: E402

# (max spp of the ladder, reference spp) per scene.
FULL = {"cornell": (256, 4096), "materials": (128, 2048), "mesh": (64, 1024)}
QUICK = {"cornell": (4, 32), "materials": (4, 32), "mesh": (2, 16)}
# Sampler and wavelengths are always named: scenes/cornell.ron pins Mitsuba's (independent, 4).
DEFAULTS = ["--sampler", "sobol", "--wavelengths", "8"]
PRISM_VARIANTS = {
    "prism": DEFAULTS,
    "prism independent": ["--sampler", "independent", "--wavelengths", "8"],
    "prism 4 wavelengths": ["--sampler", "sobol", "--wavelengths", "4"],
    "prism 1 wavelength": ["--sampler", "sobol", "--wavelengths", "1"],
    "prism uniform wavelengths": [*DEFAULTS, "--wavelength-sampling", "uniform"],
    "prism without caustics": [*DEFAULTS, "--caustics", "off"],
    "prism as Mitsuba": ["--sampler", "independent", "--wavelengths", "4", "--caustics", "off"],
    "prism scalar": [*DEFAULTS, "--simd", "off"],
}
# Adaptive sampling (issue 26 item 3): a ladder of `--rel-error` targets in place of spp, at the
# adaptive defaults (min 16, max 4096, Y). Caustic light tracing stays as the scene sets it: its
# light paths are counted per camera sample the estimates took.
ADAPTIVE = {
    "prism adaptive": [*DEFAULTS],
    "prism adaptive without caustics": [*DEFAULTS, "--caustics", "off"],
}
REL_ERRORS = {"full": [0.4, 0.28, 0.2, 0.14, 0.1], "quick": [0.4, 0.28]}
# Variants that only differ from `prism` on some scenes, run on those alone.
VARIANT_SCENES = {
    "prism without caustics": {"materials"},
    "prism adaptive without caustics": {"materials"},
}
MITSUBA_SAMPLERS = ("independent", "ldsampler")


def read_rgb(path: pathlib.Path) -> np.ndarray:
    import OpenImageIO as oiio

    inp = oiio.ImageInput.open(str(path))
    if inp is None:
        raise RuntimeError(f"cannot read {path}: {oiio.geterror()}")
    names = list(inp.spec().channelnames)
    data = inp.read_image("float")
    inp.close()
    return np.stack([data[..., names.index(c)] for c in "RGB"], axis=-1).astype(np.float64)


def relmse(img: np.ndarray, ref: np.ndarray) -> float:
    return float(np.mean((img - ref) ** 2 / (ref**2 + 0.01)))


# The floor of adaptive sampling's relative error (its default `floor`): darker pixels count
# their absolute error against it.
Y_FLOOR = 1e-3
# Rec. 709 luminance of linear sRGB, the primaries of both renderers' R, G, B.
LUMA = np.array([0.2126, 0.7152, 0.0722])


def p90_rel(img: np.ndarray, ref: np.ndarray) -> float:
    """The 90th percentile over pixels of |Y − Y_ref| / max(Y_ref, floor): "every pixel to a
    relative error" as a user asks of adaptive sampling (`--rel-error`), where the mean relMSE
    above weighs the bright pixels. A uniform sampler meets it only when its worst tenth of
    pixels does."""
    y, y_ref = img @ LUMA, ref @ LUMA
    return float(np.percentile(np.abs(y - y_ref) / np.maximum(y_ref, Y_FLOOR), 90))


METRICS = {"relmse": "mean relMSE", "p90_rel": "90th percentile of per-pixel relative error of Y"}


def errors(img: np.ndarray, ref: np.ndarray) -> dict:
    return {"relmse": relmse(img, ref), "p90_rel": p90_rel(img, ref)}


def ladder(max_spp: int) -> list[int]:
    return [2**k for k in range(int(math.log2(max_spp)) + 1)]


def fit(points: list[tuple[float, float]]) -> tuple[float, float] | None:
    """Least-squares (a, b) of log err = a + b log t over (seconds, relMSE) points."""
    pts = [(math.log(t), math.log(e)) for t, e in points if t > 0 and e > 0]
    if len(pts) < 2:
        return None
    x, y = np.array(pts).T
    b, a = np.polyfit(x, y, 1)
    return float(a), float(b)


def time_for(f: tuple[float, float], err: float) -> float:
    a, b = f
    return math.exp((math.log(err) - a) / b)


def run_scene(name: str, binary: pathlib.Path, python: str, max_spp: int, ref_spp: int, threads: int, tmp: pathlib.Path,
              variants: list[str], rel_errors: list[float]):
    scene = SCENES[name]
    spps = ladder(max_spp)
    rows: list[dict] = []
    ref_exr = tmp / f"{name}_ref_prism.exr"
    r = common.prism_render(binary, scene, ref_spp, threads, ref_exr, [*DEFAULTS, "--seed", "12345"])
    if "error" in r:
        raise RuntimeError(r["error"])
    ref_prism = read_rgb(ref_exr)
    for label, extra in PRISM_VARIANTS.items():
        if label not in variants or name not in VARIANT_SCENES.get(label, {name}):
            continue
        for spp in spps:
            exr = tmp / f"{name}_p.exr"
            load = round(os.getloadavg()[0], 2)
            r = common.prism_render(binary, scene, spp, threads, exr, extra)
            if "error" in r:
                log(f"  {label}: {r['error']}")
                break
            rows.append({"scene": name, "renderer": label, "spp": spp, "seconds": r["render_s"],
                         **errors(read_rgb(exr), ref_prism), "load_1min": load})
    for label, extra in ADAPTIVE.items():
        if label not in variants or name not in VARIANT_SCENES.get(label, {name}):
            continue
        for e in rel_errors:
            exr = tmp / f"{name}_a.exr"
            load = round(os.getloadavg()[0], 2)
            r = common.prism_render(binary, scene, None, threads, exr, [*extra, "--rel-error", str(e)])
            if "error" in r:
                log(f"  {label}: {r['error']}")
                break
            # "spp": the mean over the pixels.
            rows.append({"scene": name, "renderer": label, "spp": r["spp"], "seconds": r["render_s"],
                         **errors(read_rgb(exr), ref_prism), "load_1min": load})
    export = tmp / f"export_{name}"
    common.export_scene(binary, scene, export)
    ref_mi = None
    # A seed of its own: with the ladder's seed, the reference's first samples would be the
    # ladder's own, correlated with them, and the error would look too small.
    res = common.mitsuba_ladder(python, export, "llvm_ad_spectral", [ref_spp], threads, tmp / f"{name}_mref",
                                seed=12345, warmup=False)
    if "error" in res:
        log(f"  Mitsuba reference unavailable: {res['error'].splitlines()[-1]}")
    else:
        ref_mi = read_rgb(tmp / f"{name}_mref" / f"spp_{ref_spp}.exr")
        for variant in common.MITSUBA_VARIANTS:
            for sampler in MITSUBA_SAMPLERS:
                label = f"mitsuba {variant}" + ("" if sampler == "independent" else f" {sampler}")
                d = tmp / f"{name}_{variant}_{sampler}"
                load = round(os.getloadavg()[0], 2)
                res = common.mitsuba_ladder(python, export, variant, spps, threads, d, sampler=sampler)
                if "error" in res:
                    log(f"  {label}: {res['error'].splitlines()[-1]}")
                    continue
                seen = set()
                for spp in spps:
                    # A sampler that rounds the count (ldsampler: powers of four) renders some
                    # rungs twice; each rendered count is one point.
                    if res["spp_rendered"][str(spp)] in seen:
                        continue
                    seen.add(res["spp_rendered"][str(spp)])
                    rows.append({"scene": name, "renderer": label, "spp": res["spp_rendered"][str(spp)],
                                 "seconds": res["render_s"][str(spp)], **errors(read_rgb(d / f"spp_{spp}.exr"), ref_mi),
                                 "load_1min": load})
    cross = relmse(ref_mi, ref_prism) if ref_mi is not None else None
    return rows, cross


def speedups(rows: list[dict], scene: str, metric: str = "relmse") -> list[dict]:
    curves: dict[str, list[tuple[float, float]]] = {}
    for r in rows:
        if r["scene"] == scene and metric in r:
            curves.setdefault(r["renderer"], []).append((r["seconds"], r[metric]))
    base = curves.get("prism")
    fb = fit(base) if base else None
    if not fb:
        return []
    target = sorted(e for _, e in base)[len(base) // 2]
    t_base = time_for(fb, target)
    out = []
    for label, pts in curves.items():
        f = fit(pts)
        if not f:
            continue
        t = time_for(f, target)
        out.append({"scene": scene, "metric": metric, "renderer": label, "slope": f[1], "target": target,
                    "seconds_to_target": t, "speedup_of_prism": t / t_base})
    return out


def plot(rows: list[dict], scenes: list[str], path: pathlib.Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker

    # One row of panels per error measure.
    fig, axes = plt.subplots(len(METRICS), len(scenes), figsize=(5.2 * len(scenes), 4.4 * len(METRICS)),
                             squeeze=False)
    # One colour per renderer in every panel (the default cycle of ten repeats past ten curves).
    palette = plt.get_cmap("tab20").colors
    colour = {label: palette[i % len(palette)] for i, label in enumerate(dict.fromkeys(r["renderer"] for r in rows))}
    panels = [(ax, scene, metric) for row, metric in zip(axes, METRICS) for ax, scene in zip(row, scenes)]
    for ax, scene, metric in panels:
        labels = dict.fromkeys(r["renderer"] for r in rows if r["scene"] == scene and metric in r)
        for label in labels:
            pts = sorted((r["seconds"], r[metric]) for r in rows
                         if r["scene"] == scene and r["renderer"] == label and metric in r)
            style = "--" if label.startswith("mitsuba") else "-"
            ax.loglog(*zip(*pts), style, marker="o", ms=3, label=label, color=colour[label])
        ax.set_title(scene)
        ax.set_xlabel("render seconds")
        ax.set_ylabel(METRICS[metric])
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
        # Log axes label minor ticks too, which overlap on short ranges.
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def write_outputs(out: pathlib.Path, rows: list[dict], scenes: list[str], cross: dict, quiet: bool = False) -> None:
    """Every output file, from the rows so far (rewritten after each scene, so a run cut short keeps its finished scenes)."""
    with open(out / "error_time.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["scene", "renderer", "spp", "seconds", *METRICS, "load_1min"])
        w.writeheader()
        w.writerows(rows)
    sp = [s for name in scenes for metric in METRICS for s in speedups(rows, name, metric)]
    with open(out / "error_time_speedups.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["scene", "metric", "renderer", "slope", "target", "seconds_to_target",
                                          "speedup_of_prism"])
        w.writeheader()
        w.writerows(sp)
    plot(rows, scenes, out / "error_time.png")
    md = ["# Error against time", "", f"Command: `tools/bench/error_time.py {' '.join(sys.argv[1:])}`",
          f"Machine: {json.dumps(common.machine_info())} (at the end)", "",
          "Equal-error speedup: time the row needs to reach the target error over the time `prism` needs "
          "(power-law fits; > 1 means prism is faster). Slope: fitted d log error / d log t (-1 for relMSE and "
          "-0.5 for a relative error under plain Monte Carlo). Two errors: the mean relMSE of R, G, B, and the "
          "90th percentile of per-pixel relative error of Y (the measure `--rel-error` targets).", ""]
    for name in scenes:
        md += [f"## {name}", "", f"relMSE of Mitsuba's reference against prism's: {cross[name]}", ""]
        for metric, title in METRICS.items():
            rows_m = [s for s in sp if s["scene"] == name and s["metric"] == metric]
            if not rows_m:
                continue
            md += [f"### {title}", "", "| renderer | slope | target | seconds to target | speedup of prism |",
                   "|---|---|---|---|---|"]
            md += [f"| {s['renderer']} | {s['slope']:.2f} | {s['target']:.3g} | {s['seconds_to_target']:.3g} | "
                   f"{s['speedup_of_prism']:.2f} |" for s in rows_m]
            mi_rows = [s for s in rows_m if s["renderer"].startswith("mitsuba")]
            if mi_rows:
                best = min(mi_rows, key=lambda s: s["seconds_to_target"])
                for s in rows_m:
                    if s["renderer"] in ("prism", *ADAPTIVE):
                        md += ["", f"{s['renderer']}'s time to equal error over Mitsuba's best ({best['renderer']}): "
                                   f"**{s['seconds_to_target'] / best['seconds_to_target']:.2f}×**"]
            md.append("")
    (out / "error_time_speedups.md").write_text("\n".join(md))
    if not quiet:
        log("\n".join(md))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="smoke check: a few spp, small references")
    ap.add_argument("--scenes", default="cornell,materials,mesh")
    ap.add_argument("--threads", type=int, default=os.cpu_count())
    ap.add_argument("--max-spp", type=int, help="top of every scene's spp ladder (overrides the table)")
    ap.add_argument("--ref-spp", type=int, help="spp of every scene's references (overrides the table)")
    ap.add_argument("--out", type=pathlib.Path, help="output folder (default docs/bench, or out/bench/quick)")
    ap.add_argument("--variants", help="comma-separated prism curves to run (default all: "
                    + ", ".join([*PRISM_VARIANTS, *ADAPTIVE]) + ")")
    ap.add_argument("--rel-errors", help="the adaptive curve's --rel-error ladder, comma-separated "
                    f"(default {','.join(map(str, REL_ERRORS['full']))}; --quick {','.join(map(str, REL_ERRORS['quick']))})")
    ap.add_argument("--prism", type=pathlib.Path, help="measure this prism binary (no build)")
    args = ap.parse_args()
    known = [*PRISM_VARIANTS, *ADAPTIVE]
    variants = args.variants.split(",") if args.variants else known
    unknown = [v for v in variants if v not in known]
    if unknown or "prism" not in variants:
        ap.error(f"--variants: {unknown or 'prism'} {'unknown' if unknown else 'is required (the speedups are over it)'}; "
                 f"choose from {', '.join(known)}")
    try:
        rel_errors = ([float(x) for x in args.rel_errors.split(",")] if args.rel_errors
                      else REL_ERRORS["quick" if args.quick else "full"])
    except ValueError:
        ap.error(f"--rel-errors: {args.rel_errors!r} is not a comma-separated list of numbers, e.g. 0.2,0.1")
    if not all(0 < e < 10 for e in rel_errors):
        ap.error(f"--rel-errors: {args.rel_errors!r}: each target must be a relative error above 0, e.g. 0.1")
    out = args.out or (ROOT / ("out/bench/quick" if args.quick else "docs/bench"))
    out.mkdir(parents=True, exist_ok=True)
    table = QUICK if args.quick else FULL
    scenes = args.scenes.split(",")
    python = sys.executable
    binary = args.prism or common.build_prism()
    common.ensure_mesh(python)
    rows: list[dict] = []
    cross: dict[str, float | None] = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name in scenes:
            max_spp, ref_spp = table[name]
            max_spp, ref_spp = args.max_spp or max_spp, args.ref_spp or ref_spp
            log(f"== {name}: ladder up to {max_spp} spp, references at {ref_spp} spp, {args.threads} threads")
            r, c = run_scene(name, binary, python, max_spp, ref_spp, args.threads, pathlib.Path(tmp), variants, rel_errors)
            rows += r
            cross[name] = c
            done = scenes[: scenes.index(name) + 1]
            write_outputs(out, rows, done, cross, quiet=True)
    write_outputs(out, rows, scenes, cross)
    log(f"wrote {out}/error_time.csv, error_time_speedups.csv, error_time_speedups.md, error_time.png")


if __name__ == "__main__":
    main()
