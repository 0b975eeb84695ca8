//! What the sidecar and EXR header say about the pixels: `scene_sha256` covers every input
//! (a glTF's buffer, a curve file a sensor file names), and the camera channels' scale is
//! recorded with its units and is what the pixels show.

mod scratch;
use std::path::{Path, PathBuf};
use std::process::Command;

fn workdir(name: &str) -> scratch::Scratch {
    scratch::scratch("truth", name)
}

fn render(scene: &Path, exr: &Path) -> serde_json::Value {
    let o = Command::new(env!("CARGO_BIN_EXE_prism"))
        .arg("render")
        .arg(scene)
        .arg("-o")
        .arg(exr)
        .arg("--quiet")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_str(&std::fs::read_to_string(exr.with_extension("json")).unwrap()).unwrap()
}

/// A triangle from `tri.gltf` (its positions in `tri.bin`) under a flat sky, seen by
/// `sensor.ron`, whose NIR filter reads `curve.txt`.
fn scene(dir: &Path) -> PathBuf {
    let pos: Vec<u8> = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
        .iter()
        .flat_map(|x| x.to_le_bytes())
        .collect();
    std::fs::write(dir.join("tri.bin"), pos).unwrap();
    let gltf = r#"{"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "buffers": [{"byteLength": 36, "uri": "tri.bin"}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
            "min": [0, 0, 0], "max": [1, 1, 0]}]}"#;
    std::fs::write(dir.join("tri.gltf"), gltf).unwrap();
    std::fs::write(dir.join("curve.txt"), "nm v\n800 0\n850 1\n900 0.5\n").unwrap();
    std::fs::write(
        dir.join("sensor.ron"),
        r#"(rgb: [Srgb], bands: [Filter(name: "nir", curve: File(path: "curve.txt", column: "v"))],
           camera: (curves: Named("nikon_d810"), exposure: (iso: 200, shutter: 0.01, f_number: 2)))"#,
    )
    .unwrap();
    let ron = r#"(camera: (fov: 40, to_world: [LookAt(origin: (0, 0, 5), target: (0, 0, 0), up: (0, 1, 0))]),
        film: (width: 16, height: 12), sampler: (spp: 16, seed: 3),
        spectral: (range: (360, 1000), sampling: Uniform),
        shapes: [(shape: Gltf(path: "tri.gltf"))],
        emitters: [Constant(radiance: Constant(1.0))],
        aovs: ["alpha"],
        sensor: File("sensor.ron"))"#;
    let p = dir.join("scene.ron");
    std::fs::write(&p, ron).unwrap();
    p
}

/// Flips the lowest bit of byte `at` of `file`.
fn flip(file: &Path, at: usize) {
    let mut b = std::fs::read(file).unwrap();
    b[at] ^= 1;
    std::fs::write(file, b).unwrap();
}

#[test]
fn scene_sha256_covers_gltf_buffers_and_files_a_sensor_file_names() {
    let dir = workdir("sha");
    let scene = scene(&dir);
    let exr = dir.join("r.exr");
    let hash = |exr: &Path| render(&scene, exr)["render"]["scene_sha256"].clone();
    let first = render(&scene, &exr);
    let listed: Vec<String> = first["render"]["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["path"].as_str().unwrap().to_string())
        .collect();
    for f in ["tri.bin", "curve.txt", "sensor.ron", "tri.gltf"] {
        assert!(
            listed.iter().any(|p| p.ends_with(f)),
            "{f} not in {listed:?}"
        );
    }
    let h0 = first["render"]["scene_sha256"].clone();
    assert_eq!(hash(&exr), h0, "the same inputs hash alike");
    // Byte 1 of tri.bin: the first vertex's x becomes a denormal, still a triangle.
    flip(&dir.join("tri.bin"), 1);
    let h1 = hash(&exr);
    assert_ne!(h1, h0, "a changed glTF buffer left scene_sha256 as it was");
    flip(&dir.join("tri.bin"), 1);
    // `900 0.5` → `900 0.4` in the curve: one byte.
    let text = std::fs::read_to_string(dir.join("curve.txt")).unwrap();
    let at = text.find("0.5").unwrap() + 2;
    flip(&dir.join("curve.txt"), at);
    let h2 = hash(&exr);
    assert_ne!(h2, h0, "a changed curve file left scene_sha256 as it was");
    flip(&dir.join("curve.txt"), at);
    assert_eq!(hash(&exr), h0);
}

/// Under a spectrally flat sky of radiance 1 the camera's green channel reads the recorded
/// scale k = (ISO/100)·t·π/(4N²) = 2 · 0.01 · π / 16 where only the sky is seen (alpha 0): the mean over those
/// pixels is within 5 standard errors of k (the errors from the pixels' spread; uniform
/// wavelength sampling makes each pixel an unbiased estimate of k). The header and the sidecar
/// give k and the units.
#[test]
fn camera_channels_carry_their_recorded_scale() {
    let dir = workdir("scale");
    let scene = scene(&dir);
    let exr = dir.join("r.exr");
    let side = render(&scene, &exr);
    let k = 2.0 * 0.01 * std::f64::consts::PI / 16.0;
    let cam = &side["sensor"]["camera"];
    assert!(
        (cam["scale"].as_f64().unwrap() / k - 1.0).abs() < 1e-6,
        "{cam}"
    );
    assert!(cam["units"]
        .as_str()
        .unwrap()
        .contains("W m^-2 sr^-1 nm^-1"));
    let meta = exr::meta::MetaData::read_from_file(&exr, false).unwrap();
    let attrs = &meta.headers[0].own_attributes.other;
    assert!(attrs.keys().any(|a| a == "prism:cameraUnits"), "{attrs:?}");
    use exr::prelude::*;
    let img = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_file(&exr)
        .unwrap();
    let chan = |n: &str| -> Vec<f64> {
        let c = img.layer_data.channel_data.list.iter();
        let c = c.clone().find(|c| c.name.to_string() == n).unwrap();
        c.sample_data.values_as_f32().map(|v| v as f64).collect()
    };
    let (g, alpha) = (chan("camera.G"), chan("alpha.A"));
    // The sky: pixels no camera sample of which hit the triangle.
    let sky: Vec<f64> = g
        .iter()
        .zip(&alpha)
        .filter(|(_, a)| **a == 0.0)
        .map(|(g, _)| *g)
        .collect();
    assert!(sky.len() > 100, "{} sky pixels", sky.len());
    let n = sky.len() as f64;
    let m = sky.iter().sum::<f64>() / n;
    let se = (sky.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (n - 1.0) / n).sqrt();
    assert!((m - k).abs() < 5.0 * se, "camera.G {m} vs k {k} (se {se})");
}
