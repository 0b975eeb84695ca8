//! glTF vertex colours (`COLOR_0`) against the files' own numbers: the colours are decoded here
//! from the file's buffer (serde_json + base64, not prism's reader), the rays are intersected
//! here with the file's triangles, and prism's `albedo` AOV at each pixel-centre hit is
//! compared with the interpolated colour × base colour factor × (1 − metallic).

mod scratch;
use glam::{Vec2, Vec3};
use serde_json::Value;
use std::path::Path;

fn workdir(name: &str) -> scratch::Scratch {
    scratch::scratch("gltfcol", name)
}

/// The bytes of buffer 0 (a base64 data URI).
fn buffer(json: &Value) -> Vec<u8> {
    let uri = json["buffers"][0]["uri"].as_str().unwrap();
    base64::decode(uri.split_once(',').unwrap().1).unwrap()
}

/// Accessor `k` as rows of f32 (FLOAT, or normalised UNSIGNED_BYTE/SHORT), tightly packed.
fn accessor(json: &Value, bytes: &[u8], k: usize) -> Vec<Vec<f32>> {
    let a = &json["accessors"][k];
    let v = &json["bufferViews"][a["bufferView"].as_u64().unwrap() as usize];
    let off =
        (v["byteOffset"].as_u64().unwrap_or(0) + a["byteOffset"].as_u64().unwrap_or(0)) as usize;
    let n = match a["type"].as_str().unwrap() {
        "SCALAR" => 1,
        "VEC2" => 2,
        "VEC3" => 3,
        "VEC4" => 4,
        t => panic!("{t}"),
    };
    let (size, read): (usize, fn(&[u8]) -> f32) = match a["componentType"].as_u64().unwrap() {
        5126 => (4, |b| f32::from_le_bytes(b.try_into().unwrap())),
        5121 => (1, |b| b[0] as f32 / 255.0),
        5123 => (2, |b| {
            u16::from_le_bytes(b.try_into().unwrap()) as f32 / 65535.0
        }),
        c => panic!("{c}"),
    };
    (0..a["count"].as_u64().unwrap() as usize)
        .map(|i| {
            (0..n)
                .map(|c| read(&bytes[off + (i * n + c) * size..][..size]))
                .collect()
        })
        .collect()
}

fn indices(json: &Value, bytes: &[u8], k: usize) -> Vec<usize> {
    let a = &json["accessors"][k];
    let v = &json["bufferViews"][a["bufferView"].as_u64().unwrap() as usize];
    let off = v["byteOffset"].as_u64().unwrap_or(0) as usize;
    (0..a["count"].as_u64().unwrap() as usize)
        .map(|i| u16::from_le_bytes([bytes[off + 2 * i], bytes[off + 2 * i + 1]]) as usize)
        .collect()
}

/// Möller–Trumbore: (t, b1, b2) of the ray's hit on triangle (a, b, c), if any.
fn hit(o: Vec3, d: Vec3, [a, b, c]: [Vec3; 3]) -> Option<(f32, f32, f32)> {
    let (e1, e2) = (b - a, c - a);
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-12 {
        return None;
    }
    let s = o - a;
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let v = d.dot(q) / det;
    let t = e2.dot(q) / det;
    (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > 0.0).then_some((t, u, v))
}

/// The Khronos BoxVertexColors model (CC0; tests/data/gltf/README.md) renders in its vertex
/// colours. Its material: baseColorFactor 0.8 grey, metallic 0.1, alpha OPAQUE (the VEC4
/// colours' alpha, 0 at some corners, is then not used). The albedo AOV of a principled
/// material is base colour × (1 − metallic), in linear sRGB under D65.
///
/// Tolerance 3e-3 per channel: the albedo of the uplifted spectra returns the uplifted RGB
/// only up to the Jakob–Hanika fit (worst here measured 8.1e-4), and the
/// corner spectra are blended linearly, which the linear XYZ → sRGB map preserves. Before
/// COLOR_0 was read every pixel was 0.72 grey, off by up to 0.72 in a channel.
#[test]
fn box_vertex_colors_render_in_the_files_colours() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/gltf/BoxVertexColors.gltf");
    let json: Value = serde_json::from_str(&std::fs::read_to_string(&src).unwrap()).unwrap();
    let bytes = buffer(&json);
    let attrs = &json["meshes"][0]["primitives"][0]["attributes"];
    let at = |name: &str| accessor(&json, &bytes, attrs[name].as_u64().unwrap() as usize);
    let (pos, col) = (at("POSITION"), at("COLOR_0"));
    let idx = indices(&json, &bytes, 0);
    let factor = json["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"][0]
        .as_f64()
        .unwrap() as f32;
    let metallic = json["materials"][0]["pbrMetallicRoughness"]["metallicFactor"]
        .as_f64()
        .unwrap() as f32;
    let p = |i: usize| Vec3::new(pos[i][0], pos[i][1], pos[i][2]);

    let dir = workdir("box");
    std::fs::copy(&src, dir.join("box.gltf")).unwrap();
    let ron = r#"(film: (width: 40, height: 30), sampler: (spp: 4), spectral: (wavelengths: 4),
        outputs: (bands: 0), aovs: ["albedo"],
        camera: (to_world: [LookAt(origin: (1.3, 1.1, 1.7), target: (0, 0, 0), up: (0, 1, 0))], fov: 40),
        shapes: [(shape: Gltf(path: "box.gltf"))],
        emitters: [Constant(radiance: Named("D65"))])"#;
    std::fs::write(dir.join("s.ron"), ron).unwrap();
    let job = prism::load::load(&dir.join("s.ron"), |_| {}).unwrap();
    assert!(
        job.warnings.iter().all(|w| !w.contains("COLOR_0")),
        "{:?}",
        job.warnings
    );
    let r = prism::pipeline::render(&job, 1.0, &|_| {});
    let film = &r.film;
    let ch = |c: &str| film.channel(c).unwrap_or_else(|| panic!("{c}")).to_vec();
    let albedo = [ch("albedo.R"), ch("albedo.G"), ch("albedo.B")];
    let beauty = [ch("R"), ch("G"), ch("B")];
    let (w, h) = (40usize, 30usize);
    let (mut checked, mut worst, mut blue, mut blue_rb) = (0, 0.0f32, 0, [0.0f32; 2]);
    for y in 0..h {
        for x in 0..w {
            let ray = job
                .scene
                .camera
                .center_ray(Vec2::new(x as f32 + 0.5, y as f32 + 0.5));
            let best = idx
                .chunks(3)
                .filter_map(|t| {
                    let (tt, b1, b2) = hit(ray.o, ray.d, [p(t[0]), p(t[1]), p(t[2])])?;
                    Some((tt, b1, b2, t))
                })
                .min_by(|a, b| a.0.total_cmp(&b.0));
            let Some((_, b1, b2, t)) = best else { continue };
            let b0 = 1.0 - b1 - b2;
            // Away from edges, where a pixel-centre hit could fall on a neighbour.
            if b0.min(b1).min(b2) < 0.02 {
                continue;
            }
            let i = y * w + x;
            let expect: [f32; 3] = std::array::from_fn(|c| {
                (b0 * col[t[0]][c] + b1 * col[t[1]][c] + b2 * col[t[2]][c])
                    * factor
                    * (1.0 - metallic)
            });
            for c in 0..3 {
                worst = worst.max((albedo[c][i] - expect[c]).abs());
            }
            // Pixels the file makes clearly blue are blue in the render too, on the whole (less
            // so than the albedo: the white environment's specular reflection adds white, and
            // the pixel filter reaches over edges).
            if expect[2] > 2.0 * expect[0] && expect[2] > 0.3 {
                blue += 1;
                blue_rb[0] += beauty[0][i];
                blue_rb[1] += beauty[2][i];
            }
            checked += 1;
        }
    }
    assert!(
        checked > 200 && blue > 10,
        "{checked} pixels checked, {blue} blue"
    );
    eprintln!(
        "{checked} pixels, worst albedo error {worst}; blue pixels' B/R {}",
        blue_rb[1] / blue_rb[0]
    );
    assert!(worst < 3e-3, "albedo off the file's colours by {worst}");
}

/// One triangle (0,0,0), (1,0,0), (0,1,0) with COLOR_0 given as `color` (componentType,
/// type, bytes), a material `material`.
fn triangle(color: (u32, &str, Vec<u8>), material: &str) -> String {
    let mut bytes = Vec::new();
    for v in [0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0] {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    let (ct, ty, cb) = color;
    let n = cb.len();
    bytes.extend_from_slice(&cb);
    while bytes.len() % 4 != 0 {
        bytes.push(0);
    }
    let b64 = base64::encode(&bytes);
    let norm = if ct == 5126 {
        ""
    } else {
        r#", "normalized": true"#
    };
    format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
        "nodes": [{{"mesh": 0, "name": "tri"}}], "materials": [{material}],
        "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "COLOR_0": 1}}, "material": 0}}]}}],
        "buffers": [{{"byteLength": {}, "uri": "data:application/octet-stream;base64,{b64}"}}],
        "bufferViews": [{{"buffer": 0, "byteLength": 36}}, {{"buffer": 0, "byteOffset": 36, "byteLength": {n}}}],
        "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}},
                      {{"bufferView": 1, "componentType": {ct}, "count": 3, "type": "{ty}"{norm}}}]}}"#,
        bytes.len()
    )
}

fn load(name: &str, text: &str) -> Result<prism::load::Job, prism::error::Error> {
    let dir = workdir(name);
    let file = dir.join(format!("{name}.gltf"));
    std::fs::write(&file, text).unwrap();
    prism::load::load(&file, |c| {
        c.film.width = 8;
        c.film.height = 8;
    })
}

fn wl(lambda: f32) -> prism::spectrum::Wavelengths<1> {
    prism::spectrum::Wavelengths {
        lambda: [lambda],
        pdf: [1.0],
    }
}

fn base_color(job: &prism::load::Job) -> &prism::texture::SpectralTexture {
    let mut m = &job.scene.materials[job.scene.shape_material[0] as usize];
    if let prism::bsdf::Material::Mask { inner, .. } = m {
        m = inner;
    }
    match m {
        prism::bsdf::Material::Principled(p) => &p.base_color,
        m => panic!("{m:?}"),
    }
}

fn at(b1: f32, b2: f32) -> prism::texture::TexPoint {
    prism::texture::TexPoint {
        uv: Vec2::ZERO,
        prim: 0,
        bary: Vec2::new(b1, b2),
    }
}

const PLAIN: &str = r#"{"pbrMetallicRoughness": {"baseColorFactor": [0.5, 1, 1, 1]}}"#;

/// COLOR_0 as FLOAT, normalised UNSIGNED_BYTE and UNSIGNED_SHORT, VEC3 and VEC4: the integer
/// forms read as v / 255 and v / 65535 (glTF 2.0 §3.11), so they give the same spectra as the
/// float file with those values (to 1e-6: the same f32 inputs, one rounding apart). At a corner
/// the base colour is the uplift of factor × that corner's colour; halfway along an edge the
/// mean of the two corners' spectra (the blend is linear in the spectra).
#[test]
fn color_0_formats_read_as_the_specification_says() {
    let floats = |v: [f32; 9]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
    let f = load(
        "f32",
        &triangle(
            (
                5126,
                "VEC3",
                floats([1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.2, 0.4, 1.0]),
            ),
            PLAIN,
        ),
    )
    .unwrap();
    let u8s = load(
        "u8",
        &triangle(
            (5121, "VEC3", vec![255, 0, 0, 0, 255, 0, 51, 102, 255]),
            PLAIN,
        ),
    )
    .unwrap();
    let shorts = [65535u16, 0, 0, 9, 0, 65535, 0, 9, 13107, 26214, 65535, 9];
    let u16s = load(
        "u16",
        &triangle(
            (
                5123,
                "VEC4",
                shorts.iter().flat_map(|v| v.to_le_bytes()).collect(),
            ),
            PLAIN,
        ),
    )
    .unwrap();
    for job in [&f, &u8s, &u16s] {
        assert!(
            matches!(base_color(job), prism::texture::SpectralTexture::Vertex(_)),
            "{:?}",
            base_color(job)
        );
    }
    let red = prism::spectrum::rgb2spec::fetch([0.5, 0.0, 0.0]);
    let green = prism::spectrum::rgb2spec::fetch([0.0, 1.0, 0.0]);
    for l in [400.0, 450.0, 500.0, 550.0, 600.0, 650.0, 700.0] {
        let e =
            |job: &prism::load::Job, b1: f32, b2: f32| base_color(job).eval(at(b1, b2), &wl(l))[0];
        for (b1, b2) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (0.3, 0.3), (0.5, 0.0)] {
            assert!(
                (e(&f, b1, b2) - e(&u8s, b1, b2)).abs() < 1e-6,
                "u8 at {l} nm, ({b1}, {b2})"
            );
            assert!(
                (e(&f, b1, b2) - e(&u16s, b1, b2)).abs() < 1e-6,
                "u16 at {l} nm, ({b1}, {b2})"
            );
        }
        // Corner 0 is (1, 0, 0) × factor (0.5, 1, 1); corner 1 (0, 1, 0).
        assert!((e(&f, 0.0, 0.0) - red.eval(l)).abs() < 1e-6, "{l} nm");
        assert!((e(&f, 1.0, 0.0) - green.eval(l)).abs() < 1e-6, "{l} nm");
        let mid = 0.5 * (red.eval(l) + green.eval(l));
        assert!((e(&f, 0.5, 0.0) - mid).abs() < 1e-6, "{l} nm");
    }
}

/// COLOR_0's alpha multiplies the alpha: BLEND takes the product; MASK cuts the product (not
/// the texel alpha alone) at alphaCutoff. Alphas (1, 0.5, 0) at the corners, factor alpha 0.8:
/// at barycentrics (b1, b2) the opacity is 0.8 · (b0 + 0.5 b1). Exact in f32 up to 1e-6.
#[test]
fn color_0_alpha_multiplies_the_alpha() {
    let rgba = [
        1.0f32, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 0.5, 1.0, 1.0, 1.0, 0.0,
    ];
    let bytes: Vec<u8> = rgba.iter().flat_map(|x| x.to_le_bytes()).collect();
    let opacity = |job: &prism::load::Job, b1: f32, b2: f32| match &job.scene.materials[0] {
        prism::bsdf::Material::Mask { opacity, .. } => opacity.eval(at(b1, b2)),
        m => panic!("{m:?}"),
    };
    let blend =
        r#"{"alphaMode": "BLEND", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.8]}}"#;
    let job = load("blend", &triangle((5126, "VEC4", bytes.clone()), blend)).unwrap();
    for (b1, b2) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (0.25, 0.25), (0.5, 0.1)] {
        let expect = 0.8 * ((1.0 - b1 - b2) + 0.5 * b1);
        assert!(
            (opacity(&job, b1, b2) - expect).abs() < 1e-6,
            "({b1}, {b2})"
        );
    }
    let mask = r#"{"alphaMode": "MASK", "alphaCutoff": 0.5, "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.8]}}"#;
    let job = load("mask", &triangle((5126, "VEC4", bytes), mask)).unwrap();
    // 0.8 · (0.3 + 0.5 · 0.7) = 0.52 is kept; 0.8 · (0.2 + 0.5 · 0.7) = 0.44 is cut.
    assert_eq!(opacity(&job, 0.7, 0.0), 1.0);
    assert_eq!(opacity(&job, 0.7, 0.1), 0.0);
}

/// A COLOR_0 the specification does not allow (VEC2; a count unlike POSITION's; a NaN) is
/// refused naming the attribute, where before it was ignored with a warning (and the gltf
/// crate's reader would hit `unreachable!` on a VEC2).
#[test]
fn bad_color_0_is_refused_naming_the_attribute() {
    let floats = |v: &[f32]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
    let cases = [
        ("vec2", triangle((5126, "VEC2", floats(&[1.0; 6])), PLAIN)),
        (
            "nan",
            triangle(
                (
                    5126,
                    "VEC3",
                    floats(&[1.0, f32::NAN, 0.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0]),
                ),
                PLAIN,
            ),
        ),
        (
            "count",
            triangle((5126, "VEC3", floats(&[1.0; 9])), PLAIN).replace(
                r#""count": 3, "type": "VEC3"}]"#,
                r#""count": 2, "type": "VEC3"}]"#,
            ),
        ),
    ];
    for (name, text) in cases {
        let e = load(name, &text)
            .err()
            .unwrap_or_else(|| panic!("{name}: accepted"));
        let shown = e.to_string();
        let prism::error::Error::Input(e) = e else {
            panic!("{name}: {shown}")
        };
        assert!(
            e.field.as_deref() == Some("meshes[0].primitives[0].attributes.COLOR_0")
                && e.hint.is_some(),
            "{name}: {shown}"
        );
    }
}
