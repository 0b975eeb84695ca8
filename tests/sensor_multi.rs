//! Several sensors from one render (src/sensor/multi.rs): each extra sensor's channels, raw
//! mosaic included, equal bit for bit a render with that sensor alone at the same seed (the
//! same samples reach its accumulators in the same order, so no tolerance is needed); its
//! channels and header keys are prefixed with its name, the sidecar lists every sensor's
//! channels, and bad names are refused with exit 2.

use prism::film::Film;
use prism::integrator;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

fn sensor_file(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("configs/sensors")
        .join(name)
}

/// A diffuse sphere under a blackbody sky, 12×10 pixels, 4 spp; `{}` holds the sensors.
fn scene(sampling: &str, sensors: &str) -> String {
    format!(
        r#"(
    camera: (fov: 30, to_world: [LookAt(origin: (0, 0, 4), target: (0, 0, 0), up: (0, 1, 0))]),
    film: (width: 12, height: 10),
    sampler: (spp: 4, seed: 11),
    spectral: (range: (360, 1000), sampling: {sampling}),
    shapes: [(shape: Sphere(radius: 1), material: "m")],
    materials: {{ "m": Diffuse(reflectance: Constant(0.5)) }},
    emitters: [Constant(radiance: Scaled(0.001, Blackbody(3000)))],
    {sensors}
)"#
    )
}

fn render(text: &str) -> Film {
    let job = prism::load::load_str(text, Path::new("inline.ron")).unwrap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    pool.install(|| integrator::render(&job.scene, &job.settings, &job.channels, &|_| {}).0)
}

/// Every channel, float and uint, by name (uint as f64: exact below 2^53).
fn channels(f: &Film) -> BTreeMap<String, Vec<f64>> {
    let mut m: BTreeMap<String, Vec<f64>> = f
        .channels
        .iter()
        .map(|c| (c.name.clone(), c.data.iter().map(|&v| v as f64).collect()))
        .collect();
    for c in &f.uint_channels {
        m.insert(c.name.clone(), c.data.iter().map(|&v| v as f64).collect());
    }
    m
}

const EXTRAS: [(&str, &str); 3] = [
    ("nikon", "nikon_d810.ron"),
    ("hsi", "hyperspectral_31.ron"),
    ("chip", "raw_rggb.ron"),
];

fn extras_field() -> String {
    let list: Vec<String> = EXTRAS
        .iter()
        .map(|(n, f)| format!("(name: {n:?}, sensor: File({:?}))", sensor_file(f)))
        .collect();
    format!(
        "sensor: File({:?}),\n    sensors: [{}],",
        sensor_file("rgb_nir.ron"),
        list.join(", ")
    )
}

#[test]
fn each_sensor_of_one_render_equals_its_render_alone() {
    for sampling in ["Visible", "Uniform"] {
        let multi = channels(&render(&scene(sampling, &extras_field())));
        let main = channels(&render(&scene(
            sampling,
            &format!("sensor: File({:?}),", sensor_file("rgb_nir.ron")),
        )));
        let mut expected = main.len();
        for (k, v) in &main {
            assert!(multi[k] == *v, "{sampling}: main channel {k} differs");
        }
        for (name, file) in EXTRAS {
            let alone = channels(&render(&scene(
                sampling,
                &format!("sensor: File({:?}),", sensor_file(file)),
            )));
            for (k, v) in &alone {
                let key = format!("{name}.{k}");
                let got = multi
                    .get(&key)
                    .unwrap_or_else(|| panic!("{sampling}: no {key} in {:?}", multi.keys()));
                assert!(got == v, "{sampling}: {key} differs from {file} alone");
            }
            expected += alone.len();
        }
        assert_eq!(multi.len(), expected, "{sampling}: {:?}", multi.keys());
        assert!(multi.contains_key("chip.raw.Y") && multi.contains_key("nikon.camera.R"));
    }
}

/// `sampling: Sensor` draws from the mean of the sensors' densities: not the samples a single
/// sensor draws, so the channels agree in expectation only. Over the image, the hyperspectral
/// sensor's mean Y differs from its render alone by less than 5 standard errors of the
/// difference (both are unbiased estimates of one value; the errors come from the pixels'
/// spread, 120 pixels each).
#[test]
fn sensor_sampling_with_several_sensors_stays_unbiased() {
    let multi = render(&scene("Sensor", &extras_field()));
    let alone = render(&scene(
        "Sensor",
        &format!("sensor: File({:?}),", sensor_file("hyperspectral_31.ron")),
    ));
    let mean_se = |v: &[f32]| {
        let n = v.len() as f64;
        let m = v.iter().map(|&x| x as f64).sum::<f64>() / n;
        let var = v.iter().map(|&x| (x as f64 - m).powi(2)).sum::<f64>() / (n - 1.0);
        (m, (var / n).sqrt())
    };
    let (a, sa) = mean_se(multi.channel("hsi.Y").unwrap());
    let (b, sb) = mean_se(alone.channel("Y").unwrap());
    let z = (a - b) / (sa * sa + sb * sb).sqrt();
    assert!(z.abs() < 5.0, "hsi.Y {a} vs Y alone {b}: z = {z}");
}

fn prism() -> std::process::Command {
    std::process::Command::new(env!("CARGO_BIN_EXE_prism"))
}

fn workdir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("prism-multi-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// `prism render --also-sensor NAME=FILE`: the EXR has the prefixed channels and header keys,
/// the sidecar lists each sensor with its channels; a bad or taken name exits 2 naming the
/// field, and nothing is written.
#[test]
fn the_command_line_takes_a_list_of_sensors() {
    let dir = workdir("cli");
    let file = dir.join("s.ron");
    std::fs::write(&file, scene("Visible", "")).unwrap();
    let exr = dir.join("s.exr");
    let nikon = format!("nikon={}", sensor_file("nikon_d810.ron").display());
    let o = prism()
        .arg("render")
        .arg(&file)
        .arg("-o")
        .arg(&exr)
        .args(["--quiet", "--also-sensor", &nikon])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let meta = exr::meta::MetaData::read_from_file(&exr, false).unwrap();
    let h = &meta.headers[0];
    let names: Vec<String> = h.channels.list.iter().map(|c| c.name.to_string()).collect();
    assert!(
        names.contains(&"nikon.camera.R".to_string()) && names.contains(&"R".to_string()),
        "{names:?}"
    );
    assert!(
        h.own_attributes
            .other
            .keys()
            .any(|k| k == "prism:nikon.observer"),
        "{:?}",
        h.own_attributes.other.keys()
    );
    let side: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(exr.with_extension("json")).unwrap())
            .unwrap();
    let sensors = side["sensors"].as_array().unwrap();
    assert_eq!(sensors.len(), 2);
    assert!(sensors[0]["name"].is_null());
    assert_eq!(sensors[1]["name"], "nikon");
    let listed: Vec<&str> = sensors
        .iter()
        .flat_map(|s| s["channels"].as_array().unwrap())
        .map(|c| c.as_str().unwrap())
        .collect();
    let mut sorted = listed.clone();
    sorted.sort_unstable();
    let mut exr_names: Vec<&str> = names.iter().map(|s| s.as_str()).collect();
    exr_names.sort_unstable();
    assert_eq!(
        sorted, exr_names,
        "the sidecar's sensors list every channel"
    );
    for (bad, needle) in [
        ("depth", "already a channel prefix"),
        ("camera", "already a channel prefix"),
        ("Nikon", "not a lowercase word"),
    ] {
        let out = dir.join(format!("{bad}.exr"));
        let arg = format!("{bad}={}", sensor_file("nikon_d810.ron").display());
        let o = prism()
            .arg("render")
            .arg(&file)
            .arg("-o")
            .arg(&out)
            .args(["--quiet", "--also-sensor", &arg])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{bad}: {err}");
        assert!(
            err.contains("sensors[0].name") && err.contains(needle) && err.contains("hint"),
            "{bad}: {err}"
        );
        assert!(!out.exists(), "{bad}: an EXR was written");
    }
    let twice = nikon.clone();
    let o = prism()
        .arg("render")
        .arg(&file)
        .arg("-o")
        .arg(dir.join("twice.exr"))
        .args(["--quiet", "--also-sensor", &twice, "--also-sensor", &twice])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("sensors[1].name") && err.contains("two sensors are named"),
        "{err}"
    );
}
