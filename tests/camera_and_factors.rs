//! Inputs whose every number is valid but whose product is not: a camera `to_world` that
//! shears, scales unequally or mirrors (the sidecar's R, t and K could not describe its rays),
//! an exposure factor or raw electron scale past f32's range, an infinite dark charge or gain.
//! Each must be refused with exit 2 naming the field, and leave no output (issue 27, items 2
//! and 3). A uniform scale and a normal exposure still render.

mod scratch;
use std::process::Command;

fn workdir(name: &str) -> scratch::Scratch {
    scratch::scratch("factors", name)
}

/// Renders `scene_text`; returns (exit code, stderr, whether the EXR or its sidecar exists).
fn run(name: &str, scene_text: &str) -> (i32, String, bool) {
    let dir = workdir(name);
    let scene = dir.join("scene.ron");
    std::fs::write(&scene, scene_text).unwrap();
    let out = dir.join("out.exr");
    let o = Command::new(env!("CARGO_BIN_EXE_prism"))
        .arg("render")
        .arg(&scene)
        .arg("-o")
        .arg(&out)
        .arg("-q")
        .output()
        .unwrap();
    let written = out.exists() || dir.join("out.json").exists();
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stderr).into_owned(),
        written,
    )
}

fn scene(camera: &str, sensor: &str) -> String {
    format!(
        r#"(
    film: (width: 8, height: 6),
    sampler: (spp: 2),
    camera: ({camera}),
    materials: {{ "grey": Diffuse(reflectance: Constant(0.5)) }},
    shapes: [(shape: Sphere(center: (0, 0, 4)), material: "grey")],
    emitters: [Constant(radiance: Named("D65"))],
    {sensor}
)"#
    )
}

fn refused(name: &str, text: &str, needles: &[&str]) {
    let (code, err, written) = run(name, text);
    assert_eq!(code, 2, "{name}: exit {code}, stderr:\n{err}");
    assert!(!written, "{name}: an output was written");
    assert!(!err.contains("panicked"), "{name}: {err}");
    assert!(err.contains("hint:"), "{name}: no fix given:\n{err}");
    for n in needles {
        assert!(err.contains(n), "{name}: stderr lacks `{n}`:\n{err}");
    }
}

fn renders(name: &str, text: &str) {
    let (code, err, written) = run(name, text);
    assert_eq!(code, 0, "{name}: exit {code}, stderr:\n{err}");
    assert!(written, "{name}");
}

const LOOK: &str = "LookAt(origin: (0, 0, -1), target: (0, 0, 4), up: (0, 1, 0))";

#[test]
fn camera_shear_unequal_scale_and_mirror_are_refused() {
    for (name, op, why) in [
        ("unequal", "Scale((1, 2, 1))", "unequally"),
        ("mirror", "Scale((-1, 1, 1))", "mirrors"),
        (
            "shear",
            "Matrix(((1, 0.3, 0, 0), (0, 1, 0, 0), (0, 0, 1, 0), (0, 0, 0, 1)))",
            "shears",
        ),
    ] {
        let text = scene(&format!("fov: 40, to_world: [{op}, {LOOK}]"), "");
        refused(name, &text, &["scene.ron", "camera.to_world", why]);
    }
    // A uniform scale changes no ray: accepted, as documented (docs/sidecar.md).
    renders(
        "uniform",
        &scene(
            &format!("fov: 40, to_world: [Scale((3, 3, 3)), {LOOK}]"),
            "",
        ),
    );
}

fn camera_sensor(exposure: &str, raw: &str) -> String {
    format!(
        r#"sensor: (rgb: [Srgb], bands: [], camera: (curves: Named("sony_ilce_7m3"), exposure: ({exposure})){raw}),"#
    )
}

/// f_number 1e-21 made k = 7.9e39: Inf and NaN in camera.* and corrected.*, and exit 0.
#[test]
fn exposure_factor_past_f32_is_refused() {
    for (name, e) in [
        ("tiny_f", "iso: 100, shutter: 0.01, f_number: 1e-21"),
        ("huge_f", "iso: 100, shutter: 0.01, f_number: 1e21"),
        ("huge_iso", "iso: 3e38, shutter: 3e38, f_number: 1"),
    ] {
        let text = scene(
            &format!("fov: 40, to_world: [{LOOK}]"),
            &camera_sensor(e, ""),
        );
        refused(name, &text, &["sensor.camera.exposure", "exposure factor"]);
    }
    let ok = camera_sensor("iso: 100, shutter: 0.01, f_number: 8", "");
    renders(
        "normal",
        &scene(&format!("fov: 40, to_world: [{LOOK}]"), &ok),
    );
}

const RAW: &str = ", raw: (pattern: Rggb, pixel_pitch: 5.93, quantum_efficiency: 0.5, full_well: 50000, read_noise: 3.0, dark_current: DARK, gain: GAIN, black_level: 512, bits: 14, noise: true)";

#[test]
fn raw_factors_past_range_are_refused() {
    let cam = format!("fov: 40, to_world: [{LOOK}]");
    let raw = |dark: &str, gain: &str| RAW.replace("DARK", dark).replace("GAIN", gain);
    // k = 1e-32 · 1e30 · π/4 is a normal exposure; the raw scale is ~1e35 e⁻ per unit.
    let long = "iso: 1e-30, shutter: 1e30, f_number: 1";
    refused(
        "raw_scale",
        &scene(&cam, &camera_sensor(long, &raw("0.1", "UnityIso(315)"))),
        &["sensor.raw", "electron scale"],
    );
    let e = "iso: 100, shutter: 1e10, f_number: 1e4";
    refused(
        "dark",
        &scene(&cam, &camera_sensor(e, &raw("1e300", "UnityIso(315)"))),
        &["sensor.raw.dark_current"],
    );
    let e = "iso: 1e30, shutter: 1e-25, f_number: 1";
    refused(
        "gain",
        &scene(&cam, &camera_sensor(e, &raw("0.1", "UnityIso(1e-300)"))),
        &["sensor.raw.gain"],
    );
    let e = "iso: 100, shutter: 0.01, f_number: 4";
    renders(
        "raw_ok",
        &scene(&cam, &camera_sensor(e, &raw("0.1", "UnityIso(315)"))),
    );
}

/// Camera curves that cannot be fitted to XYZ (three identical curves, a zero curve, a curve
/// that is a sum of the others): the colour-correction matrix does not exist, and the render
/// gave NaN camera-corrected channels. Refused naming the curves, with and without white
/// balance (a zero curve under white balance was already refused, by the white balance).
#[test]
fn camera_curves_that_cannot_be_fitted_are_refused() {
    let cam = format!("fov: 40, to_world: [{LOOK}]");
    let sensor = |r: &str, g: &str, b: &str| {
        format!(
            r#"sensor: (rgb: [Srgb], bands: [], camera: (curves: Curves(r: {r}, g: {g}, b: {b}))),"#
        )
    };
    let gauss = |c: u32| format!("Gaussian(centre: {c}, fwhm: 80)");
    let (r, g, b) = (gauss(600), gauss(540), gauss(460));
    for (name, s) in [
        ("identical", sensor(&g, &g, &g)),
        ("zero", sensor(&r, "Constant(0)", &b)),
        ("two_equal", sensor(&r, &r, &b)),
    ] {
        refused(name, &scene(&cam, &s), &["sensor.camera.curves"]);
    }
    renders("three", &scene(&cam, &sensor(&r, &g, &b)));
}
