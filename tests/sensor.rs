//! The `sensor:` section end to end: the default sensor and the old `outputs` give the same
//! pixels as before, a sensor file is found relative to the scene, response channels read the
//! right values in a furnace, renders are the same at any thread count, and bad input stops
//! with exit code 2 naming the field. (Colour accuracy against colour-science is in
//! tools/tests/test_sensor.py.)

mod common;

use common::{alpha, chi2_test, mean_se};
use prism::error::Error;
use prism::film::Film;
use prism::integrator;
use prism::math::portable;
use std::path::Path;

fn render_at(text: &str, file: &Path, threads: usize) -> Film {
    let job = prism::load::load_str(text, file).unwrap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| integrator::render(&job.scene, &job.settings, &job.channels, &|_| {}).0)
}

fn render(text: &str) -> Film {
    render_at(text, Path::new("inline.ron"), 2)
}

/// A diffuse sphere under a blackbody sky, 16×16 pixels: `{}` is where the sensor goes.
fn scene(sensor: &str) -> String {
    format!(
        r#"(
    camera: (fov: 30, to_world: [LookAt(origin: (0, 0, 4), target: (0, 0, 0), up: (0, 1, 0))]),
    film: (width: 16, height: 16),
    sampler: (spp: 8, seed: 5),
    spectral: (range: (360, 1000), sampling: Uniform),
    shapes: [(shape: Sphere(radius: 1), material: "m")],
    materials: {{ "m": Diffuse(reflectance: Constant(0.5)) }},
    emitters: [Constant(radiance: Scaled(0.001, Blackbody(3000)))],
    {sensor}
)"#
    )
}

fn same(a: &Film, b: &Film) {
    let names = |f: &Film| {
        f.channels
            .iter()
            .map(|c| c.name.clone())
            .collect::<Vec<_>>()
    };
    assert_eq!(names(a), names(b));
    for (x, y) in a.channels.iter().zip(&b.channels) {
        assert!(x.data == y.data, "channel {} differs", x.name);
    }
}

#[test]
fn default_sensor_and_outputs_are_todays_output() {
    let plain = render(&scene(""));
    same(&plain, &render(&scene("sensor: (),")));
    same(
        &plain,
        &render(&scene(
            "sensor: (observer: Cie1931, xyz: true, rgb: [Srgb], bands: [Even()]),",
        )),
    );
    // Today's channel list: R, G, B, X, Y, Z and 10 nm bands over the range.
    assert_eq!(plain.channels.len(), 6 + 64);
    assert_eq!(plain.channels[0].name, "R");
    assert_eq!(plain.channels[6].name, "S0.365,000000nm");
    // The old `outputs` maps onto the sensor.
    same(
        &render(&scene(
            "outputs: (rgb: false, xyz: true, bands: 5, band_range: (400, 700)),",
        )),
        &render(&scene(
            "sensor: (rgb: [], bands: [Even(count: 5, range: (400, 700))]),",
        )),
    );
}

#[test]
fn sensor_file_is_relative_to_the_scene() {
    let dir = std::env::temp_dir().join(format!("prism-sensor-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("sensors")).unwrap();
    let text = "(rgb: [Rec2020], bands: [Boxes([(840, 860)])])";
    std::fs::write(dir.join("sensors/nir.ron"), text).unwrap();
    let scene_file = dir.join("scene.ron");
    let from_file = render_at(&scene("sensor: File(\"sensors/nir.ron\"),"), &scene_file, 2);
    let inline = render(&scene(&format!("sensor: {text},")));
    same(&from_file, &inline);
    assert!(from_file.channel("rec2020.G").is_some());
    assert!(from_file.channel("S0.850,000000nm").is_some());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Under a constant sky of 1 seen directly (no shapes), every response channel has an exact
/// value: a box band and a filter read 1 (they are normalised means), the camera's G reads 1
/// (normalised by ∫ḡ) times the exposure (1 · 0.01 · π / (4 · 2²) at ISO 100 = 0.0019635).
/// Only wavelength sampling is random: the image mean must be within 5 standard errors, and
/// the standard error at most 0.5% of the value (a bias above 2.5% fails).
/// The same with `spectral.sampling: Sensor`, whose density differs across channels: every
/// channel must still read its exact value (unbiased).
#[test]
fn response_channels_in_a_furnace() {
    for sampling in ["Uniform", "Sensor"] {
        furnace(sampling);
    }
}

fn furnace(sampling: &str) {
    let text = r#"(
    film: (width: 32, height: 32),
    sampler: (spp: 64, seed: 1),
    spectral: (range: (360, 1000), sampling: SAMPLING, wavelengths: 8),
    emitters: [Constant(radiance: Constant(1))],
    sensor: (rgb: [], bands: [Box(lo: 840, hi: 860, name: "nir"),
        Filter(name: "g", curve: Gaussian(centre: 700, fwhm: 50)),
        Filter(curve: Tabulated([(500, 0), (520, 1), (540, 0)]))],
        camera: (curves: Named("sony_ilce_7m3"), exposure: (iso: 100, shutter: 0.01, f_number: 2))),
)"#;
    let film = render(&text.replace("SAMPLING", sampling));
    let k = 0.01 * std::f64::consts::PI / 16.0;
    for (name, expect) in [
        ("nir.Y", 1.0),
        ("g.Y", 1.0),
        ("S0.520,000000nm", 1.0),
        ("camera.G", k),
        ("Y", 1.0),
    ] {
        let (m, se) = mean_se(film.channel(name).unwrap_or_else(|| panic!("{name}")));
        // The analytic tests' precision floor: se ≤ 0.5% of the value, so the 5-se bound
        // below admits at most a 2.5% bias (se < 2% admitted 10%).
        assert!(
            se <= 5e-3 * expect,
            "{name}: se {se} too large to test anything"
        );
        assert!(
            (m - expect).abs() < 5.0 * se + 1e-6,
            "{sampling}: {name}: {m} ± {se}, want {expect}"
        );
    }
}

#[test]
fn camera_render_is_the_same_at_any_thread_count() {
    let text = scene(
        "sensor: (rgb: [Srgb, AcesCg], bands: [Filter(name: \"nir\", curve: Gaussian(centre: 850, fwhm: 40))], camera: (curves: Named(\"nikon_d850\"), white_balance: Temperature(4000))),",
    );
    let one = render_at(&text, Path::new("inline.ron"), 1);
    let three = render_at(&text, Path::new("inline.ron"), 3);
    same(&one, &three);
    assert!(one.header.iter().any(|(k, _)| k == "prism:cameraToXYZ"));
}

/// Bad sensors: each must be an input error (exit code 2) naming the field and the fix.
#[test]
fn bad_sensors_name_the_field() {
    let cases = [
        // A syntax-level mistake: RON reports the line and column instead of a field.
        ("sensor: (observer: Cie1965),", "", "Cie1931"),
        ("sensor: (obsrver: Cie1964),", "", "observer"),
        ("sensor: (camera: (curves: Named(\"nikon_d8100\"))),", "sensor.camera.curves", "nikon_d810"),
        ("sensor: (bands: [Boxes([(500, 500)])]),", "sensor.bands[0][0]", "zero"),
        ("sensor: (bands: [Boxes([(300, 400)])]),", "sensor.bands[0][0]", "outside the spectral range"),
        ("sensor: (bands: [Box(lo: 500, hi: 600), Boxes([(500, 600)])]),", "sensor.bands", "both named"),
        ("sensor: (bands: [Filter(curve: Tabulated([(500, 1), (600, -1)]))]),", "sensor.bands[0].curve", "negative"),
        ("sensor: (bands: [Filter(curve: Rgb(1, 0, 0))]),", "sensor.bands[0].curve", "RGB"),
        ("sensor: (bands: [Filter(name: \"a b\", curve: Gaussian(centre: 600, fwhm: 10))]),", "sensor.bands[0].name", "layer name"),
        ("sensor: (rgb: [Srgb, Srgb]),", "sensor.rgb[1]", "twice"),
        ("sensor: (rgb: [], xyz: false, bands: []),", "sensor", "no output channels"),
        ("sensor: (camera: (curves: Named(\"nikon_d810\"), white_balance: Illuminant(\"D66\"))),", "sensor.camera.white_balance", "D65"),
        ("sensor: (camera: (curves: Named(\"nikon_d810\"), exposure: (iso: 0, shutter: 1, f_number: 2))),", "sensor.camera.exposure.iso", "positive"),
        ("sensor: File(\"no/such/sensor.ron\"),", "", "cannot read the sensor file"),
        ("sensor: (), outputs: (bands: 3),", "outputs", "both"),
    ];
    for (sensor, field, text) in cases {
        let err = match prism::load::load_str(&scene(sensor), Path::new("inline.ron")) {
            Err(e) => e,
            Ok(_) => panic!("{sensor}: accepted"),
        };
        assert_eq!(err.exit_code(), 2, "{sensor}");
        let Error::Input(e) = &err else {
            panic!("{sensor}: {err}")
        };
        if !field.is_empty() {
            assert_eq!(e.field.as_deref(), Some(field), "{sensor}: {err}");
        }
        let shown = err.to_string();
        assert!(shown.contains(text), "{sensor}: {shown}");
    }
}

/// Every preset in configs/sensors/ loads and renders (through `sensor: File(...)`, as
/// `--sensor` passes it), with the channels its comment promises.
#[test]
fn presets_load() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/sensors");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "ron") {
            continue;
        }
        let text = scene(&format!("sensor: File({:?}),", path.to_str().unwrap()))
            .replace("spp: 8", "spp: 1");
        let film = render(&text);
        let has = |c: &str| film.channel(c).is_some();
        let stem = path.file_stem().unwrap().to_str().unwrap();
        match stem {
            "cie1931" | "cie1964" => assert!(has("X") && has("R") && film.band_centers.is_empty()),
            "hyperspectral_31" => assert_eq!(film.band_centers.len(), 31),
            "rgb_nir" => assert!(has("nir.Y") && has("camera.R")),
            "raw_rggb" => assert!(
                has("camera.G") && film.uint_channels.iter().any(|c| c.name == "raw.Y"),
                "{stem}"
            ),
            _ => assert!(has("camera.G") && has("corrected.B"), "{stem}"),
        }
        n += 1;
    }
    assert!(n >= 8, "{n} presets");
}

/// `spectral.sampling: Sensor` draws wavelengths from the density it reports: a chi-square test
/// of 400k lanes (100k paths × 4) in 64 bins over 360–1000 nm against the pdf integrated over
/// each bin (midpoint rule, 64 points per bin), at α = 1% (the lanes of a path are stratified,
/// which lowers the counts' variance: the test is conservative). Each lane's pdf is the density
/// at its wavelength, and the density puts about a third of its mass (one of its three unit-area
/// groups: observer, filter, camera) in the NIR filter's 800–900 nm, which is what it is for.
#[test]
fn sensor_wavelength_sampling_chi_square() {
    let text = scene(
        "sensor: (rgb: [Srgb], bands: [Filter(name: \"nir\", curve: Gaussian(centre: 850, fwhm: 40))], camera: (curves: Named(\"sony_ilce_7m3\"))),",
    )
    .replace("sampling: Uniform", "sampling: Sensor");
    let job = prism::load::load_str(&text, Path::new("inline.ron")).unwrap();
    let ws = job.settings.wavelengths;
    let (lo, hi) = ws.range();
    let bins = 64;
    let width = (hi - lo) / bins as f32;
    let mut observed = vec![0.0f64; bins];
    let n = 100_000;
    let mut rng = prism::math::rng::Pcg32::new(7, 9);
    for _ in 0..n {
        let wl = ws.sample::<4>(rng.next_f32());
        for j in 0..4 {
            let l = wl.lambda[j];
            assert!(
                (wl.pdf[j] - ws.pdf(l)).abs() <= 1e-5 * ws.pdf(l),
                "lane pdf at {l}"
            );
            observed[(((l - lo) / width) as usize).min(bins - 1)] += 1.0;
        }
    }
    let expected: Vec<f64> = (0..bins)
        .map(|b| {
            (0..64)
                .map(|k| ws.pdf(lo + (b as f32 + (k as f32 + 0.5) / 64.0) * width) as f64)
                .sum::<f64>()
                * (width as f64 / 64.0)
                * (4 * n) as f64
        })
        .collect();
    let (p, stat, dof) = chi2_test(&observed, &expected);
    assert!(p > alpha(1), "chi-square {stat:.1}, {dof} dof, p = {p:.3e}");
    let nir: f64 = (0..bins)
        .filter(|&b| {
            let c = lo + (b as f32 + 0.5) * width;
            (800.0..900.0).contains(&c)
        })
        .map(|b| observed[b])
        .sum();
    assert!(nir > 0.3 * (4 * n) as f64, "{nir}");
}

/// The density `spectral.sampling: Sensor` samples is the documented mixture (src/sensor/
/// sampling.rs, scenes/README.md), built here from the curves alone: the observer group
/// x̄ + ȳ + z̄, the NIR filter exp(−4 ln 2 (λ − 850)² / 40²) and the camera r̄ + ḡ + b̄, each
/// normalised to unit area over 360–1000 nm, their mean, as 99%, plus 1% uniform. The sampled
/// lanes' histogram (400k lanes, 64 bins, exact integrals at 0.05 nm) must pass a chi-square
/// test against it at α = 1%; a density that weighted the groups by their raw areas, or
/// dropped the uniform floor, fails (the previous test compared the code's pdf with itself).
#[test]
fn sensor_wavelength_sampling_is_the_documented_mixture() {
    let text = scene(
        "sensor: (rgb: [Srgb], bands: [Filter(name: \"nir\", curve: Gaussian(centre: 850, fwhm: 40))], camera: (curves: Named(\"sony_ilce_7m3\"))),",
    )
    .replace("sampling: Uniform", "sampling: Sensor");
    let job = prism::load::load_str(&text, Path::new("inline.ron")).unwrap();
    let ws = job.settings.wavelengths;
    let (lo, hi) = ws.range();
    assert_eq!((lo, hi), (360.0, 1000.0));
    let cmf = prism::spectrum::color::cie1931();
    let cam = prism::sensor::camera::named("sony_ilce_7m3").unwrap();
    let groups: [&dyn Fn(f64) -> f64; 3] = [
        &|l| cmf.eval(l as f32).iter().map(|&v| v as f64).sum(),
        &|l| portable::exp(-4.0 * portable::ln(2f64) * (l - 850.0).powi(2) / (40.0 * 40.0)),
        &|l| cam.iter().map(|c| c.eval_one(l as f32) as f64).sum(),
    ];
    let h = 0.05;
    let steps = ((hi - lo) as f64 / h).round() as usize;
    let grid = |k: usize| lo as f64 + (k as f64 + 0.5) * h;
    let areas = groups.map(|g| (0..steps).map(|k| g(grid(k))).sum::<f64>() * h);
    let pdf = |l: f64| {
        let mix = groups
            .iter()
            .zip(&areas)
            .map(|(g, a)| g(l) / a)
            .sum::<f64>()
            / 3.0;
        0.99 * mix + 0.01 / (hi - lo) as f64
    };
    let bins = 64;
    let per_bin = steps / bins;
    let mut expected = vec![0.0f64; bins];
    for k in 0..steps {
        expected[k / per_bin] += pdf(grid(k)) * h;
    }
    let total: f64 = expected.iter().sum();
    assert!(
        (total - 1.0).abs() < 1e-3,
        "the mixture integrates to {total}"
    );
    let n = 100_000;
    let mut observed = vec![0.0f64; bins];
    let mut rng = prism::math::rng::Pcg32::new(11, 3);
    for _ in 0..n {
        let wl = ws.sample::<4>(rng.next_f32());
        for l in wl.lambda {
            let b = ((l - lo) / (hi - lo) * bins as f32) as usize;
            observed[b.min(bins - 1)] += 1.0;
        }
    }
    let expected: Vec<f64> = expected.iter().map(|e| e * (4 * n) as f64).collect();
    let (p, stat, dof) = chi2_test(&observed, &expected);
    assert!(p > alpha(1), "chi-square {stat:.1}, {dof} dof, p = {p:.3e}");
}

/// Issue 15 item 3: where data end inside the render range, a warning names the spectrum and
/// the range it covers: RGB reflectances (values and textures; the uplift is fitted on
/// 360–830 nm), RGB emitters and environment maps (RGB × D65, data to 830 nm). A visible-range
/// render of the same scene gives none of them.
#[test]
fn rgb_data_past_their_range_are_named() {
    let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = |range: &str| {
        format!(
            r#"(
        camera: (fov: 40, to_world: [LookAt(origin: (0, 1, 4), target: (0, 0.5, 0), up: (0, 1, 0))]),
        film: (width: 8, height: 8),
        spectral: (range: {range}),
        materials: {{
            "rgb": Diffuse(reflectance: Rgb(0.2, 0.5, 0.8)),
            "tex": Diffuse(reflectance: Bitmap(path: "textures/grid.png")),
        }},
        shapes: [
            (shape: Sphere(center: (0, 0.5, 0), radius: 0.5), material: "rgb"),
            (shape: Sphere(center: (1, 0.5, 0), radius: 0.3), material: "tex"),
            (shape: Rectangle, emitter: (radiance: Rgb(1, 1, 1)), to_world: [Rotate(axis: (1, 0, 0), angle: 90), Translate((0, 2, 0))]),
        ],
        emitters: [Envmap(filename: "textures/sky.exr")],
    )"#
        )
    };
    let file = repo.join("scenes/nir_warnings.ron");
    let warnings = |range: &str| prism::load::load_str(&text(range), &file).unwrap().warnings;
    let nir = warnings("(300, 1100)");
    let has = |field: &str, what: &str| {
        nir.iter()
            .any(|w| w.contains(field) && w.contains(what) && w.contains("300–1100 nm"))
    };
    assert!(
        has("materials.\"rgb\".reflectance", "fitted over 360–830 nm"),
        "{nir:#?}"
    );
    assert!(
        has("materials.\"tex\".reflectance", "fitted over 360–830 nm"),
        "{nir:#?}"
    );
    assert!(
        has("shapes[2].emitter.radiance", "300–830 nm only"),
        "{nir:#?}"
    );
    assert!(has("emitters[0].filename", "RGB × D65"), "{nir:#?}");
    assert_eq!(warnings("(360, 830)"), Vec::<String>::new());
}
