"""Render one prism scene file with prism and with Mitsuba 3 (its conversion of prism's export),
K independent seeds each, and judge whether the two images have the same expectation.

Verdict: `bias_test` (prism_tools.stats) on the per-tile means of the K renders of each, Welch
t-tests per tile and channel, Holm-corrected over all of them. A corrected p-value below alpha
is bias, and a failure; Monte Carlo noise alone fails with probability at most alpha. Also
reported: per-channel image means with 95% confidence intervals, the relMSE of prism's K-render
mean against Mitsuba's (noise of both included, so a number to watch, not a verdict), and a
side-by-side PNG with false-colour error maps.

    tools/.venv/bin/python tools/compare.py scenes/materials/diffuse.ron --renders 8 --spp 16 --png out.png
"""

from __future__ import annotations

import argparse
import pathlib
import sys
import tempfile
import time
from dataclasses import dataclass

import numpy as np

from . import mitsuba_scene as ms
from . import renderers, stats
from .figure import write_figure


@dataclass
class Settings:
    """How hard to look: K renders of `spp` samples per pixel each (None: the scene's spp), an
    8×8 tile grid, family-wise error rate alpha."""

    renders: int = 8
    spp: int | None = None
    grid: int = 8
    alpha: float = 1e-3


@dataclass
class Comparison:
    scene: str
    settings: Settings
    channels: list[str]
    prism_mean: np.ndarray
    prism_ci: np.ndarray
    mitsuba_mean: np.ndarray
    mitsuba_ci: np.ndarray
    rel_mse: float
    bias: stats.BiasResult
    prism_image: np.ndarray
    mitsuba_image: np.ndarray
    seconds: dict[str, float]
    #: How prism rendered: "module" (in process) or "binary" (renderers.backend).
    backend: str = "binary"

    @property
    def passed(self) -> bool:
        return not self.bias.biased

    def summary(self) -> str:
        p, r, c, ch = self.bias.worst
        lines = [f"{self.scene}: {'PASS' if self.passed else 'FAIL (bias)'}"]
        lines.append(f"  {self.settings.renders} renders × {self.spp_text()} each; tiles {self.settings.grid}×{self.settings.grid}")
        lines.append("  channel   prism mean ± 95% CI        Mitsuba mean ± 95% CI      prism/Mitsuba")
        for i, name in enumerate(self.channels):
            ratio = self.prism_mean[i] / self.mitsuba_mean[i] if self.mitsuba_mean[i] else float("nan")
            lines.append(
                f"  {name:<7} {self.prism_mean[i]:.5f} ± {self.prism_ci[i]:.5f}      "
                f"{self.mitsuba_mean[i]:.5f} ± {self.mitsuba_ci[i]:.5f}      {ratio:.4f}"
            )
        rel = self.bias.rel_diff[r, c, self.channels.index(ch)] if ch else 0.0
        lines.append(f"  bias test: smallest Holm-adjusted p = {p:.3g} (tile row {r}, column {c}, {ch}: prism {rel:+.1%} vs Mitsuba); alpha {self.settings.alpha:g}")
        lines.append(f"  relMSE (prism mean vs Mitsuba mean, noise included): {self.rel_mse:.4g}")
        lines.append(f"  time: prism {self.seconds['prism']:.1f} s ({self.backend}), Mitsuba {self.seconds['mitsuba']:.1f} s")
        return "\n".join(lines)

    def spp_text(self) -> str:
        return f"{self.settings.spp} spp" if self.settings.spp else "the scene's spp"


def compare(scene: str | pathlib.Path, settings: Settings | None = None, prism_bin: pathlib.Path | None = None) -> Comparison:
    """Renders `scene` with both renderers and compares them: prism through the binary
    `prism_bin`, or with None the default backend (renderers.backend). Raises `mitsuba_scene.Unsupported`
    (before rendering anything) when Mitsuba cannot render the scene the same way."""
    settings = settings or Settings()
    if settings.renders < 2:
        raise ValueError("at least 2 renders per renderer are needed to estimate the noise")
    scene = pathlib.Path(scene)
    with tempfile.TemporaryDirectory(prefix="prism-export-") as tmp:
        exported = renderers.export(prism_bin or renderers.prism_binary(), scene, pathlib.Path(tmp))
        channels = renderers.channels(exported)
        t0 = time.perf_counter()
        mitsuba = renderers.MitsubaRenderer(exported, settings.spp)
        mitsuba_renders = [mitsuba.render(seed, channels) for seed in range(settings.renders)]
        t1 = time.perf_counter()
    prism = renderers.PrismRenderer(scene, settings.spp, prism_bin)
    prism_renders = [prism.render(seed, channels) for seed in range(settings.renders)]
    t2 = time.perf_counter()
    pm, pci = stats.mean_ci(prism_renders)
    mm, mci = stats.mean_ci(mitsuba_renders)
    prism_image, mitsuba_image = np.mean(prism_renders, axis=0), np.mean(mitsuba_renders, axis=0)
    return Comparison(
        scene=str(scene),
        settings=settings,
        channels=channels,
        prism_mean=pm,
        prism_ci=pci,
        mitsuba_mean=mm,
        mitsuba_ci=mci,
        rel_mse=stats.rel_mse(prism_image, mitsuba_image),
        bias=stats.bias_test(mitsuba_renders, prism_renders, channels, grid=settings.grid, alpha=settings.alpha),
        prism_image=prism_image,
        mitsuba_image=mitsuba_image,
        seconds={"mitsuba": t1 - t0, "prism": t2 - t1},
        backend=prism.backend,
    )


def parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0], epilog="Exit status: 0 agree, 1 bias, 2 Mitsuba cannot render the scene.")
    ap.add_argument("scene", type=pathlib.Path, help="a prism scene file (RON)")
    ap.add_argument("--renders", "-k", type=int, default=Settings.renders, help="independent renders per renderer (default %(default)s)")
    ap.add_argument("--spp", type=int, help="samples per pixel of each render (default: the scene's)")
    ap.add_argument("--grid", type=int, default=Settings.grid, help="tiles per side for the bias test (default %(default)s)")
    ap.add_argument("--alpha", type=float, default=Settings.alpha, help="family-wise error rate (default %(default)g)")
    ap.add_argument("--png", type=pathlib.Path, help="write the side-by-side figure here")
    ap.add_argument("--prism", type=pathlib.Path, help="render with this prism binary (default: $PRISM_BIN, else the prism Python module where it imports, else target/release/prism)")
    return ap


def main(argv: list[str] | None = None) -> int:
    args = parser().parse_args(argv)
    settings = Settings(renders=args.renders, spp=args.spp, grid=args.grid, alpha=args.alpha)
    try:
        result = compare(args.scene, settings, args.prism)
    except ms.Unsupported as e:
        print(f"{args.scene}: Mitsuba cannot render this scene the same way: {e}", file=sys.stderr)
        return 2
    print(result.summary())
    if args.png:
        write_figure(result, args.png)
        print(f"  figure: {args.png}")
    return 0 if result.passed else 1
