//! Hostile glTF files (issue 27 item 7), written here inline: vertices and nodes past the
//! 1e18 extent, accessor counts and sparse indices past their data, buffer and image URIs that
//! leave the model's folder (and the `allow_outside` opt-out), and the spec-valid orthographic
//! camera with znear 0. Each refusal exits 2 naming the glTF file, the JSON field and the fix,
//! and writes nothing; each control next to it renders (exit 0), so a check that refuses too
//! much fails too.

mod scratch;
use serde_json::{json, Value};
use std::path::Path;
use std::process::Command;

fn workdir(name: &str) -> scratch::Scratch {
    scratch::scratch("gltfh", name)
}

fn data_uri(bytes: &[u8]) -> String {
    format!(
        "data:application/octet-stream;base64,{}",
        base64::encode(bytes)
    )
}

fn f32s(v: &[f32]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

/// One triangle (0,0,0), (1,0,0), (0,1,0) under node 0, its positions in buffer 0.
fn triangle() -> Value {
    let pos = f32s(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
    json!({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "buffers": [{"byteLength": 36, "uri": data_uri(&pos)}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
            "min": [0, 0, 0], "max": [1, 1, 0]}]})
}

/// Renders `doc` (written to `dir/name.gltf`) included by a RON scene (`extra` added to the
/// `Gltf(...)` shape); returns the exit code and stderr, and whether the EXR was written.
fn render(dir: &Path, name: &str, doc: &Value, extra: &str) -> (i32, String, bool) {
    let file = dir.join(format!("{name}.gltf"));
    std::fs::write(&file, doc.to_string()).unwrap();
    let ron = format!(
        "(camera: (fov: 40, to_world: [LookAt(origin: (0, 0, 5), target: (0, 0, 0), up: (0, 1, 0))]), \
         film: (width: 8, height: 6), sampler: (spp: 1), \
         shapes: [(shape: Gltf(path: \"{}\"{extra}))], emitters: [Constant(radiance: Named(\"D65\"))])",
        file.display()
    );
    let scene = dir.join(format!("{name}.ron"));
    std::fs::write(&scene, ron).unwrap();
    let out = dir.join(format!("{name}.exr"));
    let o = Command::new(env!("CARGO_BIN_EXE_prism"))
        .args([
            "render",
            scene.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "-q",
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    (o.status.code().unwrap_or(-1), err, out.exists())
}

/// Exit 2, no output, the file and every needle named, no panic.
fn refused(dir: &Path, name: &str, doc: &Value, extra: &str, needles: &[&str]) {
    let (code, err, wrote) = render(dir, name, doc, extra);
    assert_eq!(code, 2, "{name}: exit {code}: {err}");
    assert!(!wrote && !err.contains("panicked"), "{name}: {err}");
    assert!(
        err.contains(&format!("{name}.gltf")),
        "{name}: file not named: {err}"
    );
    for n in needles {
        assert!(err.contains(n), "{name}: stderr lacks `{n}`: {err}");
    }
}

fn renders(dir: &Path, name: &str, doc: &Value, extra: &str) {
    let (code, err, wrote) = render(dir, name, doc, extra);
    assert!(code == 0 && wrote, "{name}: exit {code}: {err}");
}

/// Vertices and node translations past `extent::MAX_COORD` (1e18), as OBJ meshes and RON
/// shapes are: a node at 1e30, a vertex at 1e30, a node scaled by 1e30, a light node at 1e30
/// (no mesh), a vertex at 1e30 under a node scaled by 1e-15 (world position 1e15: fine).
/// The boundary: 1e17 renders, 1e19 is refused.
#[test]
fn far_vertices_and_nodes_are_refused() {
    let dir = workdir("extent");
    let hint = "scale it down";
    let mut d = triangle();
    d["nodes"][0]["translation"] = json!([1e30, 0, 0]);
    refused(&dir, "node_1e30", &d, "", &["nodes[0]", "1e30", hint]);
    d["nodes"][0]["translation"] = json!([0, 1e19, 0]);
    refused(&dir, "node_1e19", &d, "", &["nodes[0]", "1e19", hint]);
    d["nodes"][0]["translation"] = json!([0, 0, -1e17]);
    renders(&dir, "node_1e17", &d, "");
    let mut d = triangle();
    d["nodes"][0]["scale"] = json!([1e30, 1, 1]);
    refused(&dir, "scale_1e30", &d, "", &["nodes[0]", "1e30"]);
    let mut d = triangle();
    d["buffers"][0]["uri"] = json!(data_uri(&f32s(&[
        0.0, 0.0, 0.0, 1e30, 0.0, 0.0, 0.0, 1.0, 0.0
    ])));
    d["accessors"][0]["max"] = json!([1e30, 1, 0]);
    let field = "meshes[0].primitives[0].attributes.POSITION";
    refused(
        &dir,
        "vertex_1e30",
        &d,
        "",
        &[field, "nodes[0]", "1e30", hint],
    );
    // Under a node scaled by 1e-15 the world vertex is at 1e15: within the extent.
    d["nodes"][0]["scale"] = json!([1e-15, 1, 1]);
    renders(&dir, "vertex_1e30_scaled_down", &d, "");
    // Instanced (the mesh under two nodes): checked on the instance's world vertices.
    let mut d = triangle();
    d["nodes"] =
        json!([{"children": [1, 2]}, {"mesh": 0}, {"mesh": 0, "translation": [1e30, 0, 0]}]);
    refused(&dir, "instance_1e30", &d, "", &["nodes[2]", "1e30"]);
    // A punctual light placed at 1e30.
    let mut d = triangle();
    d["extensionsUsed"] = json!(["KHR_lights_punctual"]);
    d["extensions"] =
        json!({"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 1}]}});
    d["nodes"] = json!([{"mesh": 0}, {"translation": [0, 1e30, 0],
        "extensions": {"KHR_lights_punctual": {"light": 0}}}]);
    d["scenes"] = json!([{"nodes": [0, 1]}]);
    refused(&dir, "light_1e30", &d, "", &["nodes[1]", "1e30"]);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Accessor counts past their buffer view (2^62, 2^64 − 1, one element too many, a view past
/// its buffer) and sparse parts past their data or their accessor are refused before any
/// read; a sparse index at or past the accessor's count, or not increasing, is refused once
/// the buffer is read. The control: a valid sparse accessor (index 2 replaced) renders.
#[test]
fn accessor_counts_and_sparse_indices_are_refused() {
    let dir = workdir("accessors");
    for (name, count, want) in [
        ("count_2e62", json!(1u64 << 62), "4611686018427387904"),
        ("count_u64_max", json!(u64::MAX), "accessors[0].count"),
        (
            "count_4",
            json!(4),
            "need 48 bytes of bufferViews[0], which has 36",
        ),
        ("count_0", json!(0), "count ≥ 1"),
    ] {
        let mut d = triangle();
        d["accessors"][0]["count"] = count;
        refused(
            &dir,
            name,
            &d,
            "",
            &["accessors[0].count", want, "validator"],
        );
    }
    let mut d = triangle();
    d["bufferViews"][0]["byteLength"] = json!(1u64 << 62);
    refused(
        &dir,
        "view_2e62",
        &d,
        "",
        &["bufferViews[0]", "past its buffer's 36"],
    );
    // Indices: an index accessor of count 2^62 (the example).
    let mut d = triangle();
    d["meshes"][0]["primitives"][0]["indices"] = json!(1);
    let ix = json!({"bufferView": 0, "componentType": 5125, "count": 1u64 << 62, "type": "SCALAR"});
    d["accessors"].as_array_mut().unwrap().push(ix);
    refused(&dir, "index_count_2e62", &d, "", &["accessors[1].count"]);

    // Sparse: positions, then u16 indices (at 36) and one VEC3 value per index (at 40).
    let sparse = |indices: &[u16]| {
        let mut b = f32s(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
        let n = indices.len();
        b.extend(indices.iter().flat_map(|i| i.to_le_bytes()));
        b.resize(36 + 4 * n.div_ceil(2), 0);
        let values_at = b.len();
        for _ in 0..n {
            b.extend(f32s(&[0.5, 0.5, 0.0]));
        }
        let mut d = triangle();
        d["buffers"][0] = json!({"byteLength": b.len(), "uri": data_uri(&b)});
        d["bufferViews"] = json!([{"buffer": 0, "byteLength": 36},
            {"buffer": 0, "byteOffset": 36, "byteLength": 2 * n},
            {"buffer": 0, "byteOffset": values_at, "byteLength": 12 * n}]);
        d["accessors"][0]["sparse"] = json!({"count": n,
            "indices": {"bufferView": 1, "componentType": 5123}, "values": {"bufferView": 2}});
        d["accessors"][0]["max"] = json!([1, 1, 0]);
        d
    };
    renders(&dir, "sparse_ok", &sparse(&[2]), "");
    let idx = "accessors[0].sparse.indices";
    refused(
        &dir,
        "sparse_7",
        &sparse(&[7]),
        "",
        &[idx, "is 7, past the accessor's 3"],
    );
    refused(&dir, "sparse_3", &sparse(&[3]), "", &[idx, "is 3"]);
    refused(
        &dir,
        "sparse_order",
        &sparse(&[1, 1]),
        "",
        &[idx, "not above"],
    );
    let mut d = sparse(&[2]);
    d["accessors"][0]["sparse"]["count"] = json!(4);
    refused(
        &dir,
        "sparse_count",
        &d,
        "",
        &["accessors[0].sparse.count", "[1, 3]"],
    );
    let mut d = sparse(&[1, 2]);
    d["bufferViews"][2]["byteLength"] = json!(12);
    refused(
        &dir,
        "sparse_values",
        &d,
        "",
        &["accessors[0].sparse.values", "need 24 bytes"],
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Buffer and image URIs are confined to the model's folder: `../`, its percent-encoding
/// `%2e%2e/`, an absolute path and a `file:` URI are refused (naming the URI and the
/// `allow_outside` fix) although the file they name exists and is valid; a symlink beside the
/// model that points outside is refused too. The same files render with `allow_outside: true`,
/// and a file in a subfolder renders without it.
#[test]
fn uris_outside_the_folder_are_confined() {
    let root = workdir("uris");
    let dir = root.join("model");
    std::fs::create_dir_all(dir.join("sub")).unwrap();
    let pos = f32s(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
    std::fs::write(root.join("x.bin"), &pos).unwrap();
    std::fs::write(dir.join("sub/x.bin"), &pos).unwrap();
    std::os::unix::fs::symlink(root.join("x.bin"), dir.join("link.bin")).unwrap();
    let outside = root.join("x.bin").canonicalize().unwrap();
    let abs = outside.display().to_string();
    let file_uri = format!("file://{abs}");
    for (name, uri) in [
        ("parent", "../x.bin"),
        ("percent", "%2e%2e/x.bin"),
        ("absolute", abs.as_str()),
        ("file_uri", file_uri.as_str()),
        ("symlink", "link.bin"),
    ] {
        let mut d = triangle();
        d["buffers"][0]["uri"] = json!(uri);
        refused(
            &dir,
            name,
            &d,
            "",
            &[
                "buffers[0].uri",
                &format!("\"{uri}\""),
                "outside the model's folder",
                "allow_outside: true",
            ],
        );
        renders(
            &dir,
            &format!("{name}_allowed"),
            &d,
            ", allow_outside: true",
        );
    }
    let mut d = triangle();
    d["buffers"][0]["uri"] = json!("sub/x.bin");
    renders(&dir, "subfolder", &d, "");
    // Images: the same confinement (the image need not be valid: the URI is refused first).
    let mut d = triangle();
    d["images"] = json!([{"uri": "../../etc/passwd"}, {"uri": "../../../../../../../etc/passwd"}]);
    refused(
        &dir,
        "image",
        &d,
        "",
        &["images[0].uri", "outside the model's folder"],
    );
    let _ = std::fs::remove_dir_all(&root);
}

/// A spec-valid orthographic camera with znear 0 (glTF 2.0 §5.13: orthographic znear ≥ 0)
/// renders, directly and as the same camera in RON; a perspective camera with near_clip 0 is
/// still refused (its rays start on the near plane, which must lie in front of the pinhole).
#[test]
fn orthographic_znear_zero_renders() {
    let dir = workdir("ortho");
    let mut d = triangle();
    d["cameras"] = json!([{"type": "orthographic",
        "orthographic": {"xmag": 1, "ymag": 0.75, "znear": 0, "zfar": 100}}]);
    d["nodes"] = json!([{"mesh": 0}, {"camera": 0, "translation": [0.5, 0.5, 3]}]);
    d["scenes"] = json!([{"nodes": [0, 1]}]);
    let file = dir.join("ortho.gltf");
    std::fs::write(&file, d.to_string()).unwrap();
    let job = prism::load::load(&file, |c| {
        c.film.width = 8;
        c.film.height = 6;
    })
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(job.scene.camera.model(), "orthographic");
    assert_eq!(job.scene.camera.near_clip(), 0.0);
    // The ray through the centre starts on the camera's plane (z = 3).
    let r = job.scene.camera.center_ray(glam::Vec2::new(4.0, 3.0));
    assert!((r.o.z - 3.0).abs() < 1e-5, "{r:?}");
    let out = dir.join("ortho.exr");
    let o = Command::new(env!("CARGO_BIN_EXE_prism"))
        .args([
            "render",
            file.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "-q",
        ])
        .args(["--spp", "1"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let ron = |model: &str| {
        format!(
            "(camera: (model: {model}, near_clip: 0, to_world: [Translate((0, 0, 3))]), \
             film: (width: 8, height: 6), shapes: [(shape: Rectangle)])"
        )
    };
    let build = |model: &str| {
        let file = Path::new("s.ron");
        prism::config::parse_str(&ron(model), file).and_then(|c| prism::load::build(c, file))
    };
    build("Orthographic(width: 2)").unwrap_or_else(|e| panic!("{e}"));
    let e = build("Pinhole").err().unwrap().to_string();
    assert!(
        e.contains("camera.near_clip") && e.contains("must be > 0"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
