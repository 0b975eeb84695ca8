//! `prism dataset` sensors: a sensor per frame from a list, and the exposure variation's scale
//! on the channels, recorded in the header and sidecar.

mod dataset_util;
use dataset_util::*;
use prism::math::portable;

/// A sensor from a list per frame: each frame's EXR has its own sensor's channels (camera.R and
/// corrected.R only for the camera sensor), its JSON names the file and exposure, and a
/// frame rendered alone equals the full run byte for byte.
#[test]
fn frames_take_their_sensor_from_the_list_and_render_alone_identically() {
    let dir = workdir("sensor");
    let cfg = sensor_config(&dir, 2, "(files: [CIE, NIKON], exposure: (-1, 1))");
    let out = dir.join("full");
    ok(&dataset(&cfg, &out, &[]));
    let mut seen = [false; 2];
    for i in 0..8 {
        let stem = out.join(format!("frames/{i:06}"));
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(stem.with_extension("json")).unwrap())
                .unwrap();
        let s = &json["frame"]["sensor"];
        let file = s["file"].as_str().unwrap();
        let e = s["exposure"].as_f64().unwrap();
        assert!((-1.0..=1.0).contains(&e), "frame {i}: exposure {e}");
        let px = exr_pixels(&stem.with_extension("exr"));
        let camera = file.ends_with("nikon_d810.ron");
        assert!(camera || file.ends_with("cie1931.ron"), "{file}");
        seen[camera as usize] = true;
        assert_eq!(px.contains_key("camera.R"), camera, "frame {i} ({file})");
        assert_eq!(px.contains_key("corrected.R"), camera, "frame {i} ({file})");
        assert!(
            px.contains_key("R") && px.contains_key("X"),
            "frame {i}: both write sRGB, XYZ"
        );
    }
    assert_eq!(
        seen,
        [true, true],
        "seed 2 draws both sensors in 8 frames (seed 1 draws CIE alone: p = 1/128)"
    );
    let full = frames(&out);
    let one = dir.join("one");
    ok(&dataset(
        &cfg,
        &one,
        &["--frames", "3..5", "--threads", "1"],
    ));
    let got = frames(&one);
    assert_eq!(got.len(), 2 * 3);
    for (name, bytes) in got {
        assert!(full[&name] == bytes, "{name} differs from the full run");
    }
}

/// Exposure e multiplies every sensor channel by 2^e: the same frames with `exposure: (e, e)`
/// and without the variation draw the same scene and render seed, so each channel's ratio is
/// 2^e up to the rounding of one f32 multiply (relative 2⁻²³ on the value and the factor; the
/// tolerance 1e-6 is ~4 of those); the AOV channels stay as they were.
#[test]
fn exposure_scales_the_sensor_channels_by_two_to_the_stops() {
    let base = full_run();
    let dir = workdir("exposure");
    let e = 1.5f64;
    let cfg = sensor_config(&dir, 1, &format!("(exposure: ({e}, {e}))"));
    let out = dir.join("out");
    ok(&dataset(&cfg, &out, &["--frames", "0..2"]));
    let k = portable::powf(2f64, e);
    for i in 0..2 {
        let stem = format!("frames/{i:06}.exr");
        let a = exr_pixels(&base.join(&stem));
        let b = exr_pixels(&out.join(&stem));
        assert_eq!(a.keys().collect::<Vec<_>>(), b.keys().collect::<Vec<_>>());
        let mut checked = 0;
        for (name, va) in &a {
            let vb = &b[name];
            // Colour and spectral channels are the sensor's; the rest are AOVs.
            let sensor =
                ["R", "G", "B", "X", "Y", "Z"].contains(&name.as_str()) || name.starts_with("S0.");
            for (x, y) in va.iter().zip(vb) {
                let want = if sensor { *x as f64 * k } else { *x as f64 };
                assert!(
                    (*y as f64 - want).abs() <= 1e-6 * want.abs(),
                    "frame {i} {name}: {y} vs {want}"
                );
            }
            checked += sensor as usize;
        }
        assert!(checked >= 6, "frame {i}: sensor channels {:?}", a.keys());
    }
}

/// The dataset exposure says what it did: the EXR header and the JSON's `sensor.exposure` give
/// its scale and the channels it scaled, and `stderr.*` scales with them (the standard error
/// of the values in the file): the same frames with and without `exposure: (e, e)` draw the
/// same scene and seed, so the ratio is 2^e up to one f32 multiply (tolerance 1e-6 relative,
/// as in `exposure_scales_the_sensor_channels_by_two_to_the_stops`).
#[test]
fn exposure_is_recorded_and_scales_the_standard_errors() {
    let dir = workdir("exposure-meta");
    let base = tabletop().replace(
        "    integrator: (max_depth: 6),\n",
        "    integrator: (max_depth: 6),\n    aovs: [\"stderr\", \"depth\"],\n",
    );
    std::fs::write(dir.join("base.ron"), base).unwrap();
    let e = -0.75f64;
    let k = portable::powf(2f64, e);
    let plain = config_on_base(&dir, |t| t);
    let (a, b) = (dir.join("plain"), dir.join("exposed"));
    ok(&dataset(&plain, &a, &["--frames", "0..2"]));
    let sub = dir.join("sub");
    std::fs::create_dir_all(&sub).unwrap();
    let exposed = config_on_base(&sub, |t| {
        t.replace(
            "seed: 1,",
            &format!("seed: 1,\n    sensor: (exposure: ({e}, {e})),"),
        )
    });
    std::fs::copy(dir.join("base.ron"), sub.join("base.ron")).unwrap();
    ok(&dataset(&exposed, &b, &["--frames", "0..2"]));
    for i in 0..2 {
        let stem = format!("frames/{i:06}");
        let (ja, jb) = (
            json_file(&a.join(&stem).with_extension("json")),
            json_file(&b.join(&stem).with_extension("json")),
        );
        assert!(ja["sensor"]["exposure"].is_null(), "frame {i}");
        let x = &jb["sensor"]["exposure"];
        assert!(
            (x["scale"].as_f64().unwrap() - k).abs() < 1e-7,
            "frame {i}: {x}"
        );
        assert!(
            (x["stops"].as_f64().unwrap() - e).abs() < 1e-6,
            "frame {i}: {x}"
        );
        let listed: Vec<&str> = x["channels"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c.as_str().unwrap())
            .collect();
        assert!(
            listed.contains(&"R") && listed.contains(&"stderr.*"),
            "{listed:?}"
        );
        assert!(!listed.iter().any(|c| c.starts_with("depth")), "{listed:?}");
        let h = exr_attributes(&b.join(&stem).with_extension("exr"));
        let scale: f64 = h["prism:datasetExposureScale"].parse().unwrap();
        assert!((scale - k).abs() < 1e-7, "frame {i}: header {scale}");
        assert!(!exr_attributes(&a.join(&stem).with_extension("exr"))
            .contains_key("prism:datasetExposureScale"));
        let (pa, pb) = (
            exr_pixels(&a.join(&stem).with_extension("exr")),
            exr_pixels(&b.join(&stem).with_extension("exr")),
        );
        let mut checked = 0;
        for (name, va) in pa.iter().filter(|(n, _)| n.starts_with("stderr.")) {
            for (x, y) in va.iter().zip(&pb[name]) {
                let want = *x as f64 * k;
                assert!(
                    (*y as f64 - want).abs() <= 1e-6 * want.abs(),
                    "frame {i} {name}: {y} vs {want}"
                );
            }
            checked += 1;
        }
        assert!(
            checked >= 1,
            "frame {i}: no stderr channel in {:?}",
            pa.keys()
        );
    }
}

/// `outputs.sensors` gives every frame a further sensor on the same paths: its `nikon.*`
/// channels equal bit for bit the frame rendered with the nikon file as its only sensor (the
/// variation `files: [NIKON]`: the same scene draws and render seed), the main channels equal
/// the plain run's, the JSON lists both sensors, and `dataset.json` hashes the sensor file.
#[test]
fn outputs_sensors_add_a_sensor_on_the_same_paths() {
    let plain = full_run();
    let dir = workdir("two-sensors");
    let nikon = root().join("configs/sensors/nikon_d810.ron");
    let cfg = config(&dir, |t| {
        t.replace(
            "outputs: (preview: true,",
            &format!(
                "outputs: (sensors: [(name: \"nikon\", sensor: File({nikon:?}))], preview: true,"
            ),
        )
    });
    let two = dir.join("two");
    ok(&dataset(&cfg, &two, &["--frames", "0..2"]));
    let alone_dir = dir.join("alone-cfg");
    std::fs::create_dir_all(&alone_dir).unwrap();
    let alone_cfg = sensor_config(&alone_dir, 1, "(files: [NIKON])");
    let alone = dir.join("alone");
    ok(&dataset(&alone_cfg, &alone, &["--frames", "0..2"]));
    for i in 0..2 {
        let stem = format!("frames/{i:06}");
        let both = exr_pixels(&two.join(&stem).with_extension("exr"));
        let main = exr_pixels(&plain.join(&stem).with_extension("exr"));
        let cam = exr_pixels(&alone.join(&stem).with_extension("exr"));
        for (k, v) in &main {
            assert!(both[k] == *v, "frame {i}: main channel {k} differs");
        }
        let mut matched = 0;
        for (k, v) in &cam {
            if let Some(got) = both.get(&format!("nikon.{k}")) {
                assert!(
                    got == v,
                    "frame {i}: nikon.{k} differs from the nikon alone"
                );
                matched += 1;
            }
        }
        assert!(
            matched >= 12 && both.contains_key("nikon.camera.R"),
            "frame {i}: {:?}",
            both.keys()
        );
        assert_eq!(
            both.len(),
            main.len() + matched,
            "frame {i}: {:?}",
            both.keys()
        );
        let json = json_file(&two.join(&stem).with_extension("json"));
        assert_eq!(json["sensors"][1]["name"], "nikon", "frame {i}");
    }
    let ds = json_file(&two.join("dataset.json"));
    assert!(
        ds["inputs"]
            .as_object()
            .unwrap()
            .keys()
            .any(|k| k.ends_with("nikon_d810.ron")),
        "{}",
        ds["inputs"]
    );
}
