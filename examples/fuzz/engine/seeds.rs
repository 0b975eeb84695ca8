//! The fuzzer's seeds: the repository's scenes, meshes, textures, spectra and glTF files, each
//! prepared to render in milliseconds (an 8×6 film) from a case directory.

use super::{FileKind, SeedFile, SeedScene, Seeds};
use std::path::{Path, PathBuf};

const FILM: &str = "film: (width: 8, height: 6), ";

/// The repository's scenes (scenes/**/*.ron), meshes, textures and spectra, prepared as seeds.
pub fn load_seeds(repo: &Path) -> Seeds {
    let mut scenes = Vec::new();
    let mut stack = vec![repo.join("scenes")];
    let mut files = Vec::new();
    while let Some(d) = stack.pop() {
        let mut entries: Vec<PathBuf> = std::fs::read_dir(&d)
            .expect("scenes/")
            .map(|e| e.unwrap().path())
            .collect();
        entries.sort();
        for p in entries {
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|e| e == "ron") {
                let text = std::fs::read_to_string(&p).unwrap();
                let rel = p.strip_prefix(repo).unwrap().display().to_string();
                scenes.push(SeedScene {
                    name: rel,
                    text: prepare(&text, p.parent().unwrap(), repo),
                });
            } else {
                files.push(p);
            }
        }
    }
    // Scenes that read no file would leave spectra unfuzzed; these hosts read one.
    let host = |body: &str| format!("({FILM}sampler: (spp: 1), {body})");
    let lit =
        "shapes: [(shape: Sphere(radius: 1), material: \"m\", to_world: [Translate((0, 0, 4))])], ";
    let mut seed_files = Vec::new();
    let spectra = repo.join("spectra");
    let mut tables = Vec::new();
    for sub in ["illuminants", "metals", "cmf"] {
        let mut v: Vec<PathBuf> = std::fs::read_dir(spectra.join(sub))
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        v.sort();
        tables.extend(v.into_iter().map(|p| (sub, p)));
    }
    for (sub, p) in tables {
        let bytes = std::fs::read(&p).unwrap();
        let scene = match sub {
            "illuminants" => host(&format!(
                "materials: {{\"m\": Diffuse()}}, {lit}emitters: [Constant(radiance: File(path: \"@CASE@/s.txt\"))]"
            )),
            "metals" => host(&format!(
                "materials: {{\"m\": RoughConductor(eta: File(path: \"@CASE@/s.txt\", column: \"eta\"), k: File(path: \"@CASE@/s.txt\", column: \"k\"))}}, {lit}emitters: [Constant(radiance: Named(\"D65\"))]"
            )),
            _ => host(&format!(
                "materials: {{\"m\": Diffuse(reflectance: File(path: \"@CASE@/s.txt\", column: \"y\"))}}, {lit}emitters: [Constant(radiance: Named(\"D65\"))]"
            )),
        };
        seed_files.push(SeedFile {
            kind: FileKind::Spectrum,
            name: "s.txt".into(),
            bytes,
            host: scene,
        });
    }
    for p in files {
        let ext = p.extension().and_then(|e| e.to_str()).unwrap_or("");
        let bytes = std::fs::read(&p).unwrap();
        let mat = |m: &str| {
            host(&format!(
                "materials: {{\"m\": {m}}}, shapes: [(shape: Rectangle, material: \"m\", to_world: [Translate((0, 0, 3))])], emitters: [Constant(radiance: Named(\"D65\"))]"
            ))
        };
        match ext {
            "obj" => {
                let ply = obj_to_ply(&String::from_utf8_lossy(&bytes));
                let mesh = |n: &str| {
                    host(&format!(
                        "materials: {{\"m\": Diffuse()}}, shapes: [(shape: Mesh(path: \"@CASE@/{n}\"), material: \"m\", to_world: [Translate((0, 0, 4))])], emitters: [Constant(radiance: Named(\"D65\"))]"
                    ))
                };
                seed_files.push(SeedFile {
                    kind: FileKind::Mesh,
                    name: "m.obj".into(),
                    bytes,
                    host: mesh("m.obj"),
                });
                for b in ply {
                    seed_files.push(SeedFile {
                        kind: FileKind::Mesh,
                        name: "m.ply".into(),
                        bytes: b,
                        host: mesh("m.ply"),
                    });
                }
            }
            "png" | "exr" => {
                let n = format!("t.{ext}");
                let tex = format!("Bitmap(path: \"@CASE@/{n}\")");
                for m in [
                    format!("Diffuse(reflectance: {tex})"),
                    format!("Mask(opacity: {tex}, bsdf: Diffuse())"),
                    format!("Blend(weight: {tex}, bsdf0: Diffuse(), bsdf1: Conductor())"),
                    format!("RoughConductor(alpha: {tex})"),
                ] {
                    seed_files.push(SeedFile {
                        kind: FileKind::Texture,
                        name: n.clone(),
                        bytes: bytes.clone(),
                        host: mat(&m),
                    });
                }
                seed_files.push(SeedFile {
                    kind: FileKind::Envmap,
                    name: n.clone(),
                    bytes: bytes.clone(),
                    host: host(&format!("emitters: [Envmap(filename: \"@CASE@/{n}\")]")),
                });
            }
            _ => {}
        }
    }
    gltf_seeds(repo, &host, &mut seed_files);
    sensor_seeds(repo, &host, &mut seed_files);
    scenes.extend(feature_scenes(&host));
    Seeds {
        scenes,
        files: seed_files,
        datasets: super::dataset::dataset_seeds(repo),
    }
}

/// The repository's glTF files (tests/data/gltf: the Khronos samples; examples/fuzz/seeds:
/// every extension prism reads), each as `.gltf` and wrapped as a `.glb`, included by a RON
/// scene as it is and placed, with its lights off and a material replaced.
fn gltf_seeds(repo: &Path, host: &dyn Fn(&str) -> String, out: &mut Vec<SeedFile>) {
    let mut paths = Vec::new();
    for dir in ["tests/data/gltf", "examples/fuzz/seeds"] {
        let mut v: Vec<PathBuf> = std::fs::read_dir(repo.join(dir))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "gltf"))
            .collect();
        v.sort();
        paths.extend(v);
    }
    for p in paths {
        let json = std::fs::read(&p).unwrap();
        // A replacement by name where the file has that material, else of all its materials.
        let replace = if String::from_utf8_lossy(&json).contains("\"Glass\"") {
            "materials: {\"Glass\": \"m\"})"
        } else {
            "), material: \"m\""
        };
        for (name, bytes) in [("m.gltf", json.clone()), ("m.glb", glb(&json))] {
            for shape in [
                format!("(shape: Gltf(path: \"@CASE@/{name}\"))"),
                format!("(shape: Gltf(path: \"@CASE@/{name}\", lights: false, {replace}, to_world: [Scale((2, 2, -2)), Translate((0, 0, 4))])"),
            ] {
                out.push(SeedFile {
                    kind: FileKind::Gltf,
                    name: name.into(),
                    bytes: bytes.clone(),
                    host: host(&format!("materials: {{\"m\": Diffuse()}}, shapes: [{shape}], emitters: [Constant(radiance: Named(\"D65\"))]")),
                });
            }
        }
    }
}

/// The sensor files of configs/sensors/ (observers, band sets, cameras, the raw model), read
/// by a scene whose spectral range covers their near-infrared bands.
fn sensor_seeds(repo: &Path, host: &dyn Fn(&str) -> String, out: &mut Vec<SeedFile>) {
    let mut v: Vec<PathBuf> = std::fs::read_dir(repo.join("configs/sensors"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "ron"))
        .collect();
    v.sort();
    for p in v {
        out.push(SeedFile {
            kind: FileKind::Sensor,
            name: "sensor.ron".into(),
            bytes: std::fs::read(&p).unwrap(),
            host: host(&format!(
                "spectral: (range: (360, 1000)), sensor: File(\"@CASE@/sensor.ron\"), {LIT}"
            )),
        });
    }
}

/// A lit sphere on a diffuse floor: the body of the feature scenes.
const LIT: &str = "materials: {\"m\": Diffuse()}, shapes: [(shape: Sphere(radius: 1), material: \"m\", name: \"ball\", to_world: [Translate((0, 0, 4))]), (shape: Rectangle, material: \"m\", to_world: [Scale((5, 5, 1)), Translate((0, 0, 6))])], emitters: [Constant(radiance: Named(\"D65\"))]";

/// This round's scene features, one scene each (mutated as scenes are): cameras (thin lens,
/// orthographic, intrinsics, distortion), AOVs, an inline raw sensor, camera curves.
fn feature_scenes(host: &dyn Fn(&str) -> String) -> Vec<SeedScene> {
    let features = [
        ("thin_lens", "camera: (model: ThinLens(aperture_radius: 0.05, focus_distance: 4), fov: 40), aovs: [\"depth\", \"distance\"], "),
        ("orthographic", "camera: (model: Orthographic(width: 3)), aovs: [\"normal\", \"normal_camera\", \"alpha\"], "),
        ("intrinsics_distortion", "camera: (intrinsics: Some((fx: 8, fy: 8, cx: 3.5, cy: 2.5)), distortion: Some((k1: -0.1, k2: 0.01, p1: 0.001, p2: -0.001, k3: 0))), aovs: [\"depth\", \"instance\", \"label\", \"geo_normal\"], "),
        ("aovs_all", "aovs: [\"depth\", \"distance\", \"normal\", \"normal_camera\", \"geo_normal\", \"geo_normal_camera\", \"instance\", \"label\", \"alpha\"], "),
        ("raw_inline", "sensor: (rgb: [Srgb], bands: [], camera: (curves: Named(\"sony_ilce_7m3\"), white_balance: Illuminant(\"D65\"), exposure: (iso: 100, shutter: 0.01, f_number: 4)), raw: (pattern: Rggb, pixel_pitch: 5.93, quantum_efficiency: 0.5, full_well: 50000, read_noise: 3.0, dark_current: 0.1, gain: UnityIso(315), black_level: 512, bits: 14, noise: true)), "),
        ("bands_filters", "spectral: (range: (360, 1000), sampling: Sensor), sensor: (observer: Cie1931, bands: [Even(count: 4), Boxes([(400, 450), (600, 700)]), Filter(name: \"nir\", curve: Gaussian(centre: 850, fwhm: 40))]), "),
    ];
    features
        .iter()
        .map(|(name, f)| SeedScene {
            name: format!("feature:{name}"),
            text: host(&format!("{f}{LIT}")),
        })
        .collect()
}

/// A glTF JSON document in the binary container (glTF 2.0 §4.4): the 12-byte header and one
/// JSON chunk padded with spaces to 4 bytes (embedded buffers stay data: URIs).
fn glb(json: &[u8]) -> Vec<u8> {
    let mut chunk = json.to_vec();
    while chunk.len() % 4 != 0 {
        chunk.push(b' ');
    }
    let total = 12 + 8 + chunk.len() as u32;
    let mut b = Vec::with_capacity(total as usize);
    b.extend_from_slice(b"glTF");
    b.extend_from_slice(&2u32.to_le_bytes());
    b.extend_from_slice(&total.to_le_bytes());
    b.extend_from_slice(&(chunk.len() as u32).to_le_bytes());
    b.extend_from_slice(b"JSON");
    b.extend_from_slice(&chunk);
    b
}

/// Makes a scene's relative paths `@REPO@/...` and its film 8×6.
pub(super) fn prepare(text: &str, dir: &Path, repo: &Path) -> String {
    let rel_dir = dir.strip_prefix(repo).unwrap();
    let mut t = absolutise(text, "path: \"", rel_dir);
    t = absolutise(&t, "filename: \"", rel_dir);
    for (key, v) in [("width", "8"), ("height", "6")] {
        t = set_number(&t, key, v);
    }
    if !t.contains("film:") {
        if let Some(i) = first_paren(&t) {
            t.insert_str(i + 1, FILM);
        }
    }
    t
}

/// Rewrites the string after each `key` (`path: "`) as `@REPO@/<rel_dir>/<string>`.
fn absolutise(text: &str, key: &str, rel_dir: &Path) -> String {
    let mut out = String::new();
    let mut rest = text;
    while let Some(i) = rest.find(key) {
        out.push_str(&rest[..i + key.len()]);
        rest = &rest[i + key.len()..];
        let end = rest.find('"').unwrap_or(0);
        out.push_str(&format!(
            "@REPO@/{}",
            normalise(&rel_dir.join(&rest[..end]))
        ));
        rest = &rest[end..];
    }
    out.push_str(rest);
    out
}

/// Rewrites every string literal starting `../` as `@REPO@/<rel_dir>/<string>` (a dataset
/// config's sensor and envmap files).
pub(super) fn absolute_strings(text: &str, rel_dir: &Path) -> String {
    let mut out = String::new();
    let mut rest = text;
    while let Some(i) = rest.find("\"../") {
        out.push_str(&rest[..i + 1]);
        rest = &rest[i + 1..];
        let end = rest.find('"').unwrap_or(0);
        out.push_str(&format!(
            "@REPO@/{}",
            normalise(&rel_dir.join(&rest[..end]))
        ));
        rest = &rest[end..];
    }
    out.push_str(rest);
    out
}

fn normalise(p: &Path) -> String {
    let mut parts: Vec<String> = Vec::new();
    for c in p.components() {
        match c {
            std::path::Component::ParentDir => {
                parts.pop();
            }
            std::path::Component::Normal(s) => parts.push(s.to_string_lossy().into()),
            _ => {}
        }
    }
    parts.join("/")
}

/// The first `(` outside comments.
fn first_paren(t: &str) -> Option<usize> {
    let mut off = 0;
    for line in t.split_inclusive('\n') {
        let code = line.split("//").next().unwrap();
        if let Some(i) = code.find('(') {
            return Some(off + i);
        }
        off += line.len();
    }
    None
}

/// Replaces the number after each `key:` (a whole word) with `v`.
pub(super) fn set_number(t: &str, key: &str, v: &str) -> String {
    let pat = format!("{key}:");
    let mut out = String::new();
    let mut i = 0;
    while let Some(j) = t[i..].find(&pat) {
        let at = i + j;
        let word = at == 0 || {
            let c = t.as_bytes()[at - 1];
            !(c.is_ascii_alphanumeric() || c == b'_')
        };
        out.push_str(&t[i..at + pat.len()]);
        i = at + pat.len();
        if word {
            let num_start = i + t[i..].len() - t[i..].trim_start().len();
            let num_end = num_start
                + t[num_start..]
                    .find(|c: char| !(c.is_ascii_digit() || c == '.'))
                    .unwrap_or(t.len() - num_start);
            if num_end > num_start {
                out.push(' ');
                out.push_str(v);
                i = num_end;
            }
        }
    }
    out.push_str(&t[i..]);
    out
}

/// The OBJ's vertices and faces as an ASCII PLY and a binary little-endian PLY (prism has no
/// PLY of its own in the repository).
fn obj_to_ply(obj: &str) -> Vec<Vec<u8>> {
    let mut v: Vec<[f32; 3]> = Vec::new();
    let mut f: Vec<Vec<i32>> = Vec::new();
    for l in obj.lines() {
        let mut w = l.split_whitespace();
        match w.next() {
            Some("v") => {
                let c: Vec<f32> = w.filter_map(|x| x.parse().ok()).collect();
                if c.len() >= 3 {
                    v.push([c[0], c[1], c[2]]);
                }
            }
            Some("f") => f.push(
                w.filter_map(|x| x.split('/').next()?.parse::<i32>().ok())
                    .map(|i| i - 1)
                    .collect(),
            ),
            _ => {}
        }
    }
    let header = |fmt: &str| {
        format!(
            "ply\nformat {fmt} 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
            v.len(),
            f.len()
        )
    };
    let mut ascii = header("ascii");
    for p in &v {
        ascii.push_str(&format!("{} {} {}\n", p[0], p[1], p[2]));
    }
    for face in &f {
        ascii.push_str(&face.len().to_string());
        for i in face {
            ascii.push_str(&format!(" {i}"));
        }
        ascii.push('\n');
    }
    let mut bin = header("binary_little_endian").into_bytes();
    for p in &v {
        for c in p {
            bin.extend_from_slice(&c.to_le_bytes());
        }
    }
    for face in &f {
        bin.push(face.len() as u8);
        for i in face {
            bin.extend_from_slice(&i.to_le_bytes());
        }
    }
    vec![ascii.into_bytes(), bin]
}
