//! The raw sensor (`sensor.raw`) end to end: a rendered flat field's DN per Bayer site against
//! the analytic model, the mosaic pattern, determinism across thread counts and seeds, the EXR
//! channel and header, and bad input (exit code 2 naming the file, the field and the fix).
//!
//! The flat field: a constant environment (radiance L, W m⁻² sr⁻¹ nm⁻¹) seen through user camera
//! curves that are flat over a 1 nm spectral range (550–551 nm), so every pixel's expected
//! photo-electron count is the same closed form (computed here from the config's numbers, not
//! by prism's code): S_c = t·A·π/(4N²)·(η/ĉ)·L·c_c·∫λ dλ/(h c), ∫_{550}^{551} λ dλ = 550.5 nm²,
//! and the wavelength sampling adds no noise to speak of (λ varies by 0.2% over the range).

mod scratch;
use prism::film::Film;
use prism::integrator;
use std::path::Path;
use std::process::{Command, Output};

const L: f64 = 0.75;
/// The curves' values over 550–551 nm (R, G, B); their common peak is R's 1.0.
const C: [f64; 3] = [1.0, 0.3, 0.05];
const SHUTTER: f64 = 0.01;
const F_NUMBER: f64 = 4.0;
const PITCH_UM: f64 = 4.0;
const QE: f64 = 0.5;
const DARK: f64 = 10.0; // e⁻/s
const READ: f64 = 3.0;
const GAIN: f64 = 0.5;
const BLACK: f64 = 256.0;

/// The camera and sensor, `{raw}` is the raw part's fields.
fn sensor(raw: &str) -> String {
    format!(
        r#"sensor: (
        rgb: [], bands: [],
        camera: (
            curves: Curves(
                r: Tabulated([(360, 0.2), (550, 1.0), (551, 1.0), (830, 0.2)]),
                g: Tabulated([(360, 0.6), (550, 0.3), (551, 0.3), (830, 0.0)]),
                b: Tabulated([(360, 0.9), (550, 0.05), (551, 0.05), (830, 0.0)]),
            ),
            exposure: (iso: 100, shutter: {SHUTTER}, f_number: {F_NUMBER}),
        ),
        raw: ({raw}),
    ),"#
    )
}

const RAW: &str = "pixel_pitch: 4.0, quantum_efficiency: 0.5, full_well: 30000, read_noise: 3.0, \
                   dark_current: 10.0, gain: PerElectron(0.5), black_level: 256, bits: 14";

/// A `size`² flat field of a constant sky (a sphere behind the camera keeps the scene non-empty).
fn scene(size: u32, seed: u64, sensor: &str) -> String {
    format!(
        r#"(
    camera: (fov: 30, to_world: [LookAt(origin: (0, 0, 0), target: (0, 0, 1), up: (0, 1, 0))]),
    film: (width: {size}, height: {size}),
    sampler: (spp: 4, seed: {seed}),
    spectral: (range: (550, 551), sampling: Uniform),
    shapes: [(shape: Sphere(center: (0, 0, -10), radius: 1), material: "m")],
    materials: {{ "m": Diffuse(reflectance: Constant(0.5)) }},
    emitters: [Constant(radiance: Constant({L}))],
    {sensor}
)"#
    )
}

fn render_at(text: &str, threads: usize) -> Film {
    let job = prism::load::load_str(text, Path::new("inline.ron")).unwrap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| integrator::render(&job.scene, &job.settings, &job.channels, &|_| {}).0)
}

fn raw_of(f: &Film) -> &[u32] {
    &f.uint_channels
        .iter()
        .find(|c| c.name == "raw.Y")
        .expect("a raw.Y channel")
        .data
}

/// Expected photo-electrons per channel (module docs), from the constants alone.
fn electrons() -> [f64; 3] {
    let hc = 6.626_070_15e-34 * 299_792_458.0;
    let area = (PITCH_UM * 1e-6) * (PITCH_UM * 1e-6);
    let lambda_integral = (551.0f64 * 551.0 - 550.0 * 550.0) / 2.0 * 1e-9; // nm · m
    let k = SHUTTER * area * std::f64::consts::PI / (4.0 * F_NUMBER * F_NUMBER) * QE / 1.0;
    C.map(|c| k * L * c * lambda_integral / hc)
}

/// Per site of the 2×2 tile (row-major): the values there.
fn sites(data: &[u32], width: usize) -> [Vec<f64>; 4] {
    let mut out: [Vec<f64>; 4] = Default::default();
    for (i, &v) in data.iter().enumerate() {
        out[((i / width) & 1) * 2 + ((i % width) & 1)].push(v as f64);
    }
    out
}

/// Each Bayer site's DN mean and variance on the rendered flat field against the analytic
/// model: mean = g(S + D) + black, var = g²(S + D + σ_r²) + 1/12, within 4 standard errors
/// (mean: √(s²/M); variance: √((m4 − s⁴)/M) from the sample's fourth central moment; M = 4096
/// or 8192 pixels per site on 128×128; a false alarm per check ≈ 6e-5).
#[test]
fn flat_field_matches_the_analytic_model() {
    let film = render_at(&scene(128, 7, &sensor(RAW)), 2);
    let s = electrons();
    // Sanity of the closed form's magnitude: thousands of electrons in R.
    assert!(s[0] > 5000.0 && s[0] < 12000.0, "{s:?}");
    let d = DARK * SHUTTER;
    for (site, v) in sites(raw_of(&film), 128).iter().enumerate() {
        let c = [0, 1, 1, 2][site]; // RGGB
        let want_mean = GAIN * (s[c] + d) + BLACK;
        let want_var = GAIN * GAIN * (s[c] + d + READ * READ) + 1.0 / 12.0;
        let m = v.len() as f64;
        let mean = v.iter().sum::<f64>() / m;
        let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (m - 1.0);
        let m4 = v.iter().map(|x| (x - mean).powi(4)).sum::<f64>() / m;
        let (se_mean, se_var) = ((var / m).sqrt(), ((m4 - var * var) / m).sqrt());
        eprintln!(
            "site {site} (channel {c}): mean {mean:.3} vs {want_mean:.3} ({:+.2} se), var {var:.2} vs {want_var:.2} ({:+.2} se)",
            (mean - want_mean) / se_mean,
            (var - want_var) / se_var
        );
        assert!(
            (mean - want_mean).abs() < 4.0 * se_mean,
            "site {site}: mean {mean} vs {want_mean} (se {se_mean})"
        );
        assert!(
            (var - want_var).abs() < 4.0 * se_var,
            "site {site}: var {var} vs {want_var} (se {se_var})"
        );
    }
    // The header carries the parameters.
    let get = |k: &str| {
        film.header
            .iter()
            .find(|(n, _)| n == k)
            .map(|(_, v)| v.clone())
            .unwrap_or_else(|| panic!("no {k}"))
    };
    assert_eq!(get("prism:raw.pattern"), "RGGB");
    assert_eq!(get("prism:raw.bits"), "14");
    assert_eq!(get("prism:raw.gain").parse::<f64>().unwrap(), GAIN);
}

/// Without noise each pixel reads its own site's channel: the channels' expected DN differ by
/// factors of 3 and 6, so the nearest one tells which was read; the tile comes from the
/// pattern's name, for all four patterns.
#[test]
fn mosaic_pattern() {
    let s = electrons();
    let want = s.map(|e| GAIN * (e + DARK * SHUTTER) + BLACK);
    for (p, name) in [
        ("Rggb", "RGGB"),
        ("Bggr", "BGGR"),
        ("Grbg", "GRBG"),
        ("Gbrg", "GBRG"),
    ] {
        let raw = format!("{RAW}, pattern: {p}, noise: false");
        let film = render_at(&scene(8, 1, &sensor(&raw)), 2);
        for (i, &v) in raw_of(&film).iter().enumerate() {
            let (x, y) = (i % 8, i / 8);
            let c = match name.as_bytes()[(y % 2) * 2 + x % 2] {
                b'R' => 0,
                b'G' => 1,
                _ => 2,
            };
            // Within 1 DN of its own channel's expectation (rounding).
            assert!(
                (v as f64 - want[c]).abs() <= 1.0,
                "{p} ({x}, {y}): {v} vs {want:?}"
            );
        }
    }
}

/// The raw channel is bit-identical at 1 and 3 threads; another seed leaves the camera
/// channels as they are (the flat field has no Monte Carlo noise there) and changes the noise.
#[test]
fn deterministic_across_threads_and_seeded() {
    let text = scene(24, 3, &sensor(RAW));
    let one = render_at(&text, 1);
    let three = render_at(&text, 3);
    assert!(raw_of(&one) == raw_of(&three));
    let other = render_at(&scene(24, 4, &sensor(RAW)), 3);
    let camera = |f: &Film| f.channel("camera.R").unwrap().to_vec();
    assert_eq!(camera(&one), camera(&other));
    let differ = raw_of(&one)
        .iter()
        .zip(raw_of(&other))
        .filter(|(a, b)| a != b)
        .count();
    assert!(differ > 24 * 24 * 9 / 10, "{differ} of 576 pixels differ");
}

fn workdir(name: &str) -> scratch::Scratch {
    scratch::scratch("raw", name)
}

/// `prism render -q SCENE -o OUT`.
fn render_cli(scene: &Path, out: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_prism"))
        .args(["render", "-q"])
        .arg(scene)
        .arg("-o")
        .arg(out)
        .output()
        .unwrap()
}

/// `prism render` writes raw.Y as a uint32 EXR channel with the prism:raw.* attributes, and the
/// sidecar's sensor section lists them.
#[test]
fn written_as_a_uint_channel_with_its_parameters() {
    let dir = workdir("exr");
    let scene_file = dir.join("flat.ron");
    std::fs::write(&scene_file, scene(8, 1, &sensor(RAW))).unwrap();
    let out = dir.join("flat.exr");
    let o = render_cli(&scene_file, &out);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    use exr::prelude::*;
    let img = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_file(&out)
        .unwrap();
    let ch = img
        .layer_data
        .channel_data
        .list
        .iter()
        .find(|c| c.name.to_string() == "raw.Y")
        .expect("raw.Y in the EXR");
    assert!(matches!(ch.sample_data, FlatSamples::U32(_)));
    // A single-part file's attributes may be read back as the image's or the layer's.
    let attr = |k: &str| {
        let k = Text::from(k);
        img.attributes
            .other
            .get(&k)
            .or_else(|| img.layer_data.attributes.other.get(&k))
            .map(|v| format!("{v:?}"))
    };
    assert!(attr("prism:raw.pattern").unwrap().contains("RGGB"));
    assert!(attr("prism:raw.fullWell").is_some());
    let side: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(prism::output::sidecar::path_for(&out)).unwrap(),
    )
    .unwrap();
    assert_eq!(
        side["sensor"]["attributes"]["prism:raw.channel"],
        serde_json::json!("raw.Y")
    );
}

/// Bad raw sensors: exit code 2 on `prism render`, naming the file, the field and the fix; no
/// output written.
#[test]
fn bad_raw_input_exits_2() {
    let camera_less = "sensor: (raw: ()),".to_string();
    let no_exposure = sensor(RAW).replace(
        &format!("exposure: (iso: 100, shutter: {SHUTTER}, f_number: {F_NUMBER}),"),
        "",
    );
    // (name, the raw part's fields, what stderr must say).
    let raw_cases: [(&str, &str, &[&str]); 8] = [
        (
            "pattern",
            "pattern: Rgbg",
            &["Rgbg", "Rggb", "Bggr", "Grbg", "Gbrg"],
        ),
        (
            "read",
            "read_noise: -1",
            &["sensor.raw.read_noise", "non-negative", "hint"],
        ),
        (
            "dark",
            "dark_current: -0.5",
            &["sensor.raw.dark_current", "non-negative"],
        ),
        ("bits0", "bits: 0", &["sensor.raw.bits", "1 to 32", "hint"]),
        ("bits33", "bits: 33", &["sensor.raw.bits", "1 to 32"]),
        (
            "qe",
            "quantum_efficiency: 1.5",
            &["sensor.raw.quantum_efficiency", "at most"],
        ),
        (
            "black",
            "bits: 8, black_level: 300",
            &["sensor.raw.black_level", "raise bits"],
        ),
        (
            "gain",
            "gain: PerElectron(0)",
            &["sensor.raw.gain", "positive"],
        ),
    ];
    let whole_sensor: [(&str, String, &[&str]); 2] = [
        (
            "camera",
            camera_less,
            &["sensor.raw", "needs a camera", "hint: add camera"],
        ),
        (
            "exposure",
            no_exposure,
            &["sensor.raw", "exposure", "hint: add camera.exposure"],
        ),
    ];
    let cases = raw_cases
        .into_iter()
        .map(|(name, raw, needles)| (name, sensor(raw), needles))
        .chain(whole_sensor);
    for (name, s, needles) in cases {
        let dir = workdir(name);
        let file = dir.join("bad.ron");
        std::fs::write(&file, scene(8, 1, &s)).unwrap();
        let out = dir.join("bad.exr");
        let o = render_cli(&file, &out);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{name}: {err}");
        assert!(!out.exists(), "{name}: output written");
        assert!(!err.contains("panicked"), "{name}: {err}");
        assert!(
            err.contains("bad.ron"),
            "{name}: the file is not named: {err}"
        );
        for n in needles {
            assert!(err.contains(n), "{name}: stderr lacks `{n}`:\n{err}");
        }
    }
}
