"""docs/images/sensor_cameras.png: one scene through three named cameras and an 850 nm NIR band.

The scene: six flat patches under a uniform 6500 K blackbody sky, rendered 360–1000 nm. Their
reflectances are illustrative curves written below (not measurements): two greens that look
alike to the eye but differ past 700 nm (a leaf-like red edge, and a paint that stays dark), a
red, a blue, a white and a black dye that is transparent in the NIR (so it reads bright there).

Top row: each camera's white-balanced camera RGB (camera.R/G/B, shown as if it were sRGB: what
the sensor records differs between cameras), and the NIR band (nir.Y of configs/sensors/rgb_nir.ron,
a Gaussian at 850 nm, 40 nm FWHM). Bottom row: each camera's colour-corrected sRGB
(corrected.R/G/B, through its least-squares ColorChecker matrix), and CIE 1931 linear sRGB for
reference. Each panel is scaled so that the white patch reads 0.9 in its green (or NIR) channel.

    tools/.venv/bin/python tools/make_sensor_figure.py [-o docs/images/sensor_cameras.png] [--spp 64]
"""

from __future__ import annotations

import argparse
import pathlib
import subprocess
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from prism_tools.images import read_channels, srgb_encode  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
CAMERAS = [
    ("Canon EOS 5D Mk IV", "configs/sensors/canon_eos_5d_mkiv.ron"),
    ("Nikon D810", "configs/sensors/nikon_d810.ron"),
    ("Sony ILCE-7M3 (rgb_nir)", "configs/sensors/rgb_nir.ron"),
]
# (name, [(nm, reflectance), ...]): illustrative curves, linear between the points.
PATCHES = [
    ("leaf green", [(360, 0.04), (500, 0.05), (550, 0.14), (600, 0.07), (680, 0.05), (740, 0.45), (1000, 0.5)]),
    ("paint green", [(360, 0.04), (500, 0.06), (550, 0.15), (600, 0.07), (680, 0.04), (740, 0.04), (1000, 0.05)]),
    ("red", [(360, 0.05), (570, 0.06), (610, 0.55), (1000, 0.7)]),
    ("blue", [(360, 0.1), (450, 0.45), (500, 0.3), (560, 0.05), (700, 0.04), (800, 0.3), (1000, 0.6)]),
    ("white", [(360, 0.85), (1000, 0.88)]),
    ("NIR-bright black", [(360, 0.03), (700, 0.03), (780, 0.5), (1000, 0.8)]),
]
COLS, ROWS, PATCH, GAP, DIST = 3, 2, 1.0, 0.2, 30.0


def scene(spp: int) -> str:
    width, height = COLS * PATCH + (COLS + 1) * GAP, ROWS * PATCH + (ROWS + 1) * GAP
    fov = np.degrees(2 * np.arctan(0.5 * width / DIST))
    mats, shapes = [], []
    for i, (name, pts) in enumerate(PATCHES):
        pairs = ", ".join(f"({w}, {v})" for w, v in pts)
        mats.append(f'"{name}": Diffuse(reflectance: Tabulated([{pairs}])),')
        col, row = i % COLS, i // COLS
        x = -width / 2 + GAP + PATCH / 2 + col * (PATCH + GAP)
        y = height / 2 - GAP - PATCH / 2 - row * (PATCH + GAP)
        shapes.append(
            f'(shape: Rectangle, material: "{name}", to_world: [Scale(({PATCH / 2}, {PATCH / 2}, 1)), Translate(({x}, {y}, 0))]),'
        )
    px = 40
    return f"""(
    camera: (fov: {fov:.6f}, fov_axis: X, to_world: [LookAt(origin: (0, 0, {DIST}), target: (0, 0, 0), up: (0, 1, 0))]),
    film: (width: {round(width * px)}, height: {round(height * px)}, filter: Box()),
    sampler: (spp: {spp}, seed: 1),
    spectral: (range: (360, 1000), sampling: Sensor, wavelengths: 8),
    materials: {{ {" ".join(mats)} }},
    shapes: [{" ".join(shapes)}],
    emitters: [Constant(radiance: Scaled(4e-5, Blackbody(6500)))],
)"""


def render(prism: str, scene_file: pathlib.Path, sensor: str, out: pathlib.Path) -> dict[str, np.ndarray]:
    subprocess.run([prism, "render", str(scene_file), "--sensor", str(ROOT / sensor), "-o", str(out), "-q"], check=True)
    return read_channels(out)


def white_level(img: np.ndarray) -> float:
    """The white patch's (index 4) mean, from its central pixels."""
    h, w = img.shape[:2]
    cy, cx = int(h * 0.73), int(w * 0.5)
    return float(np.mean(img[cy - 5 : cy + 5, cx - 5 : cx + 5]))


def panel(ch: dict[str, np.ndarray], prefix: str) -> np.ndarray:
    rgb = np.stack([ch[prefix + c] for c in "RGB"], axis=-1)
    return np.clip(srgb_encode(0.9 * rgb / white_level(rgb[..., 1])), 0, 1)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--out", default=str(ROOT / "docs/images/sensor_cameras.png"))
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--prism", default=str(ROOT / "target/release/prism"))
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        tmp = pathlib.Path(tmp)
        scene_file = tmp / "patches.ron"
        scene_file.write_text(scene(args.spp))
        renders = [(label, render(args.prism, scene_file, s, tmp / f"{k}.exr")) for k, (label, s) in enumerate(CAMERAS)]
    fig, axes = plt.subplots(2, 4, figsize=(10, 3.9), constrained_layout=True)
    for k, (label, ch) in enumerate(renders):
        axes[0, k].imshow(panel(ch, "camera."))
        axes[0, k].set_title(f"{label}\ncamera RGB", fontsize=8)
        axes[1, k].imshow(panel(ch, "corrected."))
        axes[1, k].set_title(f"{label}\ncolour-corrected sRGB", fontsize=8)
    nir = renders[2][1]["nir.Y"]
    axes[0, 3].imshow(np.clip(srgb_encode(0.9 * nir / white_level(nir)), 0, 1), cmap="gray", vmin=0, vmax=1)
    axes[0, 3].set_title("rgb_nir: NIR band\n850 nm, 40 nm FWHM", fontsize=8)
    axes[1, 3].imshow(panel(renders[2][1], ""))
    axes[1, 3].set_title("CIE 1931 observer\nlinear sRGB", fontsize=8)
    width, height = COLS * PATCH + (COLS + 1) * GAP, ROWS * PATCH + (ROWS + 1) * GAP
    for i, (name, _) in enumerate(PATCHES):
        col, row = i % COLS, i // COLS
        x = (GAP + PATCH / 2 + col * (PATCH + GAP)) / width
        y = 1 - (GAP + 0.9 * PATCH + row * (PATCH + GAP)) / height
        axes[0, 3].text(x, y, name, transform=axes[0, 3].transAxes, ha="center", fontsize=5.5, color="tab:orange")
    for ax in axes.flat:
        ax.set_xticks([])
        ax.set_yticks([])
    fig.savefig(args.out, dpi=100)
    print(f"wrote {args.out} ({pathlib.Path(args.out).stat().st_size // 1024} KB)")


if __name__ == "__main__":
    main()
