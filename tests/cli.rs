//! The `prism` command: renders, writes its outputs, and meets bad input with a clear error
//! (file, place, fix) on stderr, exit code 2, and no output file.

mod scratch;
use std::path::Path;
use std::process::Command;

fn prism() -> Command {
    Command::new(env!("CARGO_BIN_EXE_prism"))
}

fn workdir(name: &str) -> scratch::Scratch {
    scratch::scratch("cli", name)
}

const GOOD: &str = r#"(
    film: (width: 16, height: 12),
    sampler: (spp: 4),
    materials: { "grey": Diffuse(reflectance: Constant(0.5)) },
    shapes: [(shape: Sphere(center: (0, 0, 4)), material: "grey")],
    emitters: [Constant(radiance: Named("D65"))],
)"#;

/// Runs `prism render` on `scene_text`; returns (exit code, stderr, whether the EXR exists).
fn run(name: &str, scene_text: &str, extra: &[&str]) -> (i32, String, bool) {
    let dir = workdir(name);
    let scene = dir.join("scene.ron");
    std::fs::write(&scene, scene_text).unwrap();
    let out = dir.join("out.exr");
    let o = prism()
        .arg("render")
        .arg(&scene)
        .arg("-o")
        .arg(&out)
        .args(extra)
        .output()
        .unwrap();
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stderr).into_owned(),
        out.exists(),
    )
}

fn assert_input_error(name: &str, scene_text: &str, extra: &[&str], needles: &[&str]) {
    let (code, err, written) = run(name, scene_text, extra);
    assert_eq!(code, 2, "{name}: exit code {code}, stderr:\n{err}");
    assert!(!written, "{name}: an output file was written");
    assert!(err.starts_with("error: "), "{name}: {err}");
    assert!(!err.contains("panicked"), "{name}: {err}");
    for n in needles {
        assert!(err.contains(n), "{name}: stderr lacks `{n}`:\n{err}");
    }
}

#[test]
fn renders_and_writes_outputs() {
    let dir = workdir("good");
    let scene = dir.join("scene.ron");
    std::fs::write(&scene, GOOD).unwrap();
    let (out, png) = (dir.join("a.exr"), dir.join("a.png"));
    let o = prism()
        .args(["render"])
        .arg(&scene)
        .arg("-o")
        .arg(&out)
        .arg("--preview")
        .arg(&png)
        .args(["--spp", "2", "--seed", "4", "--threads", "1"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(out.exists() && png.exists());
    assert!(
        err.contains("rendered 16x12 at 2 spp") && err.contains("Msamples/s"),
        "{err}"
    );
    // No temporary files are left beside the outputs.
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(names.iter().all(|n| !n.contains(".tmp")), "{names:?}");
}

#[test]
fn help_documents_the_flags() {
    let o = prism().args(["render", "--help"]).output().unwrap();
    let text = String::from_utf8_lossy(&o.stdout);
    for flag in [
        "--output",
        "--spp",
        "--seed",
        "--threads",
        "--preview",
        "--exposure",
    ] {
        assert!(text.contains(flag), "render --help lacks {flag}");
    }
}

#[test]
fn malformed_ron_reports_line_and_column() {
    let broken = GOOD.replace("sampler: (spp: 4),", "sampler: (spp: 4,");
    assert_input_error("malformed", &broken, &[], &["scene.ron:"]);
    let (_, err, _) = run("malformed2", &broken, &[]);
    let loc = err.split("scene.ron:").nth(1).unwrap();
    let nums: Vec<&str> = loc.split(':').take(2).collect();
    assert!(
        nums.iter().all(|n| n.trim().parse::<usize>().is_ok()),
        "no line:column in {err}"
    );
}

#[test]
fn unknown_field_is_named() {
    assert_input_error(
        "typo",
        &GOOD.replace("width: 16", "widht: 16"),
        &[],
        &["widht", "scenes/README.md"],
    );
}

#[test]
fn unknown_material_lists_the_valid_ones() {
    assert_input_error(
        "material",
        &GOOD.replace(r#"material: "grey""#, r#"material: "gray""#),
        &[],
        &["shapes[0].material", "\"gray\"", "\"grey\""],
    );
}

#[test]
fn unknown_spectrum_name_lists_the_valid_ones() {
    assert_input_error(
        "spectrum",
        &GOOD.replace("Named(\"D65\")", "Named(\"D66\")"),
        &[],
        &["emitters[0].radiance", "D66", "D65", "FL11"],
    );
}

#[test]
fn missing_mesh_file() {
    assert_input_error(
        "mesh",
        &GOOD.replace(
            "Sphere(center: (0, 0, 4))",
            "Mesh(path: \"nope/bunny.ply\")",
        ),
        &[],
        &["shapes[0].shape.path", "bunny.ply", "does not exist"],
    );
}

#[test]
fn nan_and_negative_values() {
    assert_input_error(
        "nan",
        &GOOD.replace("Constant(0.5)", "Constant(NaN)"),
        &[],
        &["materials.\"grey\".reflectance", "finite"],
    );
    assert_input_error(
        "negative",
        &GOOD.replace("Constant(0.5)", "Tabulated([(400, 0.5), (700, -0.2)])"),
        &[],
        &["negative"],
    );
    assert_input_error(
        "above one",
        &GOOD.replace("Constant(0.5)", "Rgb(1.5, 0.2, 0.2)"),
        &[],
        &["[0, 1]"],
    );
    assert_input_error(
        "radius",
        &GOOD.replace(
            "Sphere(center: (0, 0, 4))",
            "Sphere(center: (0, 0, 4), radius: -1)",
        ),
        &[],
        &["radius"],
    );
    assert_input_error(
        "fov",
        &GOOD.replace("film:", "camera: (fov: 0), film:"),
        &[],
        &["camera.fov"],
    );
}

#[test]
fn zero_spp_and_zero_size() {
    assert_input_error(
        "spp file",
        &GOOD.replace("spp: 4", "spp: 0"),
        &[],
        &["sampler.spp"],
    );
    assert_input_error("spp flag", GOOD, &["--spp", "0"], &["--spp"]);
    assert_input_error(
        "size",
        &GOOD.replace("width: 16", "width: 0"),
        &[],
        &["film", "0×12"],
    );
}

#[test]
fn bad_spectrum_file_names_its_line() {
    let dir = workdir("specfile");
    std::fs::write(dir.join("paint.txt"), "nm value\n400 0.2\n500 zero\n").unwrap();
    let scene = dir.join("scene.ron");
    std::fs::write(
        &scene,
        GOOD.replace("Constant(0.5)", "File(path: \"paint.txt\")"),
    )
    .unwrap();
    let o = prism()
        .arg("render")
        .arg(&scene)
        .arg("-o")
        .arg(dir.join("x.exr"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("paint.txt:3:") && err.contains("`zero` is not a number"),
        "{err}"
    );
    assert!(!Path::new(&dir.join("x.exr")).exists());
}

#[test]
fn missing_scene_file() {
    let o = prism()
        .args(["render", "/nonexistent/scene.ron"])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("/nonexistent/scene.ron"));
}

/// `GOOD` with its emitter replaced.
fn with_emitter(emitter: &str) -> String {
    GOOD.replace(r#"Constant(radiance: Named("D65"))"#, emitter)
}

#[test]
fn missing_or_unreadable_envmap_image() {
    assert_input_error(
        "envmap missing",
        &with_emitter(r#"Envmap(filename: "nope/sky.exr")"#),
        &[],
        &[
            "scene.ron",
            "emitters[0].filename",
            "nope/sky.exr",
            "does not exist",
        ],
    );
    let dir = workdir("envmap-garbage");
    std::fs::write(dir.join("sky.exr"), "not an image").unwrap();
    let scene = dir.join("scene.ron");
    std::fs::write(&scene, with_emitter(r#"Envmap(filename: "sky.exr")"#)).unwrap();
    let o = prism()
        .arg("render")
        .arg(&scene)
        .arg("-o")
        .arg(dir.join("x.exr"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("scene.ron")
            && err.contains("emitters[0].filename")
            && err.contains("sky.exr"),
        "{err}"
    );
    assert!(!dir.join("x.exr").exists());
}

#[test]
fn bad_spot_parameters() {
    let spot = |params: &str| with_emitter(&format!("Spot({params})"));
    for (name, params, needles) in [
        (
            "cutoff 0",
            "cutoff_angle: 0",
            &["emitters[0].cutoff_angle", "(0, 90]"][..],
        ),
        (
            "cutoff 120",
            "cutoff_angle: 120",
            &["emitters[0].cutoff_angle"][..],
        ),
        (
            "cutoff nan",
            "cutoff_angle: NaN",
            &["emitters[0].cutoff_angle"][..],
        ),
        (
            "beam wider",
            "cutoff_angle: 20, beam_width: 25",
            &["emitters[0].beam_width", "cutoff_angle"][..],
        ),
        (
            "beam negative",
            "beam_width: -1",
            &["emitters[0].beam_width"][..],
        ),
        (
            "intensity negative",
            "intensity: Constant(-2)",
            &["emitters[0].intensity", "negative"][..],
        ),
    ] {
        assert_input_error(name, &spot(params), &[], needles);
    }
}

#[test]
fn bad_directional_and_envmap_parameters() {
    assert_input_error(
        "zero direction",
        &with_emitter("Directional(direction: (0, 0, 0))"),
        &[],
        &["emitters[0].direction", "non-zero"],
    );
    assert_input_error(
        "direction and to_world",
        &with_emitter(
            "Directional(direction: (0, -1, 0), to_world: [Rotate(axis: (1, 0, 0), angle: 90)])",
        ),
        &[],
        &["emitters[0]", "not both"],
    );
    assert_input_error(
        "irradiance nan",
        &with_emitter("Directional(irradiance: Constant(NaN))"),
        &[],
        &["emitters[0].irradiance", "finite"],
    );
    assert_input_error(
        "envmap scale",
        &with_emitter(r#"Envmap(filename: "sky.exr", scale: -1)"#),
        &[],
        &["emitters[0].scale", "≥ 0"],
    );
    assert_input_error(
        "envmap scaled",
        &with_emitter(r#"Envmap(filename: "sky.exr", to_world: [Scale((2, 1, 1))])"#),
        &[],
        &["emitters[0].to_world", "rotate"],
    );
}

#[test]
fn envmap_must_be_equirectangular() {
    for (name, w, h, needles) in [
        (
            "envmap 16x12",
            16,
            12,
            &["16×12", "equirectangular", "twice as wide as high"][..],
        ),
        ("envmap 4x2", 4, 2, &["4×2", "at least 6×3"][..]),
    ] {
        let dir = workdir(&name.replace(' ', "-"));
        exr::prelude::write_rgb_file(dir.join("sky.exr"), w, h, |_, _| (1.0f32, 1.0, 1.0)).unwrap();
        let scene = dir.join("scene.ron");
        std::fs::write(&scene, with_emitter(r#"Envmap(filename: "sky.exr")"#)).unwrap();
        let o = prism()
            .arg("render")
            .arg(&scene)
            .arg("-o")
            .arg(dir.join("x.exr"))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{name}: {err}");
        assert!(!dir.join("x.exr").exists(), "{name}");
        for n in ["scene.ron", "emitters[0].filename", "sky.exr"]
            .iter()
            .chain(needles)
        {
            assert!(err.contains(n), "{name}: stderr lacks `{n}`:\n{err}");
        }
    }
}

#[test]
fn bad_conductors() {
    let with = |m: &str| GOOD.replace("Diffuse(reflectance: Constant(0.5))", m);
    assert_input_error(
        "unknown metal",
        &with("Conductor(material: \"Unobtainium\")"),
        &[],
        &[
            "materials.\"grey\".material",
            "Unobtainium",
            "Au",
            "Pt",
            "none",
        ],
    );
    assert_input_error(
        "alpha zero",
        &with("RoughConductor(material: \"Au\", alpha: 0)"),
        &[],
        &["materials.\"grey\".alpha", "(0, 1]", "Conductor"],
    );
    assert_input_error(
        "alpha negative",
        &with("RoughConductor(alpha_u: 0.1, alpha_v: -0.2)"),
        &[],
        &["materials.\"grey\".alpha_v", "(0, 1]"],
    );
    assert_input_error(
        "alpha nan",
        &with("RoughConductor(alpha: NaN)"),
        &[],
        &["materials.\"grey\".alpha"],
    );
    assert_input_error(
        "alpha_u alone",
        &with("RoughConductor(alpha_u: 0.1)"),
        &[],
        &["materials.\"grey\"", "alpha_v"],
    );
    assert_input_error(
        "negative eta",
        &with("Conductor(eta: Tabulated([(400, 0.2), (700, -0.1)]), k: Constant(3))"),
        &[],
        &["materials.\"grey\".eta", "negative"],
    );
    assert_input_error(
        "rgb k",
        &with("RoughConductor(eta: Constant(0.2), k: Rgb(3, 2, 1))"),
        &[],
        &["materials.\"grey\".k", "RGB"],
    );
    assert_input_error(
        "metal and eta",
        &with("Conductor(material: \"Cu\", eta: Constant(1.5))"),
        &[],
        &["materials.\"grey\"", "not both"],
    );
}

/// `--accel embree` (or `accel: Embree`) in a build without the `embree` feature is an input
/// error that says how to get it; with the feature, it renders.
#[test]
fn accel_embree_needs_the_feature() {
    let with_field = GOOD.replace("\n)", "\n    accel: Embree,\n)");
    if cfg!(feature = "embree") {
        for (name, text, extra) in [
            ("embree-flag", GOOD, &["--accel", "embree"][..]),
            ("embree-field", with_field.as_str(), &[][..]),
        ] {
            let (code, err, written) = run(name, text, extra);
            assert!(code == 0 && written, "{name}: exit {code}: {err}");
        }
    } else {
        assert_input_error(
            "embree-flag",
            GOOD,
            &["--accel", "embree"],
            &["accel", "--features embree"],
        );
        assert_input_error(
            "embree-field",
            &with_field,
            &[],
            &["accel", "--features embree"],
        );
    }
}
#[test]
fn unreadable_textures() {
    let with = |m: &str| GOOD.replace("Diffuse(reflectance: Constant(0.5))", m);
    assert_input_error(
        "missing texture",
        &with("Diffuse(reflectance: Bitmap(path: \"textures/nope.png\"))"),
        &[],
        &["materials.\"grey\".reflectance", "nope.png"],
    );
    let dir = workdir("corrupt-texture-data");
    let bad = dir.join("corrupt.png");
    std::fs::write(&bad, b"\x89PNG\r\n\x1a\nthis is not a PNG").unwrap();
    assert_input_error(
        "corrupt texture",
        &with(&format!(
            "Diffuse(reflectance: Bitmap(path: {:?}))",
            bad.to_str().unwrap()
        )),
        &[],
        &["materials.\"grey\".reflectance", "corrupt.png"],
    );
    assert_input_error(
        "corrupt opacity texture",
        &with(&format!(
            "Mask(opacity: Bitmap(path: {:?}), bsdf: Diffuse())",
            bad.to_str().unwrap()
        )),
        &[],
        &["materials.\"grey\".opacity", "corrupt.png"],
    );
}

/// `prism export` writes spot, directional and envmap emitters with Mitsuba 3's parameter names,
/// defaults resolved, the map's absolute path and 4×4 row-major matrices.
#[test]
fn export_writes_spot_directional_and_envmap() {
    let dir = workdir("export-emitters");
    exr::prelude::write_rgb_file(dir.join("sky.exr"), 8, 4, |_, _| (1.0f32, 1.0, 1.0)).unwrap();
    let scene = dir.join("scene.ron");
    std::fs::write(
        &scene,
        GOOD.replace(
            r#"emitters: [Constant(radiance: Named("D65"))]"#,
            r#"emitters: [
                Spot(to_world: [Translate((1, 2, 3))]),
                Directional(irradiance: Constant(2), direction: (0, 0, -2)),
                Envmap(filename: "sky.exr", scale: 0.5, to_world: [Rotate(axis: (0, 1, 0), angle: 90)]),
            ]"#,
        ),
    )
    .unwrap();
    let out = dir.join("out");
    let o = prism()
        .arg("export")
        .arg(&scene)
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("scene.json")).unwrap()).unwrap();
    let e = &json["emitters"];
    let close = |v: &serde_json::Value, want: &[f64]| {
        let got: Vec<f64> = v
            .as_array()
            .unwrap()
            .iter()
            .flat_map(|r| match r.as_array() {
                Some(row) => row.iter().map(|x| x.as_f64().unwrap()).collect(),
                None => vec![r.as_f64().unwrap()],
            })
            .collect();
        assert_eq!(got.len(), want.len());
        assert!(
            got.iter().zip(want).all(|(a, b)| (a - b).abs() < 1e-6),
            "{got:?} vs {want:?}"
        );
    };
    // The spot: Mitsuba's defaults, cutoff 20° and beam ¾ of it; intensity D65 tabulated.
    assert_eq!(e[0]["type"], "spot");
    assert_eq!(e[0]["cutoff_angle"], 20.0);
    assert_eq!(e[0]["beam_width"], 15.0);
    assert_eq!(e[0]["intensity"]["type"], "irregular");
    #[rustfmt::skip]
    close(&e[0]["to_world"], &[1., 0., 0., 1., 0., 1., 0., 2., 0., 0., 1., 3., 0., 0., 0., 1.]);
    assert_eq!(e[1]["type"], "directional");
    close(&e[1]["direction"], &[0.0, 0.0, -1.0]);
    assert_eq!(e[1]["irradiance"]["value"], 2.0);
    assert_eq!(e[2]["type"], "envmap");
    assert_eq!(
        e[2]["filename"].as_str().unwrap(),
        dir.join("sky.exr")
            .canonicalize()
            .unwrap()
            .to_str()
            .unwrap()
    );
    assert_eq!(e[2]["scale"], 0.5);
    // A 90° turn about +y: x → −z, z → x.
    #[rustfmt::skip]
    close(&e[2]["to_world"], &[0., 0., 1., 0., 0., 1., 0., 0., -1., 0., 0., 0., 0., 0., 0., 1.]);
}

// Dielectrics.

/// Bad indices of refraction and roughness: exit code 2, the file and the field named, and the
/// valid names listed where a name was misspelt.
#[test]
fn bad_dielectric_parameters() {
    let glass = |m: &str| GOOD.replace("Diffuse(reflectance: Constant(0.5))", m);
    assert_input_error(
        "ior name",
        &glass("Dielectric(int_ior: Named(\"watter\"))"),
        &[],
        &[
            "scene.ron",
            "materials.\"grey\".int_ior",
            "watter",
            "water",
            "diamond",
        ],
    );
    assert_input_error(
        "glass name",
        &glass("RoughDielectric(int_ior: Glass(\"BK8\"))"),
        &[],
        &["materials.\"grey\".int_ior", "BK8", "N-BK7", "N-SF11"],
    );
    assert_input_error(
        "ior zero",
        &glass("Dielectric(ext_ior: 0)"),
        &[],
        &["materials.\"grey\".ext_ior", "> 0"],
    );
    assert_input_error(
        "ior nan",
        &glass("ThinDielectric(int_ior: NaN)"),
        &[],
        &["materials.\"grey\".int_ior", "finite"],
    );
    assert_input_error(
        "ior negative cauchy",
        &glass("Dielectric(int_ior: Cauchy(a: -1.5, b: 0.004))"),
        &[],
        &["materials.\"grey\".int_ior", "> 0"],
    );
    assert_input_error(
        "ior table too short",
        &glass("Dielectric(int_ior: Spectrum(Tabulated([(450, 1.52), (650, 1.51)])))"),
        &[],
        &["materials.\"grey\".int_ior", "cover"],
    );
    assert_input_error(
        "ior sellmeier pole",
        &glass("Dielectric(int_ior: Sellmeier(b: (1, 0, 0), c: (0.25, 0, 0)))"),
        &[],
        &["materials.\"grey\".int_ior", "pole"],
    );
    assert_input_error(
        "ior rgb",
        &glass("Dielectric(int_ior: Spectrum(Rgb(1, 1, 1)))"),
        &[],
        &["materials.\"grey\".int_ior", "RGB"],
    );
    assert_input_error(
        "ior misspelt form",
        &glass("Dielectric(int_ior: Glas(\"BK7\"))"),
        &[],
        &["scene.ron:", "index of refraction"],
    );
    assert_input_error(
        "alpha negative",
        &glass("RoughDielectric(alpha: -0.1)"),
        &[],
        &["materials.\"grey\".alpha", "(0, 1]", "Dielectric"],
    );
    assert_input_error(
        "alpha both",
        &glass("RoughDielectric(alpha: 0.1, alpha_u: 0.2, alpha_v: 0.1)"),
        &[],
        &["materials.\"grey\"", "alpha_u"],
    );
    assert_input_error(
        "alpha half",
        &glass("RoughDielectric(alpha_u: 0.2)"),
        &[],
        &["materials.\"grey\"", "both `alpha_u` and `alpha_v`"],
    );
    assert_input_error(
        "index matched",
        &glass("RoughDielectric(int_ior: 1.333, ext_ior: \"water\")"),
        &[],
        &["materials.\"grey\"", "differ"],
    );
}

/// Every IOR form a scene may write renders (Mitsuba's string names included).
#[test]
fn dielectric_forms_render() {
    for m in [
        "Dielectric()",
        "Dielectric(int_ior: \"water\", ext_ior: \"air\")",
        "Dielectric(int_ior: Value(1.7), ext_ior: 1)",
        "RoughDielectric(distribution: Ggx, alpha_u: 0.05, alpha_v: 0.2, int_ior: Glass(\"fused silica\"))",
        "RoughDielectric(alpha: Checkerboard(value0: 0.05, value1: 0.3), int_ior: Sellmeier(b: (1.03961212, 0.231792344, 1.01046945), c: (0.00600069867, 0.0200179144, 103.560653)))",
        "ThinDielectric(int_ior: Cauchy(a: 1.5046, b: 0.0042), specular_transmittance: Rgb(0.9, 0.8, 0.7))",
        "Dielectric(int_ior: Spectrum(Tabulated([(300, 1.53), (900, 1.50)])))",
    ] {
        let (code, err, written) = run(
            "forms",
            &GOOD.replace("Diffuse(reflectance: Constant(0.5))", m),
            &[],
        );
        assert!(code == 0 && written, "{m}: exit {code}\n{err}");
    }
}

/// `prism export` writes a dielectric's indices as Mitsuba takes them: numbers when the
/// interface is not dispersive; otherwise both sides as spectra (a tabulated glass, a
/// constant air) and `"dispersive": true`. Tolerance: 1e-6 on n (JSON round trip of f32).
#[test]
fn export_writes_dielectric_iors() {
    let dir = workdir("export");
    let scene = dir.join("scene.ron");
    let text = GOOD
        .replace(
            r#"materials: { "grey": Diffuse(reflectance: Constant(0.5)) }"#,
            r#"materials: {
                "a": Dielectric(int_ior: "water"),
                "b": RoughDielectric(distribution: Ggx, alpha_u: 0.05, alpha_v: 0.2, int_ior: Glass("BK7")),
                "c": ThinDielectric(int_ior: 1.6, ext_ior: 1.1),
            }"#,
        )
        .replace(
            r#"shapes: [(shape: Sphere(center: (0, 0, 4)), material: "grey")]"#,
            r#"shapes: [
                (shape: Sphere(center: (0, 0, 4)), material: "a"),
                (shape: Sphere(center: (1, 0, 4)), material: "b"),
                (shape: Sphere(center: (2, 0, 4)), material: "c"),
            ]"#,
        );
    std::fs::write(&scene, text).unwrap();
    let out = dir.join("exported");
    let o = prism()
        .arg("export")
        .arg(&scene)
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("scene.json")).unwrap()).unwrap();
    let m = &json["materials"];
    let close = |v: &serde_json::Value, x: f64| (v.as_f64().unwrap() - x).abs() < 1e-6;
    assert_eq!(m[0]["type"], "dielectric");
    assert!(close(&m[0]["int_ior"], 1.333) && close(&m[0]["ext_ior"], 1.000277));
    assert_eq!(m[0]["dispersive"], false);
    assert_eq!(m[0]["specular_transmittance"]["type"], "constant");
    assert_eq!(m[1]["type"], "roughdielectric");
    assert_eq!(m[1]["distribution"], "ggx");
    assert!(close(&m[1]["alpha_u"]["value"], 0.05) && close(&m[1]["alpha_v"]["value"], 0.2));
    assert_eq!(m[1]["dispersive"], true);
    assert_eq!(m[1]["ext_ior"]["type"], "constant");
    assert!(close(&m[1]["ext_ior"]["value"], 1.000277));
    let (nm, n) = (&m[1]["int_ior"]["wavelengths"], &m[1]["int_ior"]["values"]);
    assert_eq!(m[1]["int_ior"]["type"], "irregular");
    // N-BK7 at the helium d line, 587.56 nm: the table's neighbours bracket n_d = 1.51680.
    let i = nm
        .as_array()
        .unwrap()
        .iter()
        .position(|w| w.as_f64().unwrap() >= 587.5)
        .unwrap();
    let (lo, hi) = (n[i].as_f64().unwrap(), n[i - 1].as_f64().unwrap());
    assert!(lo < 1.51680 && 1.51680 < hi + 1e-5, "{lo} {hi}");
    assert_eq!(m[2]["type"], "thindielectric");
    assert!(close(&m[2]["int_ior"], 1.6) && close(&m[2]["ext_ior"], 1.1));
}

/// Plastics take a dielectric's index forms (numbers, names) but, as in Mitsuba, only
/// constant ones: a dispersive index is an input error naming the field.
#[test]
fn plastic_iors() {
    let with = |m: &str| GOOD.replace("Diffuse(reflectance: Constant(0.5))", m);
    for m in [
        "Plastic(int_ior: \"bk7\")",
        "RoughPlastic(int_ior: Named(\"acrylic glass\"), ext_ior: \"water\")",
        "Plastic(int_ior: 1.6, ext_ior: Spectrum(Constant(1.0)))",
    ] {
        let (code, err, written) = run("plastic ior", &with(m), &[]);
        assert!(code == 0 && written, "{m}: exit {code}\n{err}");
    }
    assert_input_error(
        "dispersive plastic",
        &with("RoughPlastic(int_ior: Glass(\"SF11\"))"),
        &[],
        &[
            "materials.\"grey\".int_ior",
            "varies with wavelength",
            "Dielectric",
        ],
    );
    assert_input_error(
        "cauchy plastic",
        &with("Plastic(ext_ior: Cauchy(a: 1.3, b: 0.003))"),
        &[],
        &["materials.\"grey\".ext_ior", "one number"],
    );
    assert_input_error(
        "unknown plastic ior",
        &with("Plastic(int_ior: \"polypropylen\")"),
        &[],
        &["materials.\"grey\".int_ior", "polypropylene"],
    );
}

#[test]
fn bad_caustics_settings() {
    let with = |c: &str| {
        GOOD.replace(
            "sampler:",
            &format!("integrator: (caustics: Some({c})), sampler:"),
        )
    };
    assert_input_error(
        "caustics light_paths",
        &with("(light_paths: 0)"),
        &[],
        &["integrator.caustics.light_paths", "positive"],
    );
    assert_input_error(
        "caustics bright_ratio",
        &with("(bright_ratio: NaN)"),
        &[],
        &["integrator.caustics.bright_ratio"],
    );
    assert_input_error(
        "caustics max_roughness",
        &with("(max_roughness: 2)"),
        &[],
        &["integrator.caustics.max_roughness", "[0, 1]"],
    );
    assert_input_error(
        "caustics unknown field",
        &with("(light_path: 1)"),
        &[],
        &["light_path", "light_paths"],
    );
}

/// `--caustics on` turns light tracing on with the defaults (the EXR's metadata says so);
/// `--caustics off` turns a scene's off.
#[test]
fn caustics_flag_overrides_the_scene() {
    let dir = workdir("caustics-flag");
    let scene = dir.join("scene.ron");
    std::fs::write(
        &scene,
        GOOD.replace(
            "sampler:",
            "integrator: (caustics: Some((light_paths: 2))), sampler:",
        ),
    )
    .unwrap();
    for (flag, want) in [
        (None, "light_paths 2"),
        (Some("off"), "caustics off"),
        (Some("on"), "light_paths 2"),
    ] {
        let out = dir.join("out.exr");
        let mut cmd = prism();
        cmd.arg("render").arg(&scene).arg("-o").arg(&out).arg("-q");
        if let Some(f) = flag {
            cmd.args(["--caustics", f]);
        }
        let o = cmd.output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let exr = std::fs::read(&out).unwrap();
        let text = String::from_utf8_lossy(&exr);
        assert!(
            text.contains(want),
            "--caustics {flag:?}: metadata lacks `{want}`"
        );
    }
    let plain = GOOD.replace("sampler:", "integrator: (max_depth: 3), sampler:");
    std::fs::write(&scene, plain).unwrap();
    let out = dir.join("out.exr");
    let o = prism()
        .args(["render", "-q", "--caustics", "on", "-o"])
        .arg(&out)
        .arg(&scene)
        .output()
        .unwrap();
    assert!(o.status.success());
    let text = String::from_utf8_lossy(&std::fs::read(&out).unwrap()).into_owned();
    assert!(
        text.contains("light_paths 0.1"),
        "--caustics on: defaults not taken"
    );
}
