"""`prism render`'s command-line overrides and its output files, checked by independent readers.

- Each override (`--spp`, `--seed`, `--sampler`, `--wavelengths`, `--wavelength-sampling`,
  `--clamp`, `--accel`) takes effect and beats the scene file: the scene says A, the flag says B;
  the image must be bit-identical to the scene saying B (and differ from A's where the setting
  changes pixels), and the EXR's metadata must record B. `--threads` changes no pixel (renders
  are deterministic at any thread count) and the summary line reports it; `--exposure` is
  checked through the preview.
- `--help` lists every field of `RenderArgs` (read from src/cli/ and the structs it flattens, so a
  new flag is covered).
- The EXR read by OpenImageIO (not by prism's own `exr` crate, and not by a byte search): every
  channel float32, every prism:* attribute present with the value the run used.
- The preview PNG decoded by OpenCV (libpng) equals the EXR's RGB × 2^exposure under the sRGB
  transfer function of colour-science (IEC 61966-2-1), rounded to 8 bits.
- A failed or killed render leaves an existing output byte for byte as it was.
"""

from __future__ import annotations

import os
import pathlib
import re
import signal
import subprocess
import time

import colour
import cv2
import numpy as np
import OpenImageIO as oiio
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]

# A small scene whose pixels depend on every setting under test: a glossy sphere (so the sampler
# and wavelengths change the noise), a bright small light (fireflies for the clamp), a coloured
# floor, and a sky.
SCENE = """(
    camera: (fov: 40, to_world: [LookAt(origin: (0, 1, 4), target: (0, 0.4, 0), up: (0, 1, 0))]),
    film: (width: 24, height: 16, filter: Box()),
    sampler: ({sampler}),
    spectral: ({spectral}),
    integrator: (max_depth: 5{integrator}),
    {accel}
    materials: {{
        "floor": Diffuse(reflectance: Rgb(0.7, 0.4, 0.2)),
        "ball": RoughConductor(material: "Au", alpha: 0.2),
    }},
    shapes: [
        (shape: Rectangle, material: "floor", to_world: [Scale((4, 4, 1)), Rotate(axis: (1, 0, 0), angle: -90)]),
        (shape: Sphere(center: (0, 0.5, 0), radius: 0.5), material: "ball"),
        (shape: Rectangle, emitter: (radiance: Scaled(400, Named("D65"))), to_world: [Scale((0.05, 0.05, 1)), Rotate(axis: (1, 0, 0), angle: 90), Translate((0.8, 2, 0.8))]),
    ],
    emitters: [Constant(radiance: Scaled(0.3, Named("D65")))],
)"""


def scene_text(sampler="spp: 4, seed: 1", spectral="wavelengths: 4", integrator="", accel="") -> str:
    return SCENE.format(sampler=sampler, spectral=spectral, integrator=integrator, accel=accel)


def run_prism(prism_bin, scene: str, out: pathlib.Path, *args: str, check: bool = True) -> subprocess.CompletedProcess:
    path = out.with_suffix(".ron")
    path.write_text(scene)
    p = subprocess.run([str(prism_bin), "render", str(path), "-o", str(out), *args], capture_output=True, text=True)
    if check:
        assert p.returncode == 0, p.stderr
    return p


def read_exr(path: pathlib.Path) -> tuple[oiio.ImageSpec, np.ndarray]:
    inp = oiio.ImageInput.open(str(path))
    assert inp is not None, oiio.geterror()
    spec = inp.spec()
    pixels = inp.read_image(format="float")
    inp.close()
    return spec, np.asarray(pixels)


def attrs(spec: oiio.ImageSpec) -> dict[str, str]:
    return {a.name: a.value for a in spec.extra_attribs if a.name.startswith("prism:")}


# (flag, its value, the scene's own setting, the scene setting that equals the flag, metadata
# key, what the metadata must say, whether the setting changes pixels)
OVERRIDES = [
    ("--spp", "8", dict(sampler="spp: 4, seed: 1"), dict(sampler="spp: 8, seed: 1"), "prism:spp", "8", True),
    ("--seed", "7", dict(sampler="spp: 4, seed: 1"), dict(sampler="spp: 4, seed: 7"), "prism:seed", "7", True),
    (
        "--sampler",
        "independent",
        dict(sampler="kind: Sobol, spp: 4, seed: 1"),
        dict(sampler="kind: Independent, spp: 4, seed: 1"),
        "prism:sampler",
        "Independent",
        True,
    ),
    ("--wavelengths", "8", dict(spectral="wavelengths: 4"), dict(spectral="wavelengths: 8"), "prism:wavelengths", "8 per path", True),
    (
        "--wavelength-sampling",
        "uniform",
        dict(spectral="wavelengths: 4, sampling: Visible"),
        dict(spectral="wavelengths: 4, sampling: Uniform"),
        "prism:wavelengths",
        "Uniform",
        True,
    ),
    ("--clamp", "0.5", dict(integrator=", clamp: 50"), dict(integrator=", clamp: 0.5"), "prism:integrator", "clamp 0.5", True),
    # BruteForce and the BVH find the same hits: the image may not change, the metadata must.
    ("--accel", "brute-force", dict(accel="accel: Bvh,"), dict(accel="accel: BruteForce,"), "prism:accel", "BruteForce", False),
]


@pytest.mark.parametrize("flag,value,scene_has,scene_wants,key,want,changes", OVERRIDES, ids=[o[0] for o in OVERRIDES])
def test_override_takes_effect_and_beats_the_scene(prism_bin, tmp_path, flag, value, scene_has, scene_wants, key, want, changes):
    flagged, reference, plain = tmp_path / "flag.exr", tmp_path / "ref.exr", tmp_path / "plain.exr"
    run_prism(prism_bin, scene_text(**scene_has), flagged, "-q", flag, value)
    run_prism(prism_bin, scene_text(**scene_wants), reference, "-q")
    run_prism(prism_bin, scene_text(**scene_has), plain, "-q")
    spec_f, img_f = read_exr(flagged)
    spec_r, img_r = read_exr(reference)
    spec_p, img_p = read_exr(plain)
    assert want in attrs(spec_f)[key], (key, attrs(spec_f)[key])
    assert attrs(spec_f)[key] == attrs(spec_r)[key]
    assert attrs(spec_p)[key] != attrs(spec_f)[key], f"{flag}: the test's two settings do not differ"
    assert np.array_equal(img_f, img_r), f"{flag} {value} renders differently from the scene saying so"
    if changes:
        assert not np.array_equal(img_f, img_p), f"{flag} {value} changed no pixel"


def test_threads_change_no_pixel_and_are_reported(prism_bin, tmp_path):
    imgs = []
    for t in ["1", "2"]:
        out = tmp_path / f"t{t}.exr"
        p = run_prism(prism_bin, scene_text(), out, "--threads", t)
        assert re.search(rf"\b{t} threads?\)", p.stderr), p.stderr
        imgs.append(read_exr(out)[1])
    assert np.array_equal(*imgs)


def render_args_fields() -> list[str]:
    """The fields of `RenderArgs` in src/cli/ (args.rs), as flags (the positional `scene` left
    out); a `#[command(flatten)]` field stands for the fields of its struct (in src/cli/ or
    src/pipeline/workers.rs, where the worker flags shared with `prism dataset` live)."""
    files = [*sorted((ROOT / "src/cli").glob("*.rs")), ROOT / "src/pipeline/workers.rs"]
    assert any("pub struct RenderArgs" in f.read_text() for f in files), "RenderArgs moved: update this list"
    src = "\n".join(f.read_text() for f in files)

    def fields(struct: str) -> list[str]:
        body = re.search(rf"pub struct {struct} \{{(.*?)\n\}}", src, re.S).group(1)
        found = re.findall(r"^\s*(#\[command\(flatten\)\]\s*)?pub (\w+): ([\w:]+)", body, re.M)
        return [n for flat, name, ty in found for n in (fields(ty.split("::")[-1]) if flat else [name])]

    return ["--" + n.replace("_", "-") for n in fields("RenderArgs") if n != "scene"]


def test_help_lists_every_flag(prism_bin):
    flags = render_args_fields()
    assert {"--seed", "--sampler", "--accel", "--exposure", "--wavelength-sampling"} <= set(flags), flags
    text = subprocess.run([str(prism_bin), "render", "--help"], capture_output=True, text=True, check=True).stdout
    listed = set(re.findall(r"--[a-z][a-z-]*", text))
    missing = [f for f in flags if f not in listed]
    assert not missing, f"render --help lacks {missing}"


def test_exr_is_float32_with_every_attribute(prism_bin, tmp_path):
    out = tmp_path / "out.exr"
    scene = scene_text(sampler="spp: 4, seed: 11", spectral="wavelengths: 8, sampling: Uniform", integrator=", clamp: 20")
    run_prism(prism_bin, scene, out, "-q", "--accel", "brute-force")
    spec, img = read_exr(out)
    # Every channel float32: the spec's per-channel formats when they differ, else its format.
    formats = [str(f) for f in spec.channelformats] or [str(spec.format)] * spec.nchannels
    assert formats == ["float"] * spec.nchannels, formats
    assert {"R", "G", "B", "X", "Y", "Z"} <= set(spec.channelnames)
    assert np.all(np.isfinite(img))
    a = attrs(spec)
    version = re.search(r'^version = "([^"]+)"', (ROOT / "Cargo.toml").read_text(), re.M).group(1)
    assert a["prism:version"] == version
    assert a["prism:scene"] == str(out.with_suffix(".ron"))
    assert a["prism:spp"] == "4" and a["prism:seed"] == "11"
    assert a["prism:sampler"] == "Sobol" and a["prism:accel"] == "BruteForce"
    assert re.fullmatch(r"8 per path, Uniform over [0-9.]+-[0-9.]+ nm", a["prism:wavelengths"]), a["prism:wavelengths"]
    assert "max_depth 5" in a["prism:integrator"] and "clamp 20" in a["prism:integrator"], a["prism:integrator"]
    assert "caustics off" in a["prism:integrator"]
    assert int(a["prism:invalidSamples"]) == 0
    assert 0 <= int(a["prism:clampedSamples"]) <= 24 * 16 * 4
    assert float(a["prism:renderSeconds"]) >= 0.0
    # Nothing else in the prism: namespace that is empty or unreadable.
    assert all(isinstance(v, str) and v for v in a.values()), a


@pytest.mark.parametrize("exposure", [0.0, 1.5, -2.0])
def test_preview_is_the_exr_under_srgb_and_exposure(prism_bin, tmp_path, exposure):
    out, png = tmp_path / "out.exr", tmp_path / "out.png"
    run_prism(prism_bin, scene_text(sampler="spp: 8, seed: 2"), out, "-q", "--preview", str(png), "--exposure", str(exposure))
    spec, img = read_exr(out)
    rgb = img[..., [spec.channelnames.index(c) for c in "RGB"]].astype(np.float64)
    decoded = cv2.imread(str(png), cv2.IMREAD_UNCHANGED)
    assert decoded is not None and decoded.dtype == np.uint8 and decoded.shape == rgb.shape
    decoded = decoded[..., ::-1].astype(int)  # OpenCV's BGR
    encoded = colour.cctf_encoding(np.clip(rgb * 2.0**exposure, 0.0, None), function="sRGB")
    expect = np.floor(np.clip(encoded, 0.0, 1.0) * 255.0 + 0.5).astype(int)
    diff = np.abs(decoded - expect)
    # ±1 where f32 (prism) and f64 (here) round a value within ~1e-6 of a half step apart.
    assert diff.max() <= 1, diff.max()
    assert np.mean(diff == 0) > 0.99, np.mean(diff == 0)
    # The scene spans the curve (near-black, mid-tones, and clipped values unless darkened), so
    # a wrong transfer function or exposure could not pass by luck.
    assert expect.min() < 40 and np.mean((expect > 60) & (expect < 200)) > 0.2
    assert expect.max() == 255 or exposure < 0


def test_failed_render_leaves_the_existing_output_untouched(prism_bin, tmp_path):
    out, png = tmp_path / "out.exr", tmp_path / "out.png"
    good = os.urandom(4096)
    out.write_bytes(good)
    png.write_bytes(good[::-1])
    # Bad input: exit 2, both files as they were.
    p = run_prism(prism_bin, scene_text().replace("spp: 4", "spp: -4"), out, "--preview", str(png), check=False)
    assert p.returncode == 2, p.stderr
    assert out.read_bytes() == good and png.read_bytes() == good[::-1]
    # A render killed while it runs (SIGKILL: no chance to clean up) leaves them too.
    big = scene_text(sampler="spp: 4096, seed: 1").replace("width: 24, height: 16", "width: 256, height: 256")
    scene = tmp_path / "big.ron"
    scene.write_text(big)
    proc = subprocess.Popen([str(prism_bin), "render", str(scene), "-o", str(out), "-q", "--preview", str(png)], stderr=subprocess.DEVNULL)
    time.sleep(1.0)
    assert proc.poll() is None, "the render finished before it could be killed"
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    assert out.read_bytes() == good and png.read_bytes() == good[::-1]
    # A render that succeeds replaces them, leaving no temporary file beside them.
    run_prism(prism_bin, scene_text(), out, "-q", "--preview", str(png))
    assert read_exr(out)[0].nchannels >= 3 and cv2.imread(str(png)) is not None
    assert not [f.name for f in tmp_path.iterdir() if ".tmp" in f.name]
