//! glTF 2.0 import: every Khronos sample model in tests/data/gltf (credits in its README) loads
//! and renders with finite pixels; instance, triangle and bound counts match the file (read
//! here straight from its JSON); node transforms (TRS and column-major matrices) and the camera
//! put OrientationTest's arrows where the file says; a glTF camera renders the same pixels as
//! the same camera written in RON; a RON scene includes a glTF file with a transform and
//! material overrides; bad input exits with code 2 naming the file, the field and the fix.
//! Textures beyond base colour (specular, specular colour, transmission), KHR_texture_transform
//! rotation and texCoord, TEXCOORD_1, normal maps on mirrored uvs, the ignored occlusion
//! texture, and orthographic cameras against RON, on small glTF files the tests write.

mod scratch;
use glam::{Mat4, Quat, Vec3};
use prism::bsdf::BsdfLobe;
use prism::load::gltf;
use prism::math::portable;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

const MODELS: &[&str] = &[
    "Box",
    "BoxTextured",
    "Cameras",
    "OrientationTest",
    "SimpleMeshes",
    "SimpleSparseAccessor",
    "Triangle",
    "TriangleWithoutIndices",
];

fn model(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/gltf")
        .join(format!("{name}.gltf"))
}

fn workdir(name: &str) -> scratch::Scratch {
    scratch::scratch("gltf", name)
}

/// Renders a loaded job at a small size; returns the RGB channels.
fn render(job: &prism::load::Job) -> Vec<f32> {
    let (film, _) = prism::integrator::render(&job.scene, &job.settings, &job.channels, &|_| {});
    ["R", "G", "B"]
        .iter()
        .flat_map(|c| film.channel(c).expect("rgb channels").to_vec())
        .collect()
}

fn small(cfg: &mut prism::config::SceneConfig) {
    cfg.film.width = 32;
    cfg.film.height = 24;
    cfg.sampler.spp = prism::config::Spp::Fixed(2);
    cfg.spectral.wavelengths = 4;
    cfg.outputs.bands = Some(0);
}

/// A node's local matrix from its JSON (column-major `matrix`, or T·R·S).
fn local_matrix(n: &Value) -> Mat4 {
    if let Some(m) = n.get("matrix") {
        let v: Vec<f32> = m
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap() as f32)
            .collect();
        return Mat4::from_cols_slice(&v);
    }
    let arr = |k: &str, d: &[f32]| -> Vec<f32> {
        n.get(k).map_or(d.to_vec(), |a| {
            a.as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap() as f32)
                .collect()
        })
    };
    let t = arr("translation", &[0.0; 3]);
    let r = arr("rotation", &[0.0, 0.0, 0.0, 1.0]);
    let s = arr("scale", &[1.0; 3]);
    Mat4::from_scale_rotation_translation(
        Vec3::from_slice(&s),
        Quat::from_xyzw(r[0], r[1], r[2], r[3]),
        Vec3::from_slice(&t),
    )
}

/// (mesh instances, triangles, world bounds of the accessors' min/max boxes) from the JSON.
fn expected_counts(json: &Value) -> (usize, usize, Vec3, Vec3) {
    let scene = json.get("scene").and_then(Value::as_u64).unwrap_or(0) as usize;
    let roots: Vec<usize> = json["scenes"][scene]["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_u64().unwrap() as usize)
        .collect();
    let mut stack: Vec<(usize, Mat4)> = roots.into_iter().map(|r| (r, Mat4::IDENTITY)).collect();
    let (mut instances, mut tris) = (0, 0);
    let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
    while let Some((i, parent)) = stack.pop() {
        let n = &json["nodes"][i];
        let world = parent * local_matrix(n);
        if let Some(m) = n.get("mesh").and_then(Value::as_u64) {
            instances += 1;
            for p in json["meshes"][m as usize]["primitives"].as_array().unwrap() {
                let pos =
                    &json["accessors"][p["attributes"]["POSITION"].as_u64().unwrap() as usize];
                let count = match p.get("indices").and_then(Value::as_u64) {
                    Some(ix) => json["accessors"][ix as usize]["count"].as_u64().unwrap(),
                    None => pos["count"].as_u64().unwrap(),
                };
                tris += count as usize / 3;
                let v3 = |k: &str| {
                    let a: Vec<f32> = pos[k]
                        .as_array()
                        .unwrap()
                        .iter()
                        .map(|x| x.as_f64().unwrap() as f32)
                        .collect();
                    Vec3::from_slice(&a)
                };
                let (a, b) = (v3("min"), v3("max"));
                for c in 0..8 {
                    let corner = Vec3::new(
                        if c & 1 == 0 { a.x } else { b.x },
                        if c & 2 == 0 { a.y } else { b.y },
                        if c & 4 == 0 { a.z } else { b.z },
                    );
                    let w = world.transform_point3(corner);
                    lo = lo.min(w);
                    hi = hi.max(w);
                }
            }
        }
        if let Some(ch) = n.get("children").and_then(Value::as_array) {
            for c in ch {
                stack.push((c.as_u64().unwrap() as usize, world));
            }
        }
    }
    (instances, tris, lo, hi)
}

#[test]
fn every_model_loads_and_renders_finite_pixels() {
    for name in MODELS {
        let path = model(name);
        let job = prism::load::load(&path, small).unwrap_or_else(|e| panic!("{name}: {e}"));
        let px = render(&job);
        assert!(
            px.iter().all(|v| v.is_finite()),
            "{name}: non-finite pixels"
        );
        assert!(px.iter().any(|&v| v > 0.0), "{name}: black image");
    }
}

/// Instances, triangles and bounds against the file's own JSON. The bounds of the accessors'
/// boxes after the node transforms enclose the geometry; where every transform maps the axes to
/// axes (all models but the rotated ones) they are exact, else the walk's bounds lie inside.
#[test]
fn counts_and_bounds_match_the_file() {
    for name in MODELS {
        let path = model(name);
        let json: Value = serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
        let (instances, tris, lo, hi) = expected_counts(&json);
        let m = gltf::open(&path).unwrap();
        let w = gltf::walk(&m, Mat4::IDENTITY, &mut Vec::new()).unwrap();
        assert_eq!(w.mesh_instances, instances, "{name}: mesh instances");
        let got_tris: usize = w.primitives.iter().map(|p| p.mesh.indices.len()).sum();
        assert_eq!(got_tris, tris, "{name}: triangles");
        let (blo, bhi) = w.bounds.unwrap();
        let tol = 1e-4 * (hi - lo).length().max(1.0);
        let axis_aligned = !matches!(*name, "Cameras" | "OrientationTest");
        if axis_aligned {
            assert!(
                (blo - lo).abs().max_element() < tol && (bhi - hi).abs().max_element() < tol,
                "{name}: bounds {blo}..{bhi}, file {lo}..{hi}"
            );
        } else {
            assert!(
                blo.cmpge(lo - tol).all() && bhi.cmple(hi + tol).all(),
                "{name}: bounds {blo}..{bhi} outside {lo}..{hi}"
            );
        }
        // The scene built from it holds the same triangles, one shape per primitive instance.
        let job = prism::load::load(&path, small).unwrap();
        assert_eq!(
            job.scene.primitive_count(),
            tris,
            "{name}: scene primitives"
        );
        assert_eq!(job.scene.shape_name.len(), w.primitives.len());
    }
    // SimpleMeshes: one mesh used by two nodes, the second moved by +1 in x.
    let m = gltf::open(&model("SimpleMeshes")).unwrap();
    let w = gltf::walk(&m, Mat4::IDENTITY, &mut Vec::new()).unwrap();
    assert_eq!(w.primitives.len(), 2);
    let d = w.primitives[1].mesh.positions[0] - w.primitives[0].mesh.positions[0];
    assert!((d - Vec3::X).length() < 1e-6, "{d}");
    assert_eq!(w.primitives[0].name, "node0");
}

/// OrientationTest: arrows at ±5 on each axis (TRS nodes and column-major matrix nodes). Their
/// centroids must sit on their axis in the world, and the camera ray through each arrow's
/// projection must hit that arrow: +x to the right of the image, +y above its centre.
#[test]
fn orientation_test_comes_out_the_right_way_up() {
    let path = model("OrientationTest");
    let job = prism::load::load(&path, small).unwrap();
    let s = &job.scene;
    let centroid = |name: &str| -> (usize, Vec3) {
        let i = s
            .shape_name
            .iter()
            .position(|n| n.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("no shape {name}"));
        let prism::shape::Shape::Mesh(m) = &s.shapes[i] else {
            panic!()
        };
        let c = m.positions.iter().copied().sum::<Vec3>() / m.positions.len() as f32;
        (i, c)
    };
    for (name, axis) in [
        ("ArrowX1", Vec3::X),
        ("ArrowX2", -Vec3::X),
        ("ArrowY1", Vec3::Y),
        ("ArrowY2", -Vec3::Y),
        ("ArrowZ1", Vec3::Z),
        ("ArrowZ2", -Vec3::Z),
    ] {
        let (_, c) = centroid(name);
        // Along its axis at about 5; the arrow's length runs across it.
        assert!(
            c.dot(axis) > 4.0 && c.dot(axis) < 6.0,
            "{name} centroid {c}"
        );
    }
    let (w, h) = (32.0, 24.0);
    // (name, to the right of the centre?, above the centre?)
    for (name, right, up) in [
        ("ArrowX1", Some(true), None),
        ("ArrowX2", Some(false), None),
        ("ArrowY1", None, Some(true)),
        ("ArrowY2", None, Some(false)),
    ] {
        let (_, c) = centroid(name);
        let pr = s.camera.project(c, 0.0).expect("in view");
        if let Some(r) = right {
            assert_eq!(pr.film.x > w / 2.0, r, "{name} at {}", pr.film);
        }
        if let Some(u) = up {
            assert_eq!(pr.film.y < h / 2.0, u, "{name} at {}", pr.film);
        }
    }
    // ArrowZ1 points at the camera, in front of the base cube: the ray through its projection
    // hits it (the other arrows hide partly behind the cube).
    let (i, c) = centroid("ArrowZ1");
    let pr = s.camera.project(c, 0.0).expect("in view");
    let hit = s
        .intersect(&s.camera.ray(
            pr.film,
            &mut prism::sampler::PixelSampler::new(prism::sampler::SamplerKind::Independent, 0, 0),
        ))
        .expect("the arrow is hit");
    assert_eq!(
        hit.shape as usize, i,
        "ArrowZ1: the ray through its projection hits {:?}",
        s.shape_name[hit.shape as usize]
    );
}

/// Cameras.gltf's perspective camera (yfov 0.7 rad, aspect 1, node at (0.5, 0.5, 3)) and the
/// same camera written in RON render identical pixels.
#[test]
fn gltf_camera_matches_ron_camera() {
    let path = model("Cameras");
    let direct = prism::load::load(&path, small).unwrap();
    let fov = 0.7f32.to_degrees();
    let dir = workdir("camera");
    std::fs::copy(&path, dir.join("Cameras.gltf")).unwrap();
    let ron = format!(
        "(camera: (fov: {fov:?}, fov_axis: Y, near_clip: 0.01, far_clip: 100, \
           to_world: [Scale((-1, 1, -1)), Translate((0.5, 0.5, 3.0))]), \
         film: (width: 32, height: 24), sampler: (spp: 2), spectral: (wavelengths: 4), outputs: (bands: 0), \
         shapes: [(shape: Gltf(path: \"Cameras.gltf\"))], emitters: [Constant(radiance: Named(\"D65\"))])"
    );
    let scene = dir.join("scene.ron");
    std::fs::write(&scene, ron).unwrap();
    let via_ron = prism::load::load(&scene, |_| {}).unwrap();
    assert_eq!(direct.scene.camera, via_ron.scene.camera);
    assert_eq!(render(&direct), render(&via_ron), "pixels differ");
    // The direct load took the file's aspect ratio: 576 × 576 before `small` resized it.
    let (cfg, _) = gltf::scene_config(&path).unwrap();
    assert_eq!((cfg.film.width, cfg.film.height), (576, 576));
}

/// A RON scene places a glTF model with `to_world` and replaces its materials by name.
#[test]
fn ron_includes_gltf_with_transform_and_overrides() {
    let dir = workdir("include");
    std::fs::copy(model("OrientationTest"), dir.join("o.gltf")).unwrap();
    let ron = r#"(film: (width: 16, height: 12), sampler: (spp: 1), outputs: (bands: 0),
        camera: (to_world: [LookAt(origin: (0, 0, 40), target: (0, 0, 0), up: (0, 1, 0))]),
        materials: { "gold": Conductor(material: "Au") },
        shapes: [(shape: Gltf(path: "o.gltf", materials: {"MatX1": "gold"}), to_world: [Translate((10, 0, 0))])],
        emitters: [Constant(radiance: Named("D65"))])"#;
    std::fs::write(dir.join("s.ron"), ron).unwrap();
    let job = prism::load::load(&dir.join("s.ron"), |_| {}).unwrap();
    let s = &job.scene;
    let (lo, hi) = s.bounds();
    let m = gltf::open(&model("OrientationTest")).unwrap();
    let (wlo, whi) = gltf::walk(&m, Mat4::IDENTITY, &mut Vec::new())
        .unwrap()
        .bounds
        .unwrap();
    assert!(
        (lo - wlo - Vec3::new(10.0, 0.0, 0.0)).length() < 1e-4
            && (hi - whi - Vec3::new(10.0, 0.0, 0.0)).length() < 1e-4
    );
    // Every shape with glTF material MatX1 (ArrowX1, TargetX1) uses the scene's "gold" (index 0).
    let gold: Vec<_> = (0..s.shapes.len())
        .filter(|&i| s.shape_material[i] == 0)
        .map(|i| s.shape_name[i].clone().unwrap())
        .collect();
    assert!(
        !gold.is_empty() && gold.iter().all(|n| n.ends_with("X1")),
        "{gold:?}"
    );
    assert!(matches!(
        s.materials[0],
        prism::bsdf::Material::Conductor(_)
    ));
}

fn prism_cli(args: &[&str]) -> (i32, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_prism"))
        .args(args)
        .output()
        .unwrap();
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// Bad glTF input: exit code 2, an error naming the file, the field and the fix; no output.
#[test]
fn bad_gltf_input_is_reported() {
    let dir = workdir("bad");
    let tri = std::fs::read_to_string(model("Triangle")).unwrap();
    let mut cases: Vec<(&str, String, Vec<&str>)> = vec![
        ("invalid_json", "{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [".into(), vec!["not valid glTF JSON", "invalid_json.gltf:"]),
        ("old_version", "{\"asset\": {\"version\": \"1.0\"}}".into(), vec!["asset.version", "glTF 1.0"]),
        (
            "missing_buffer",
            r#"{"asset": {"version": "2.0"}, "buffers": [{"uri": "gone.bin", "byteLength": 36}]}"#.into(),
            vec!["buffers[0].uri", "gone.bin` does not exist", "beside"],
        ),
        (
            "missing_image",
            r#"{"asset": {"version": "2.0"}, "images": [{"uri": "gone.png"}]}"#.into(),
            vec!["images[0].uri", "gone.png` does not exist", "beside"],
        ),
        (
            "bad_accessor",
            r#"{"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": 7}}]}]}"#.into(),
            vec!["invalid glTF", "meshes[0]", "validator"],
        ),
    ];
    for ext in [
        "KHR_draco_mesh_compression",
        "EXT_meshopt_compression",
        "KHR_texture_basisu",
    ] {
        let text = tri.replacen(
            "{",
            &format!("{{\"extensionsUsed\": [\"{ext}\"], \"extensionsRequired\": [\"{ext}\"],"),
            1,
        );
        let fix = if ext == "KHR_texture_basisu" {
            "PNG/JPEG"
        } else {
            "without mesh compression"
        };
        cases.push((ext, text, vec!["extensionsRequired[0]", ext, fix]));
    }
    for (name, text, needles) in &cases {
        let file = dir.join(format!("{name}.gltf"));
        std::fs::write(&file, text).unwrap();
        let out = dir.join(format!("{name}.exr"));
        let (code, err) = prism_cli(&[
            "render",
            file.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "-q",
        ]);
        assert_eq!(code, 2, "{name}: exit {code}: {err}");
        assert!(!out.exists(), "{name}: wrote output");
        assert!(!err.contains("panicked"), "{name}: {err}");
        assert!(
            err.contains(&format!("{name}.gltf")),
            "{name}: the file is not named: {err}"
        );
        for n in needles {
            assert!(err.contains(n), "{name}: stderr lacks `{n}`: {err}");
        }
    }
    // An override naming a glTF material the file lacks.
    std::fs::copy(model("OrientationTest"), dir.join("o.gltf")).unwrap();
    let ron = r#"(materials: {"m": Diffuse()}, shapes: [(shape: Gltf(path: "o.gltf", materials: {"Nope": "m"}))])"#;
    std::fs::write(dir.join("s.ron"), ron).unwrap();
    let (code, err) = prism_cli(&[
        "render",
        dir.join("s.ron").to_str().unwrap(),
        "-o",
        dir.join("s.exr").to_str().unwrap(),
        "-q",
    ]);
    assert_eq!(code, 2, "{err}");
    for n in [
        "shapes[0].shape.materials.\"Nope\"",
        "no material named \"Nope\"",
        "\"MatX1\"",
    ] {
        assert!(err.contains(n), "stderr lacks `{n}`: {err}");
    }
}

/// A one-triangle glTF with `materials` (JSON text) used by its primitive (material 0), and
/// `extensions_used`.
fn triangle_gltf(materials: &str, extensions_used: &str) -> String {
    // Positions (0,0,0), (1,0,0), (0,1,0) as little-endian f32.
    let mut bytes = Vec::new();
    for v in [0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0] {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    let b64 = base64::encode(&bytes);
    format!(
        r#"{{"asset": {{"version": "2.0"}}, "extensionsUsed": [{extensions_used}], "scene": 0, "scenes": [{{"nodes": [0]}}],
        "nodes": [{{"mesh": 0, "name": "tri"}}], "materials": {materials},
        "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "material": 0}}]}}],
        "buffers": [{{"byteLength": 36, "uri": "data:application/octet-stream;base64,{b64}"}}],
        "bufferViews": [{{"buffer": 0, "byteLength": 36}}],
        "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}}]}}"#
    )
}

fn load_text(name: &str, gltf_text: &str) -> prism::load::Job {
    let dir = workdir(name);
    let file = dir.join(format!("{name}.gltf"));
    std::fs::write(&file, gltf_text).unwrap();
    prism::load::load(&file, small).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// KHR_materials_dispersion (20 / V_d) on a transmissive material becomes a dispersive
/// dielectric with that Abbe number and n_d = ior; emission × KHR_materials_emissive_strength
/// an area light (and no default environment); alpha MASK below the cutoff a transparent mask.
#[test]
fn dispersion_emission_and_alpha() {
    let glass = triangle_gltf(
        r#"[{"name": "flint", "extensions": {"KHR_materials_ior": {"ior": 1.62}, "KHR_materials_transmission": {"transmissionFactor": 1},
             "KHR_materials_dispersion": {"dispersion": 0.5}}, "pbrMetallicRoughness": {"metallicFactor": 0, "roughnessFactor": 0}}]"#,
        r#""KHR_materials_ior", "KHR_materials_transmission", "KHR_materials_dispersion""#,
    );
    let job = load_text("dispersion", &glass);
    let prism::bsdf::Material::Dielectric(prism::bsdf::DielectricParams { ior, .. }) =
        &job.scene.materials[0]
    else {
        panic!("{:?}", job.scene.materials[0])
    };
    assert!(ior.dispersive());
    assert!(
        (ior.int.abbe_number() - 40.0).abs() < 0.01,
        "{}",
        ior.int.abbe_number()
    );
    assert!((ior.int.eval_one(587.56) - 1.62).abs() < 1e-5);
    assert!(job.scene.materials[0].dispersive());
    // KHR_materials_volume is rendered thin-walled and warned about, except on a dispersive
    // glass, which refracts as a solid dielectric.
    let volume = |dispersion: &str| {
        triangle_gltf(
            &format!(
                r#"[{{"extensions": {{"KHR_materials_transmission": {{"transmissionFactor": 1}}, "KHR_materials_volume": {{"thicknessFactor": 1}}{dispersion}}}}}]"#
            ),
            r#""KHR_materials_transmission", "KHR_materials_volume", "KHR_materials_dispersion""#,
        )
    };
    let thin = load_text("volume", &volume(""));
    assert!(
        thin.warnings.len() == 1 && thin.warnings[0].contains("thin-walled"),
        "{:?}",
        thin.warnings
    );
    let solid = load_text(
        "volume_dispersion",
        &volume(r#", "KHR_materials_dispersion": {"dispersion": 0.5}"#),
    );
    assert!(solid.warnings.is_empty(), "{:?}", solid.warnings);

    let lamp = triangle_gltf(
        r#"[{"emissiveFactor": [1, 0.5, 0.2], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4}}}]"#,
        r#""KHR_materials_emissive_strength""#,
    );
    let job = load_text("emission", &lamp);
    assert_eq!(
        job.scene.emitters.len(),
        1,
        "one area light, no default environment"
    );
    assert_eq!(job.scene.shape_emitter, vec![Some(0)]);
    assert!(matches!(
        job.scene.emitters[0],
        prism::emitter::Emitter::Area(_)
    ));

    let cut = triangle_gltf(
        r#"[{"alphaMode": "MASK", "alphaCutoff": 0.5, "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.3]}}]"#,
        "",
    );
    let job = load_text("mask", &cut);
    let prism::bsdf::Material::Mask { opacity, .. } = &job.scene.materials[0] else {
        panic!()
    };
    assert_eq!(*opacity, prism::texture::FloatTexture::Constant(0.0));
    let blend = triangle_gltf(
        r#"[{"alphaMode": "BLEND", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.3]}}]"#,
        "",
    );
    let job = load_text("blend", &blend);
    let prism::bsdf::Material::Mask { opacity, .. } = &job.scene.materials[0] else {
        panic!()
    };
    assert_eq!(*opacity, prism::texture::FloatTexture::Constant(0.3));
}

/// The unit quad's two triangles in z = 0: their six corners (x, y).
const QUAD_CORNERS: [[f32; 2]; 6] = [
    [0.0, 0.0],
    [1.0, 0.0],
    [1.0, 1.0],
    [1.0, 1.0],
    [0.0, 1.0],
    [0.0, 0.0],
];

/// Appends `v` to `bytes` as little-endian f32s (a glTF buffer's layout).
fn push_f32s(bytes: &mut Vec<u8>, v: &[f32]) {
    v.iter()
        .for_each(|x| bytes.extend_from_slice(&x.to_le_bytes()))
}

/// The unit quad's buffer: POSITION (72 bytes), NORMAL +z (72) and TEXCOORD_0 = (x, 1 − y)
/// (48; glTF's v runs down the image), each for the six corners, in that order.
fn quad_buffer() -> Vec<u8> {
    let mut bytes = Vec::new();
    for c in QUAD_CORNERS {
        push_f32s(&mut bytes, &[c[0], c[1], 0.0]);
    }
    for _ in QUAD_CORNERS {
        push_f32s(&mut bytes, &[0.0, 0.0, 1.0]);
    }
    for c in QUAD_CORNERS {
        push_f32s(&mut bytes, &[c[0], 1.0 - c[1]]);
    }
    bytes
}

/// A unit quad in z = 0 (normal +z, glTF's uv layout: u along +x, v down the image = along −y)
/// with a 1×1 normal texture holding tangent-space normal `n`, optionally with TANGENTs.
fn normal_mapped_quad(dir: &Path, n: Vec3, tangents: bool) -> PathBuf {
    let texel = n
        .normalize()
        .to_array()
        .map(|c| ((c + 1.0) * 0.5 * 255.0).round() as u8);
    image::RgbImage::from_raw(1, 1, texel.to_vec())
        .unwrap()
        .save(dir.join("n.png"))
        .unwrap();
    let mut bytes = quad_buffer();
    if tangents {
        for _ in QUAD_CORNERS {
            push_f32s(&mut bytes, &[1.0, 0.0, 0.0, 1.0]);
        }
    }
    let len = bytes.len();
    let tangent_attr = if tangents { r#", "TANGENT": 3"# } else { "" };
    let tangent_acc = if tangents {
        r#", {"bufferView": 3, "componentType": 5126, "count": 6, "type": "VEC4"}"#
    } else {
        ""
    };
    let tangent_view = if tangents {
        r#", {"buffer": 0, "byteOffset": 192, "byteLength": 96}"#
    } else {
        ""
    };
    let text = format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}], "nodes": [{{"mesh": 0, "name": "quad"}}],
        "materials": [{{"normalTexture": {{"index": 0}}, "pbrMetallicRoughness": {{"metallicFactor": 0}}}}],
        "textures": [{{"source": 0}}], "images": [{{"uri": "n.png"}}],
        "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2{tangent_attr}}}, "material": 0}}]}}],
        "buffers": [{{"byteLength": {len}, "uri": "data:application/octet-stream;base64,{}"}}],
        "bufferViews": [{{"buffer": 0, "byteLength": 72}}, {{"buffer": 0, "byteOffset": 72, "byteLength": 72}},
                        {{"buffer": 0, "byteOffset": 144, "byteLength": 48}}{tangent_view}],
        "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 6, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}},
                      {{"bufferView": 1, "componentType": 5126, "count": 6, "type": "VEC3"}},
                      {{"bufferView": 2, "componentType": 5126, "count": 6, "type": "VEC2"}}{tangent_acc}]}}"#,
        base64::encode(&bytes)
    );
    let file = dir.join(format!("quad{}.gltf", if tangents { "_t" } else { "" }));
    std::fs::write(&file, text).unwrap();
    file
}

/// Normal maps: the shading normal at a hit is the texture's tangent-space normal in the frame
/// (tangent = +u, bitangent = normal × tangent · w, normal); glTF's +Y of a normal texture is up
/// the image (here world +y). With the file's TANGENTs and with MikkTSpace's (none in the file)
/// alike. Tolerance 0.01: the texel is 8-bit.
#[test]
fn normal_maps_tilt_the_shading_normal() {
    for (k, tangents) in [false, true].into_iter().enumerate() {
        for (m, expect) in [
            (Vec3::new(0.5, 0.0, 0.866), Vec3::new(0.5, 0.0, 0.866)),
            (Vec3::new(0.0, 0.5, 0.866), Vec3::new(0.0, 0.5, 0.866)),
            (Vec3::new(-0.3, -0.4, 0.866), Vec3::new(-0.3, -0.4, 0.866)),
        ] {
            let dir = workdir(&format!("nmap{k}{}", m.x));
            let file = normal_mapped_quad(&dir, m, tangents);
            let job = prism::load::load(&file, small).unwrap();
            assert!(job.warnings.is_empty(), "{:?}", job.warnings);
            let s = &job.scene;
            for p in [glam::Vec2::new(0.3, 0.2), glam::Vec2::new(0.8, 0.7)] {
                let ray = prism::ray::Ray {
                    o: Vec3::new(p.x, p.y, 1.0),
                    d: -Vec3::Z,
                    t_max: 10.0,
                    time: 0.0,
                };
                let si = s.intersect(&ray).expect("the quad is hit");
                let n = si.frame.n;
                assert!(
                    (n - expect.normalize()).length() < 0.01,
                    "tangents in file: {tangents}, map {m}: shading normal {n}"
                );
                assert!((si.ng - Vec3::Z).length() < 1e-6);
            }
        }
    }
}

/// A binary glTF (.glb: header, JSON chunk, BIN chunk holding the buffer) renders directly,
/// with the same triangle as the same file written as .gltf with a data URI; a truncated GLB
/// is refused with exit code 2.
#[test]
fn glb_container() {
    let mut bin = Vec::new();
    for v in [0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0] {
        bin.extend_from_slice(&v.to_le_bytes());
    }
    let mut json = br#"{"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0, "name": "tri"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}], "buffers": [{"byteLength": 36}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}]}"#
        .to_vec();
    while json.len() % 4 != 0 {
        json.push(b' ');
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut glb = Vec::new();
    glb.extend_from_slice(b"glTF");
    glb.extend_from_slice(&2u32.to_le_bytes());
    glb.extend_from_slice(&(total as u32).to_le_bytes());
    glb.extend_from_slice(&(json.len() as u32).to_le_bytes());
    glb.extend_from_slice(b"JSON");
    glb.extend_from_slice(&json);
    glb.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    glb.extend_from_slice(b"BIN\0");
    glb.extend_from_slice(&bin);
    let dir = workdir("glb");
    let file = dir.join("tri.glb");
    std::fs::write(&file, &glb).unwrap();
    let job = prism::load::load(&file, small).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(job.scene.primitive_count(), 1);
    assert_eq!(job.scene.shape_name, vec![Some("tri".to_string())]);
    let text = load_text("glb_as_gltf", &triangle_gltf("[{}]", ""));
    let prism::shape::Shape::Mesh(a) = &job.scene.shapes[0] else {
        panic!()
    };
    let prism::shape::Shape::Mesh(b) = &text.scene.shapes[0] else {
        panic!()
    };
    assert_eq!(a.positions, b.positions);
    assert!(render(&job).iter().all(|v| v.is_finite()));
    std::fs::write(dir.join("cut.glb"), &glb[..glb.len() - 10]).unwrap();
    let out = dir.join("cut.exr");
    let (code, err) = prism_cli(&[
        "render",
        dir.join("cut.glb").to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "-q",
    ]);
    assert!(!out.exists());
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("cut.glb") && err.contains("GLB"), "{err}");
}

/// Textures: BoxTextured's base colour image (211 × 211, REPEAT, LINEAR magnification) is
/// uplifted texel by texel; a texture's KHR_texture_transform offset and scale become its uv
/// map; metallic and roughness come from the B and G channels times their factors.
#[test]
fn textures_and_texture_transform() {
    let job = prism::load::load(&model("BoxTextured"), small).unwrap();
    let prism::bsdf::Material::Principled(p) = &job.scene.materials[0] else {
        panic!()
    };
    let prism::texture::SpectralTexture::Bitmap(g) = &p.base_color else {
        panic!("{:?}", p.base_color)
    };
    assert_eq!((g.width, g.height), (211, 211));
    assert_eq!(
        (g.wrap, g.filter),
        (
            prism::texture::Wrap::Repeat,
            prism::texture::TexFilter::Bilinear
        )
    );

    let dir = workdir("texxform");
    // 2×1 texels: (R, G = roughness, B = metalness).
    image::RgbImage::from_raw(2, 1, vec![0, 255, 128, 0, 51, 255])
        .unwrap()
        .save(dir.join("mr.png"))
        .unwrap();
    let text = triangle_gltf(
        r#"[{"pbrMetallicRoughness": {"metallicFactor": 0.5, "roughnessFactor": 0.8, "metallicRoughnessTexture": {"index": 0,
             "extensions": {"KHR_texture_transform": {"offset": [0.25, 0.5], "scale": [2, 3]}}}}}]"#,
        r#""KHR_texture_transform""#,
    )
    .replacen(
        r#""materials":"#,
        r#""textures": [{"source": 0, "sampler": 0}], "samplers": [{"magFilter": 9728, "wrapS": 33071}], "images": [{"uri": "mr.png"}], "materials":"#,
        1,
    );
    let file = dir.join("t.gltf");
    std::fs::write(&file, text).unwrap();
    let job = prism::load::load(&file, small).unwrap();
    let prism::bsdf::Material::Principled(p) = &job.scene.materials[0] else {
        panic!()
    };
    let (prism::texture::FloatTexture::Bitmap(m), prism::texture::FloatTexture::Bitmap(r)) =
        (&p.metallic, &p.roughness)
    else {
        panic!()
    };
    assert_eq!(m.map.offset, glam::Vec2::new(0.25, 0.5));
    assert_eq!(m.map.scale, glam::Vec2::new(2.0, 3.0));
    assert_eq!(
        (m.wrap, m.filter),
        (
            prism::texture::Wrap::Clamp,
            prism::texture::TexFilter::Nearest
        )
    );
    let close = |a: f32, b: f32| (a - b).abs() < 1e-6;
    assert!(
        close(m.texels[0], 0.5 * 128.0 / 255.0) && close(m.texels[1], 0.5),
        "{:?}",
        m.texels
    );
    assert!(
        close(r.texels[0], 0.8) && close(r.texels[1], 0.8 * 51.0 / 255.0),
        "{:?}",
        r.texels
    );
}

/// A unit quad in z = 0 facing +z, with TEXCOORD_0 = (x, 1 − y) (glTF's layout: v down the
/// image) and TEXCOORD_1 = (1 − x, 1 − y) (mirrored in u), material `material` (JSON) and the
/// images `images` (written into `dir` as PNG, referenced by textures 0, 1, … in order, each
/// with sampler 0: NEAREST, CLAMP_TO_EDGE).
fn textured_quad(
    dir: &Path,
    name: &str,
    material: &str,
    images: &[image::DynamicImage],
) -> PathBuf {
    let mut bytes = quad_buffer();
    for c in QUAD_CORNERS {
        push_f32s(&mut bytes, &[1.0 - c[0], 1.0 - c[1]]);
    }
    let mut textures = Vec::new();
    let mut uris = Vec::new();
    for (k, im) in images.iter().enumerate() {
        let f = format!("{name}_{k}.png");
        im.save(dir.join(&f)).unwrap();
        textures.push(format!(r#"{{"source": {k}, "sampler": 0}}"#));
        uris.push(format!(r#"{{"uri": "{f}"}}"#));
    }
    let text = format!(
        r#"{{"asset": {{"version": "2.0"}}, "extensionsUsed": ["KHR_texture_transform", "KHR_materials_specular", "KHR_materials_transmission"],
        "scene": 0, "scenes": [{{"nodes": [0]}}], "nodes": [{{"mesh": 0, "name": "quad"}}],
        "materials": [{material}], "samplers": [{{"magFilter": 9728, "wrapS": 33071, "wrapT": 33071}}],
        "textures": [{}], "images": [{}],
        "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2, "TEXCOORD_1": 3}}, "material": 0}}]}}],
        "buffers": [{{"byteLength": {}, "uri": "data:application/octet-stream;base64,{}"}}],
        "bufferViews": [{{"buffer": 0, "byteLength": 72}}, {{"buffer": 0, "byteOffset": 72, "byteLength": 72}},
                        {{"buffer": 0, "byteOffset": 144, "byteLength": 48}}, {{"buffer": 0, "byteOffset": 192, "byteLength": 48}}],
        "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 6, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}},
                      {{"bufferView": 1, "componentType": 5126, "count": 6, "type": "VEC3"}},
                      {{"bufferView": 2, "componentType": 5126, "count": 6, "type": "VEC2"}},
                      {{"bufferView": 3, "componentType": 5126, "count": 6, "type": "VEC2"}}]}}"#,
        textures.join(", "),
        uris.join(", "),
        bytes.len(),
        base64::encode(&bytes)
    );
    let file = dir.join(format!("{name}.gltf"));
    std::fs::write(&file, text).unwrap();
    file
}

/// `w` × `h` RGBA texels.
fn rgba_image(w: u32, h: u32, texels: &[[u8; 4]]) -> image::DynamicImage {
    image::DynamicImage::ImageRgba8(image::RgbaImage::from_raw(w, h, texels.concat()).unwrap())
}

/// The uv the quad's material is looked up at where a ray down −z meets world point (x, y).
fn quad_uv(job: &prism::load::Job, x: f32, y: f32) -> glam::Vec2 {
    let ray = prism::ray::Ray {
        o: Vec3::new(x, y, 1.0),
        d: -Vec3::Z,
        t_max: 10.0,
        time: 0.0,
    };
    job.scene.intersect(&ray).expect("the quad is hit").uv
}

fn principled(job: &prism::load::Job) -> &prism::bsdf::PrincipledParams {
    match &job.scene.materials[job.scene.shape_material[0] as usize] {
        prism::bsdf::Material::Principled(p) => p,
        m => panic!("{m:?}"),
    }
}

/// One wavelength.
fn wl(lambda: f32) -> prism::spectrum::Wavelengths<1> {
    prism::spectrum::Wavelengths {
        lambda: [lambda],
        pdf: [1.0],
    }
}

/// KHR_materials_specular's textures and KHR_materials_transmission's, against closed forms of
/// glTF's BRDF at normal incidence (wi = wo = n, so h = n, Schlick's weight is 0, G = 1 and
/// GGX's D(n) = 1/(π α²)). Black base colour, metallic 0, roughness 0.5 (α = 0.25):
/// f·cos = specular · f0 / (4 π α²) with f0 = ((ior − 1)/(ior + 1))² · specularColor = 0.04 ·
/// specularColor; specularTexture's A channel is the weight, specularColorTexture's sRGB RGB the
/// colour. Through the surface (wo = −n) with white base colour, f·cos = (1 − specular · f0) ·
/// transmission / (4 π α²), transmissionTexture's R channel times the factor. Two texels per
/// texture (left, right half of the quad) with different values, so a texture that is not read
/// fails. Tolerance 2e-3 relative: 8-bit texels, and the colour's uplifted spectrum, whose
/// values at 450 and 650 nm for pure red and white are bounded (not computed) here.
#[test]
fn specular_and_transmission_textures() {
    let dir = workdir("spectex");
    let a2 = 0.25f32 * 0.25;
    let lobe = 1.0 / (4.0 * std::f32::consts::PI * a2);
    let n = Vec3::Z;
    // specularTexture: A = 255 (left), 0 (right); specularFactor 0.8.
    let spec = rgba_image(2, 1, &[[0, 0, 0, 255], [0, 0, 0, 0]]);
    let file = textured_quad(
        &dir,
        "spec",
        r#"{"pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0, "roughnessFactor": 0.5},
            "extensions": {"KHR_materials_specular": {"specularFactor": 0.8, "specularTexture": {"index": 0}}}}"#,
        &[spec],
    );
    let job = prism::load::load(&file, small).unwrap();
    assert!(job.warnings.is_empty(), "{:?}", job.warnings);
    let p = principled(&job);
    for (x, weight) in [(0.25, 0.8f32), (0.75, 0.0)] {
        let f = p.at(quad_uv(&job, x, 0.5), &wl(550.0)).eval(n, n)[0];
        let want = weight * 0.04 * lobe;
        assert!(
            (f - want).abs() <= 2e-3 * lobe * 0.04,
            "x {x}: f {f}, want {want}"
        );
    }
    // specularColorTexture: white (left), pure red (right): f0 at 450 nm drops to ~0 on the
    // right and stays 0.04 on the left; at 650 nm both are ~0.04 (a red reflectance's
    // uplifted spectrum is near 1 there).
    let color = rgba_image(2, 1, &[[255, 255, 255, 255], [255, 0, 0, 255]]);
    let file = textured_quad(
        &dir,
        "speccolor",
        r#"{"pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0, "roughnessFactor": 0.5},
            "extensions": {"KHR_materials_specular": {"specularColorTexture": {"index": 0}}}}"#,
        &[color],
    );
    let job = prism::load::load(&file, small).unwrap();
    let p = principled(&job);
    let f = |x: f32, l: f32| p.at(quad_uv(&job, x, 0.5), &wl(l)).eval(n, n)[0] / (0.04 * lobe);
    assert!((f(0.25, 450.0) - 1.0).abs() < 2e-3, "{}", f(0.25, 450.0));
    assert!((f(0.25, 650.0) - 1.0).abs() < 2e-3, "{}", f(0.25, 650.0));
    assert!(f(0.75, 450.0) < 0.05, "{}", f(0.75, 450.0));
    assert!(f(0.75, 650.0) > 0.85, "{}", f(0.75, 650.0));
    // transmissionTexture: R = 255 (left), 51 (right); transmissionFactor 0.5.
    let t = rgba_image(2, 1, &[[255, 0, 0, 255], [51, 0, 0, 255]]);
    let file = textured_quad(
        &dir,
        "trans",
        r#"{"pbrMetallicRoughness": {"metallicFactor": 0, "roughnessFactor": 0.5},
            "extensions": {"KHR_materials_transmission": {"transmissionFactor": 0.5, "transmissionTexture": {"index": 0}}}}"#,
        &[t],
    );
    let job = prism::load::load(&file, small).unwrap();
    assert!(job.warnings.is_empty(), "{:?}", job.warnings);
    let p = principled(&job);
    for (x, trans) in [(0.25, 0.5f32), (0.75, 0.5 * 51.0 / 255.0)] {
        let f = p.at(quad_uv(&job, x, 0.5), &wl(550.0)).eval(n, -n)[0];
        let want = (1.0 - 0.04) * trans * lobe;
        assert!((f - want).abs() <= 2e-3 * want, "x {x}: f {f}, want {want}");
    }
}

/// KHR_texture_transform's rotation, with offset and scale, as the extension defines it:
/// uv' = T · R · S · uv with R = [[cos r, sin r], [−sin r, cos r]] (the matrices written out
/// here as the specification gives them, not the loader's formula); texel lookups on a 2 × 2
/// NEAREST texture (metalness in B: 0, 85, 170, 255) land where uv' says. Exact: nearest texels.
#[test]
fn texture_transform_rotation() {
    let dir = workdir("rotation");
    let mr = rgba_image(
        2,
        2,
        &[
            [0, 0, 0, 255],
            [0, 0, 85, 255],
            [0, 0, 170, 255],
            [0, 0, 255, 255],
        ],
    );
    let (offset, rotation, scale) = ([0.1f32, 0.9], 1.0f32, [0.7f32, 0.8]);
    let file = textured_quad(
        &dir,
        "rot",
        &format!(
            r#"{{"pbrMetallicRoughness": {{"metallicRoughnessTexture": {{"index": 0,
                "extensions": {{"KHR_texture_transform": {{"offset": {offset:?}, "rotation": {rotation}, "scale": {scale:?}}}}}}}}}}}"#
        ),
        &[mr],
    );
    let job = prism::load::load(&file, small).unwrap();
    assert!(job.warnings.is_empty(), "{:?}", job.warnings);
    let p = principled(&job);
    let t = glam::Mat3::from_cols_array_2d(&[
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [offset[0], offset[1], 1.0],
    ]);
    let (c, s) = (portable::cos(rotation), portable::sin(rotation));
    // Row-major [[c, s, 0], [−s, c, 0], [0, 0, 1]] written column by column.
    let r = glam::Mat3::from_cols_array_2d(&[[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]);
    let sc = glam::Mat3::from_diagonal(Vec3::new(scale[0], scale[1], 1.0));
    let m = t * r * sc;
    let mut seen = std::collections::BTreeSet::new();
    for x in [0.05f32, 0.3, 0.55, 0.8, 0.95] {
        for y in [0.05f32, 0.3, 0.55, 0.8, 0.95] {
            let uv = quad_uv(&job, x, y);
            let q = m * Vec3::new(uv.x, uv.y, 1.0);
            // CLAMP_TO_EDGE, 2 texels a side.
            let (i, j) = (
                (q.x * 2.0).floor().clamp(0.0, 1.0) as usize,
                (q.y * 2.0).floor().clamp(0.0, 1.0) as usize,
            );
            let want = [0.0, 85.0, 170.0, 255.0][2 * j + i] / 255.0;
            let got = p.metallic.eval(uv);
            assert!(
                (got - want).abs() < 1e-6,
                "uv {uv}: uv' {q}: got {got}, want {want}"
            );
            seen.insert(2 * j + i);
        }
    }
    assert!(seen.len() >= 3, "the probes cover several texels: {seen:?}");
}

/// TEXCOORD_1: a texture with texCoord 1 (or KHR_texture_transform's texCoord override) reads
/// the mesh's second uv set (here u mirrored: the left half of the quad shows the right texel);
/// a material whose textures read different sets is warned about. The occlusion texture is
/// ignored on purpose (prism traces the occlusion of indirect light): a black one leaves the
/// render bit-identical to the same quad without it.
#[test]
fn texcoord_1_and_occlusion() {
    let dir = workdir("texcoord1");
    // Base colour: red (left texel), blue (right texel).
    let bc = || rgba_image(2, 1, &[[255, 0, 0, 255], [0, 0, 255, 255]]);
    let red_at = |job: &prism::load::Job, x: f32| {
        let p = principled(job);
        let uv = quad_uv(job, x, 0.5);
        let v = |l| p.base_color.eval(uv, &wl(l))[0];
        v(650.0) > 0.8 && v(450.0) < 0.1
    };
    for (k, info) in [
        r#"{"index": 0, "texCoord": 1}"#,
        r#"{"index": 0, "extensions": {"KHR_texture_transform": {"texCoord": 1}}}"#,
        r#"{"index": 0}"#,
    ]
    .into_iter()
    .enumerate()
    {
        let file = textured_quad(
            &dir,
            &format!("set{k}"),
            &format!(r#"{{"pbrMetallicRoughness": {{"baseColorTexture": {info}}}}}"#),
            &[bc()],
        );
        let job = prism::load::load(&file, small).unwrap();
        assert!(job.warnings.is_empty(), "{:?}", job.warnings);
        let set1 = k < 2;
        // x = 0.25: TEXCOORD_0 u = 0.25 (red), TEXCOORD_1 u = 0.75 (blue).
        assert_eq!(red_at(&job, 0.25), !set1, "{info}");
        assert_eq!(red_at(&job, 0.75), set1, "{info}");
    }
    let file = textured_quad(
        &dir,
        "mixed",
        r#"{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicRoughnessTexture": {"index": 0, "texCoord": 1}}}"#,
        &[bc()],
    );
    let job = prism::load::load(&file, small).unwrap();
    assert!(
        job.warnings.len() == 1
            && job.warnings[0].contains("metallicRoughnessTexture (TEXCOORD_1)")
            && job.warnings[0].contains("baseColorTexture reads TEXCOORD_0"),
        "{:?}",
        job.warnings
    );
    let plain =
        r#"{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0}"#;
    let without = textured_quad(&dir, "noao", &format!("{plain}}}"), &[bc()]);
    let with = textured_quad(
        &dir,
        "ao",
        &format!(r#"{plain}, "occlusionTexture": {{"index": 1, "texCoord": 1, "strength": 1}}}}"#),
        &[bc(), rgba_image(1, 1, &[[0, 0, 0, 255]])],
    );
    let a = prism::load::load(&without, small).unwrap();
    let b = prism::load::load(&with, small).unwrap();
    assert!(b.warnings.is_empty(), "{:?}", b.warnings);
    let (ra, rb) = (render(&a), render(&b));
    assert!(ra.iter().any(|v| *v > 0.0), "the quad is lit and seen");
    assert_eq!(ra, rb, "the occlusion texture changed the render");
}

/// Mirrored uvs (the NormalTangentMirrorTest's case, built here: the Khronos model itself is not
/// in the repository): a normal texture read through the quad's TEXCOORD_1, which runs along −x
/// (u mirrored), tilts the shading normal the mirrored way, n_world = (−n_x, n_y, n_z) for a
/// tangent-space texel n, while TEXCOORD_0 (u along +x) gives (n_x, n_y, n_z); both through
/// MikkTSpace tangents (the file has none) and read back from the `normal` AOV at every pixel
/// that sees the quad. Tolerance 0.01: the texel is 8-bit.
#[test]
fn normal_maps_on_mirrored_uvs() {
    let dir = workdir("mirror");
    let m = Vec3::new(0.5, 0.3, 0.0);
    let m = Vec3::new(m.x, m.y, (1.0 - m.length_squared()).sqrt());
    let texel = m
        .to_array()
        .map(|c| ((c + 1.0) * 0.5 * 255.0).round() as u8);
    for (set, want) in [(0, m), (1, Vec3::new(-m.x, m.y, m.z))] {
        let file = textured_quad(
            &dir,
            &format!("n{set}"),
            &format!(
                r#"{{"normalTexture": {{"index": 0, "texCoord": {set}}}, "pbrMetallicRoughness": {{"metallicFactor": 0}}}}"#
            ),
            &[rgba_image(1, 1, &[[texel[0], texel[1], texel[2], 255]])],
        );
        let job = prism::load::load(&file, |c| {
            small(c);
            c.aovs = vec!["normal".into()];
        })
        .unwrap();
        assert!(job.warnings.is_empty(), "{:?}", job.warnings);
        let mut film =
            prism::integrator::render(&job.scene, &job.settings, &job.channels, &|_| {}).0;
        prism::pipeline::add_layers(&job, &mut film, None);
        let ch = |c: &str| film.channel(&format!("normal.{c}")).unwrap().to_vec();
        let (x, y, z) = (ch("X"), ch("Y"), ch("Z"));
        let mut seen = 0;
        for i in 0..x.len() {
            let n = Vec3::new(x[i], y[i], z[i]);
            if n == Vec3::ZERO {
                continue;
            }
            seen += 1;
            assert!(
                (n - want.normalize()).length() < 0.01,
                "TEXCOORD_{set}: pixel {i}: normal {n}, want {want}"
            );
        }
        assert!(
            seen > 100,
            "the quad covers the film's middle: {seen} pixels"
        );
    }
}

/// An orthographic glTF camera (xmag 1.2, ymag 0.8: a view 2.4 × 1.6 wide; znear 0.5, zfar 50)
/// renders the same pixels and AOVs as the same camera written in
/// RON (`Orthographic(width: 2.4)` on a 3:2 film, the node matrix composed with
/// diag(−1, 1, −1)); the direct load takes the film's aspect xmag / ymag (864 × 576). And
/// against glTF's definition: the ray through the film's top-left corner starts at camera-frame
/// (−xmag, +ymag) and runs along the camera's −z.
#[test]
fn gltf_orthographic_camera_matches_ron_camera() {
    let dir = workdir("ortho");
    let mut json: Value =
        serde_json::from_str(&std::fs::read_to_string(model("Cameras")).unwrap()).unwrap();
    json["cameras"] = serde_json::json!([{"type": "orthographic",
        "orthographic": {"xmag": 1.2, "ymag": 0.8, "znear": 0.5, "zfar": 50}}]);
    json["nodes"] = serde_json::json!([json["nodes"][0].clone(),
        {"translation": [0.5, 0.5, 3.0], "camera": 0}]);
    json["scenes"] = serde_json::json!([{"nodes": [0, 1]}]);
    let file = dir.join("Ortho.gltf");
    std::fs::write(&file, serde_json::to_string(&json).unwrap()).unwrap();
    let (cfg, _) = gltf::scene_config(&file).unwrap();
    assert_eq!((cfg.film.width, cfg.film.height), (864, 576));
    let film = |c: &mut prism::config::SceneConfig| {
        small(c);
        c.film.width = 36;
        c.film.height = 24;
        c.aovs = vec!["depth".into(), "normal".into(), "instance".into()];
    };
    let direct = prism::load::load(&file, film).unwrap();
    let ron = "(camera: (model: Orthographic(width: 2.4), near_clip: 0.5, far_clip: 50, \
           to_world: [Scale((-1, 1, -1)), Translate((0.5, 0.5, 3.0))]), \
         film: (width: 36, height: 24), sampler: (spp: 2), spectral: (wavelengths: 4), outputs: (bands: 0), \
         aovs: [\"depth\", \"normal\", \"instance\"], \
         shapes: [(shape: Gltf(path: \"Ortho.gltf\"))], emitters: [Constant(radiance: Named(\"D65\"))])";
    let scene = dir.join("scene.ron");
    std::fs::write(&scene, ron).unwrap();
    let via_ron = prism::load::load(&scene, |_| {}).unwrap();
    assert_eq!(direct.scene.camera.model(), "orthographic");
    assert_eq!(direct.scene.camera, via_ron.scene.camera);
    let full = |job: &prism::load::Job| {
        let mut f = prism::integrator::render(&job.scene, &job.settings, &job.channels, &|_| {}).0;
        prism::pipeline::add_layers(job, &mut f, None);
        f
    };
    let (a, b) = (full(&direct), full(&via_ron));
    for ch in ["R", "G", "B", "depth.Z", "normal.X", "normal.Y", "normal.Z"] {
        let (x, y) = (a.channel(ch).unwrap(), b.channel(ch).unwrap());
        assert!(
            x.iter().zip(y).all(|(p, q)| p.to_bits() == q.to_bits()),
            "{ch} differs"
        );
    }
    let ids = |f: &prism::film::Film| {
        f.uint_channels
            .iter()
            .find(|c| c.name == "instance.ID")
            .unwrap()
            .data
            .clone()
    };
    assert_eq!(ids(&a), ids(&b));
    assert!(ids(&a).iter().any(|&i| i != 0), "the box is in view");
    // glTF: the view spans [−xmag, xmag] × [−ymag, ymag] in the camera's x (right), y (up).
    let r = direct.scene.camera.center_ray(glam::Vec2::ZERO);
    let local = r.o - Vec3::new(0.5, 0.5, 3.0);
    assert!(
        (local.x + 1.2).abs() < 1e-4 && (local.y - 0.8).abs() < 1e-4,
        "corner ray origin {local} (camera frame)"
    );
    let d = r.d.normalize();
    assert!((d - Vec3::NEG_Z).length() < 1e-5, "{d}");
}

/// Issue 27 item 4: a sampler's wrapT is honoured apart from wrapS (both used wrapS), and
/// what prism does not read warns at load: COLOR_0, MIRRORED_REPEAT, a dispersive glass's
/// roughness texture. The texture: 2×2 nearest texels whose G (roughness) is 1.0, 0.6 (top
/// row) and 0.4, 0.2 (bottom); wrapS REPEAT and wrapT CLAMP_TO_EDGE. At uv (1.25, 0.25)
/// u repeats onto the top-left texel (1.0; clamped it would be 0.6); at (0.25, 1.25) v clamps
/// onto the bottom-left texel (0.4; repeated it would be 1.0). Exact: 8-bit texels / 255.
#[test]
fn wrap_t_and_unread_features() {
    let dir = workdir("wrapt");
    let img = image::DynamicImage::ImageRgb8(
        image::RgbImage::from_raw(2, 2, vec![0, 255, 0, 0, 153, 0, 0, 102, 0, 0, 51, 0]).unwrap(),
    );
    let mat = r#"{"pbrMetallicRoughness": {"metallicRoughnessTexture": {"index": 0}}}"#;
    let file = textured_quad(&dir, "wrapt", mat, std::slice::from_ref(&img));
    let text = std::fs::read_to_string(&file).unwrap();
    let clamp_both = r#""wrapS": 33071, "wrapT": 33071"#;
    assert!(text.contains(clamp_both));
    std::fs::write(
        &file,
        text.replace(clamp_both, r#""wrapS": 10497, "wrapT": 33071"#),
    )
    .unwrap();
    let job = prism::load::load(&file, small).unwrap();
    let prism::texture::FloatTexture::Bitmap(g) = &principled(&job).roughness else {
        panic!()
    };
    assert_eq!(
        (g.wrap, g.wrap_v),
        (prism::texture::Wrap::Repeat, prism::texture::Wrap::Clamp)
    );
    let r = &principled(&job).roughness;
    let at = |u: f32, v: f32| r.eval(glam::Vec2::new(u, v));
    assert_eq!(at(1.25, 0.25), 1.0);
    assert_eq!(at(0.25, 1.25), 102.0 / 255.0);
    assert!(
        job.warnings.iter().all(|w| !w.contains("COLOR_0")),
        "{:?}",
        job.warnings
    );

    // COLOR_0 (the normals' accessor read as colours: a valid VEC3 float) is read now, so
    // not warned about; COLOR_1 is not read, and a mirrored sampler is read as REPEAT: each
    // named in a warning.
    let text = std::fs::read_to_string(&file)
        .unwrap()
        .replace(
            r#""TEXCOORD_1": 3}"#,
            r#""TEXCOORD_1": 3, "COLOR_0": 1, "COLOR_1": 1}"#,
        )
        .replace(r#""wrapS": 10497"#, r#""wrapS": 33648"#);
    std::fs::write(&file, text).unwrap();
    let job = prism::load::load(&file, small).unwrap();
    let has = |needle: &str| job.warnings.iter().any(|w| w.contains(needle));
    assert!(
        !has("COLOR_0") && has("COLOR_1") && has("wrapt.gltf"),
        "{:?}",
        job.warnings
    );
    assert!(has("MIRRORED_REPEAT"), "{:?}", job.warnings);

    // A dispersive glass with a roughness texture honours it: α = (G × roughnessFactor)² per
    // texel (G = 1, 0.6, 0.4, 0.2 here; factor 0.3).
    let glass = r#"{"pbrMetallicRoughness": {"roughnessFactor": 0.3, "metallicRoughnessTexture": {"index": 0}},
        "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1}, "KHR_materials_dispersion": {"dispersion": 0.5}}}"#;
    let file = textured_quad(&dir, "glass", glass, &[img]);
    let text = std::fs::read_to_string(&file).unwrap().replace(
        r#""KHR_materials_transmission"]"#,
        r#""KHR_materials_transmission", "KHR_materials_dispersion"]"#,
    );
    std::fs::write(&file, text).unwrap();
    let job = prism::load::load(&file, small).unwrap();
    let prism::bsdf::Material::RoughDielectric(prism::bsdf::RoughDielectricParams {
        alpha_u: prism::texture::FloatTexture::Bitmap(g),
        alpha_v,
        ..
    }) = &job.scene.materials[job.scene.shape_material[0] as usize]
    else {
        panic!("{:?}", job.scene.materials)
    };
    assert_eq!(alpha_v, &prism::texture::FloatTexture::Bitmap(g.clone()));
    for (t, gv) in g.texels.iter().zip([255.0f32, 153.0, 102.0, 51.0]) {
        let expect = (gv / 255.0 * 0.3).powi(2);
        assert!((t - expect).abs() < 1e-6, "{:?}", g.texels);
    }
    assert!(
        job.warnings
            .iter()
            .all(|w| !w.contains("metallicRoughnessTexture")),
        "{:?}",
        job.warnings
    );
}
