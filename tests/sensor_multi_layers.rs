//! The `stderr` and `albedo` layers of every sensor of one render (src/sensor/stderr.rs,
//! src/pipeline/layers.rs): an extra sensor's `<name>.stderr.<channel>` is the standard error
//! of its own channel (checked against the spread of independent renders), and a sensor that
//! repeats the main one has the main one's layers bit for bit.

use prism::film::Film;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

fn sensor_file(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("configs/sensors")
        .join(name)
}

/// A diffuse sphere under a blackbody sky, 12×10 pixels, independent samples (so a pixel's
/// samples are i.i.d. and s²/n is unbiased for the variance of its mean), `stderr` and
/// `albedo` asked for; `main` is the main sensor's file, `extras` (name, file).
fn scene(seed: u64, spp: u32, main: &str, extras: &[(&str, &str)]) -> String {
    let list: Vec<String> = extras
        .iter()
        .map(|(n, f)| format!("(name: {n:?}, sensor: File({:?}))", sensor_file(f)))
        .collect();
    format!(
        r#"(
    camera: (fov: 30, to_world: [LookAt(origin: (0, 0, 4), target: (0, 0, 0), up: (0, 1, 0))]),
    film: (width: 12, height: 10),
    sampler: (kind: Independent, spp: {spp}, seed: {seed}),
    spectral: (range: (360, 1000), sampling: Uniform),
    shapes: [(shape: Sphere(radius: 1), material: "m")],
    materials: {{ "m": Diffuse(reflectance: Constant(0.5)) }},
    emitters: [Constant(radiance: Scaled(0.001, Blackbody(3000)))],
    aovs: ["stderr", "albedo"],
    sensor: File({:?}),
    sensors: [{}],
)"#,
        sensor_file(main),
        list.join(", ")
    )
}

/// The colour pass and the AOV layers, as `prism render` makes them.
fn render(text: &str) -> (Film, prism::load::Job) {
    let job = prism::load::load_str(text, Path::new("inline.ron")).unwrap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let film = pool.install(|| prism::pipeline::render(&job, 1.0, &|_| {}).film);
    (film, job)
}

fn channels(f: &Film) -> BTreeMap<String, Vec<f32>> {
    let named = f.channels.iter().map(|c| (c.name.clone(), c.data.clone()));
    named.collect()
}

/// Each sensor's stderr channel (the main one's and the extras') against the spread of its value channel over R renders
/// with other seeds. Both estimate the variance of a pixel's mean: the layer's s²/n (averaged
/// over the R renders' own layers) and the unbiased variance across renders, each pooled over
/// the 120 pixels. The across-render estimate has relative standard error ≈ √(2/(R−1)) per
/// pixel, ≈ 0.26/√120 ≈ 2.4% pooled for Gaussian means (more with skewed path samples); the
/// layer's side is tighter (R·120 estimates). A tolerance of ±15% is > 5σ, and still fails an
/// error taken from another slot, a missing white-balance factor (nikon's multipliers are
/// far from 1) or the bands' errors added in quadrature (tests/sensor_multi_layers.rs breaks).
#[test]
fn an_extra_sensors_stderr_is_the_spread_of_its_own_channel() {
    const R: u64 = 24;
    let extras = [("nikon", "nikon_d810.ron"), ("hsi", "hyperspectral_31.ron")];
    let runs: Vec<BTreeMap<String, Vec<f32>>> = (0..R)
        .map(|s| channels(&render(&scene(100 + s, 8, "rgb_nir.ron", &extras)).0))
        .collect();
    let mut checked = Vec::new();
    for name in runs[0].keys() {
        // The main sensor's `stderr.<c>` and an extra's `<name>.stderr.<c>`.
        let value = match (name.strip_prefix("stderr."), name.split_once(".stderr.")) {
            (Some(c), _) => c.to_string(),
            (None, Some((sensor, c))) => format!("{sensor}.{c}"),
            (None, None) => continue,
        };
        let Some(v0) = runs[0].get(&value) else {
            continue;
        };
        let (mut layer, mut spread) = (0.0f64, 0.0f64);
        for p in 0..v0.len() {
            let vals: Vec<f64> = runs.iter().map(|r| r[&value][p] as f64).collect();
            let mean = vals.iter().sum::<f64>() / R as f64;
            spread += vals.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (R - 1) as f64;
            layer += runs
                .iter()
                .map(|r| (r[name][p] as f64).powi(2))
                .sum::<f64>()
                / R as f64;
        }
        let ratio = layer / spread;
        assert!(
            (ratio - 1.0).abs() < 0.15,
            "{name}: mean s²/n {layer:e} vs spread {spread:e} over renders (ratio {ratio})"
        );
        checked.push(name.clone());
    }
    let wanted = [
        "stderr.camera.R",
        "nikon.stderr.camera.R",
        "nikon.stderr.Y",
        "hsi.stderr.S0.550,000000nm",
    ];
    for want in wanted {
        assert!(
            checked.iter().any(|c| c == want),
            "{want} not in {checked:?}"
        );
    }
}

/// A sensor that repeats the main one accumulates the same values in the same order, so its
/// stderr and albedo channels equal the main sensor's bit for bit; the layers hold exactly the
/// channels the sidecar lists (`Sensor::stderr_names`, `Sensor::albedo_names`).
#[test]
fn a_twin_sensors_layers_equal_the_main_sensors() {
    let file = "hyperspectral_31.ron";
    let (film, job) = render(&scene(7, 4, file, &[("twin", file)]));
    let c = channels(&film);
    let mut same = 0;
    for (name, data) in &c {
        if let Some(own) = name.strip_prefix("twin.") {
            if own.starts_with("stderr.") || own.starts_with("albedo.") {
                assert_eq!(data, &c[own], "{name}");
                same += 1;
            }
        }
    }
    // stderr: Y and 31 bands; albedo: 31 bands.
    assert_eq!(same, 1 + 31 + 31, "{:?}", c.keys());
    let sensor = &job.channels.sensor;
    for n in sensor.stderr_names().iter().chain(&sensor.albedo_names()) {
        assert!(c.contains_key(n), "{n} listed but not written");
    }
    let written = c
        .keys()
        .filter(|n| n.contains("stderr.") || n.contains("albedo."));
    assert_eq!(
        written.count(),
        sensor.stderr_names().len() + sensor.albedo_names().len()
    );
}
