//! The mutation fuzzer's engine, shared by the long-run driver (`examples/fuzz/main.rs`) and the
//! test (`tests/fuzz.rs`). A case is a scene text, perhaps with one input file (mesh, texture,
//! spectrum table), made by mutating the repository's own scenes and files; it is run through
//! prism (the binary, or the library in-process) and must end with exit code 0 or 2: no panic,
//! no other code, no signal, no hang past the time bound, no allocation past the memory bound.
//!
//! Scene texts carry two placeholders, so a case (and a regression case in tests/fuzz_corpus/)
//! can be replayed anywhere: `@REPO@` (the repository root) and `@CASE@` (the case's directory,
//! which holds `scene.ron` and the mutated input file).

#![allow(dead_code)]

use prism::math::rng::{hash3, Pcg32};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// What an input file is (decides the mutations and the scene that uses it).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileKind {
    Mesh,
    Texture,
    Envmap,
    Spectrum,
}

/// A seed scene: its name and text with every relative path made `@REPO@/...`, the film shrunk
/// to 8×6 so that each case renders in milliseconds.
#[derive(Clone, Debug)]
pub struct SeedScene {
    pub name: String,
    pub text: String,
}

/// A seed file and a scene that reads it through `@CASE@/<name>`.
#[derive(Clone, Debug)]
pub struct SeedFile {
    pub kind: FileKind,
    /// The file name the case writes (keeps the extension, which selects the reader).
    pub name: String,
    pub bytes: Vec<u8>,
    pub host: String,
}

pub struct Seeds {
    pub scenes: Vec<SeedScene>,
    pub files: Vec<SeedFile>,
}

/// One case: the scene text and at most one input file (name, bytes) beside it.
#[derive(Clone, Debug)]
pub struct Case {
    pub index: u64,
    pub what: String,
    pub scene: String,
    pub file: Option<(String, Vec<u8>)>,
}

/// How a case ended.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Verdict {
    Ok(i32),
    Panic(String),
    WrongExit(i32, String),
    Signal(String),
    Hang,
}

impl Verdict {
    pub fn is_ok(&self) -> bool {
        matches!(self, Verdict::Ok(_))
    }
    pub fn label(&self) -> &'static str {
        match self {
            Verdict::Ok(_) => "ok",
            Verdict::Panic(_) => "panic",
            Verdict::WrongExit(..) => "wrong-exit",
            Verdict::Signal(_) => "signal",
            Verdict::Hang => "hang",
        }
    }
}

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
    Seeds {
        scenes,
        files: seed_files,
    }
}

/// Makes a scene's relative paths `@REPO@/...` and its film 8×6.
fn prepare(text: &str, dir: &Path, repo: &Path) -> String {
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
fn set_number(t: &str, key: &str, v: &str) -> String {
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

// ---------------------------------------------------------------------------------------------
// Mutations.

struct Rng(Pcg32);

impl Rng {
    fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            ((self.0.next_u32() as u64 * n as u64) >> 32) as usize
        }
    }
    fn chance(&mut self, p: f32) -> bool {
        self.0.next_f32() < p
    }
    fn pick<'a, T>(&mut self, v: &'a [T]) -> &'a T {
        &v[self.below(v.len())]
    }
}

/// Numbers that break things: non-finite, huge, tiny, negative, zero, off-by-one at integer
/// limits, a float where an integer belongs.
const NUMBERS: &[&str] = &[
    "NaN",
    "inf",
    "-inf",
    "1e38",
    "-1e38",
    "3.5e38",
    "1e-45",
    "0",
    "-0",
    "-1",
    "1e9",
    "-1e9",
    "4294967295",
    "4294967296",
    "18446744073709551615",
    "18446744073709551616",
    "-2147483648",
    "1.5",
    "65536",
    "65537",
    "32768",
    "32769",
    "4097",
    "1e20",
    "1e-30",
    "0.0001",
    "17",
    "3",
    "1e6",
    "-0.5",
    "2",
];

/// Strings for string fields: missing, odd or hostile paths, odd text.
const STRINGS: &[&str] = &[
    "",
    "/dev/zero",
    "/dev/stdin",
    "/proc/self/mem",
    "@CASE@",
    "@CASE@/nonexistent.png",
    "@REPO@/scenes",
    "@REPO@/scenes/cornell.ron",
    "@REPO@/scenes/textures/sky.exr",
    "@REPO@/scenes/meshes/prism.obj",
    "@REPO@/spectra/metals/Au.txt",
    "@REPO@/spectra/cmf/CIE1931_2deg.txt",
    "場景",
    "a\\u{0}b",
    "none",
    "Au",
    "D65",
    "bk7",
    "SF11",
];

/// Fragments spliced in: fields and values the format has (taken from no particular scene).
const FRAGMENTS: &[&str] = &[
    "width: 40000, ",
    "height: 32768, ",
    "bands: 4096, ",
    "bands: 0, ",
    "wavelengths: 16, ",
    "wavelengths: 3, ",
    "max_depth: 100000, ",
    "caustics: (light_paths: 1e9), ",
    "caustics: (), ",
    "clamp: 0, ",
    "range: (830, 360), ",
    "range: (1, 1e9), ",
    "band_range: (400, 401), ",
    "spp: 0, ",
    "kind: Independent, ",
    "fov: 179.99, ",
    "near_clip: 1e-30, ",
    "to_world: [Matrix(((1,0,0,0),(0,1,0,0),(0,0,1,0),(0,0,0.5,1)))], ",
    "to_world: [Scale((0, 1, 1))], ",
    "to_world: [Scale((1e30, 1e30, 1e30))], ",
    "filter: Box(radius: 8), ",
    "filter: Gaussian(stddev: 1e-30), ",
    "\"m\": Diffuse(), \"m\": Conductor(), ",
    "emitter: (radiance: Scaled(1e19, Named(\"D65\"))), ",
    "Scaled(1e38, Named(\"D65\"))",
    "Blackbody(1e30)",
    "Tabulated([])",
    "Tabulated([(500, 1), (500, 2)])",
    "Rgb(1e30, 0, 0)",
    "Checkerboard(color0: Constant(2), color1: Rgb(NaN, 0, 0))",
    "Sphere(radius: 1e-30)",
    "Sphere(radius: 1e30)",
    "Mesh(path: \"@REPO@/scenes/stress/meshes/slivers.obj\")",
    "accel: BruteForce, ",
    "accel: Embree, ",
    "(((((((((((((((((((((((((((((((((((((((((((((",
    "[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[",
    "\u{feff}",
    "/*",
    "r#\"",
];

fn token_spans(t: &str) -> Vec<(usize, usize)> {
    let b = t.as_bytes();
    let mut v = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        let start = i;
        if c.is_ascii_whitespace() {
            i += 1;
            continue;
        } else if c.is_ascii_alphanumeric() || c == b'_' || c == b'.' || c == b'-' || c == b'+' {
            while i < b.len()
                && (b[i].is_ascii_alphanumeric() || matches!(b[i], b'_' | b'.' | b'-' | b'+'))
            {
                i += 1;
            }
        } else if c == b'"' {
            i += 1;
            while i < b.len() && b[i] != b'"' {
                i += 1;
            }
            i = (i + 1).min(b.len());
        } else {
            i += 1;
            while i < b.len() && !b[i].is_ascii() {
                i += 1;
            }
        }
        v.push((start, i));
    }
    v
}

fn number_spans(t: &str) -> Vec<(usize, usize)> {
    token_spans(t)
        .into_iter()
        .filter(|&(a, b)| {
            let s = &t[a..b];
            s.parse::<f64>().is_ok() && s.as_bytes()[0] != b'.'
        })
        .collect()
}

fn string_spans(t: &str) -> Vec<(usize, usize)> {
    token_spans(t)
        .into_iter()
        .filter(|&(a, b)| b - a >= 2 && t.as_bytes()[a] == b'"' && t.as_bytes()[b - 1] == b'"')
        .map(|(a, b)| (a + 1, b - 1))
        .collect()
}

/// One structure-aware mutation of RON (or any text) `t`; returns its description.
fn mutate_text(r: &mut Rng, t: &mut String, others: &[SeedScene]) -> String {
    let op = r.below(10);
    match op {
        0..=2 => {
            let nums = number_spans(t);
            if nums.is_empty() {
                return mutate_text(r, t, others);
            }
            let (a, b) = *r.pick(&nums);
            let old = t[a..b].to_string();
            let new = if r.chance(0.2) {
                let x: f64 = old.parse().unwrap_or(1.0);
                format!("{}", x * [10.0, 1e10, -1.0, 0.1, 1e30][r.below(5)])
            } else {
                r.pick(NUMBERS).to_string()
            };
            t.replace_range(a..b, &new);
            format!("number {old} -> {new} at {a}")
        }
        3 => {
            let toks = token_spans(t);
            if toks.is_empty() {
                return "nothing".into();
            }
            let (a, b) = *r.pick(&toks);
            let old = t[a..b].to_string();
            t.replace_range(a..b, "");
            format!("drop token {old:?} at {a}")
        }
        4 => {
            let toks = token_spans(t);
            if toks.is_empty() {
                return "nothing".into();
            }
            let (a, b) = *r.pick(&toks);
            let old = t[a..b].to_string();
            t.insert_str(b, &old);
            format!("duplicate token {old:?} at {a}")
        }
        5 => {
            let s = string_spans(t);
            if s.is_empty() {
                return mutate_text(r, t, others);
            }
            let (a, b) = *r.pick(&s);
            let new = r.pick(STRINGS).to_string();
            let old = t[a..b].to_string();
            t.replace_range(a..b, &new);
            format!("string {old:?} -> {new:?}")
        }
        6 => {
            // Splice a fragment at a token boundary.
            let toks = token_spans(t);
            let at = if toks.is_empty() { 0 } else { r.pick(&toks).1 };
            let frag = if r.chance(0.5) || others.is_empty() {
                r.pick(FRAGMENTS).to_string()
            } else {
                let o = &r.pick(others).text;
                let lines: Vec<&str> = o.lines().collect();
                r.pick(&lines).to_string()
            };
            t.insert_str(at, &frag);
            format!("splice {frag:?} at {at}")
        }
        7 => {
            // Drop or duplicate a run of tokens (a field, a list item).
            let toks = token_spans(t);
            if toks.len() < 2 {
                return "nothing".into();
            }
            let i = r.below(toks.len());
            let j = (i + 1 + r.below(8)).min(toks.len());
            let (a, b) = (toks[i].0, toks[j - 1].1);
            if r.chance(0.5) {
                t.replace_range(a..b, "");
                format!("drop tokens {a}..{b}")
            } else {
                let s = t[a..b].to_string();
                t.insert_str(b, &s);
                format!("duplicate tokens {a}..{b}")
            }
        }
        8 => {
            let at = floor_char(t, r.below(t.len() + 1));
            t.truncate(at);
            format!("truncate at {at}")
        }
        _ => {
            // Swap two lines.
            let mut lines: Vec<String> = t.lines().map(String::from).collect();
            if lines.len() < 2 {
                return "nothing".into();
            }
            let (a, b) = (r.below(lines.len()), r.below(lines.len()));
            lines.swap(a, b);
            *t = lines.join("\n");
            format!("swap lines {a} {b}")
        }
    }
}

fn floor_char(t: &str, mut i: usize) -> usize {
    while i > 0 && !t.is_char_boundary(i) {
        i -= 1;
    }
    i
}

/// One byte-level mutation.
fn mutate_bytes(r: &mut Rng, b: &mut Vec<u8>) -> String {
    let n = b.len();
    match r.below(8) {
        0 if n > 0 => {
            let i = r.below(n);
            b[i] ^= 1 << r.below(8);
            format!("flip bit at {i}")
        }
        1 if n > 0 => {
            let i = r.below(n);
            b[i] = *r.pick(&[
                0u8, 0xff, 0x7f, 0x80, b'(', b')', b',', b'"', b':', b'\n', b'-', b'9',
            ]);
            format!("set byte {i}")
        }
        2 => {
            let i = r.below(n + 1);
            b.insert(i, r.0.next_u32() as u8);
            format!("insert byte at {i}")
        }
        3 if n > 0 => {
            let i = r.below(n);
            let len = (1 + r.below(64)).min(n - i);
            b.drain(i..i + len);
            format!("delete {len} bytes at {i}")
        }
        4 if n > 0 => {
            let i = r.below(n);
            let len = (1 + r.below(256)).min(n - i);
            let chunk: Vec<u8> = b[i..i + len].to_vec();
            let at = r.below(n + 1);
            b.splice(at..at, chunk);
            format!("duplicate {len} bytes at {i} to {at}")
        }
        5 => {
            let at = r.below(n + 1);
            b.truncate(at);
            format!("truncate at {at}")
        }
        6 if n >= 4 => {
            // A 32-bit word set to a boundary value (sizes, counts, offsets in binary headers).
            let i = r.below(n - 3);
            let v: u32 = *r.pick(&[0, 1, 0x7fff_ffff, 0xffff_ffff, 0x8000_0000, 65536, 1 << 24]);
            b[i..i + 4].copy_from_slice(&v.to_le_bytes());
            format!("set u32 at {i} to {v}")
        }
        _ => {
            const ODD: [&[u8]; 3] = [b"\xef\xbb\xbf", b"\xff\xfe", b"\xc3\x28"];
            let pre: &[u8] = ODD[r.below(ODD.len())];
            let at = r.below(n + 1);
            b.splice(at..at, pre.iter().copied());
            format!("insert odd bytes at {at}")
        }
    }
}

/// The case `index` of the run seeded `seed` (the same pair always gives the same case).
pub fn make_case(seeds: &Seeds, seed: u64, index: u64) -> Case {
    let mut r = Rng(Pcg32::new(hash3(seed, index, 0x5eed), index));
    let mut what = Vec::new();
    let steps = 1 + r.below(3);
    if r.chance(0.35) && !seeds.files.is_empty() {
        let f = r.pick(&seeds.files).clone();
        what.push(format!("{:?} {}", f.kind, f.name));
        let mut bytes = f.bytes.clone();
        let texty = matches!(f.kind, FileKind::Spectrum | FileKind::Mesh);
        for _ in 0..steps {
            let text = if texty && r.chance(0.6) {
                String::from_utf8(bytes.clone()).ok()
            } else {
                None
            };
            if let Some(mut t) = text {
                what.push(mutate_text(&mut r, &mut t, &[]));
                bytes = t.into_bytes();
            } else {
                what.push(mutate_bytes(&mut r, &mut bytes));
            }
        }
        let mut scene = f.host.clone();
        if r.chance(0.1) {
            what.push(mutate_text(&mut r, &mut scene, &seeds.scenes));
        }
        Case {
            index,
            what: what.join("; "),
            scene,
            file: Some((f.name, bytes)),
        }
    } else {
        let s = r.pick(&seeds.scenes);
        what.push(s.name.clone());
        let mut t = s.text.clone();
        if r.chance(0.15) {
            let mut b = t.into_bytes();
            what.push(mutate_bytes(&mut r, &mut b));
            t = String::from_utf8_lossy(&b).into_owned();
            if r.chance(0.5) {
                // Keep invalid UTF-8 sometimes: write the bytes as they are.
                return Case {
                    index,
                    what: what.join("; "),
                    scene: t,
                    file: None,
                };
            }
        }
        for _ in 0..steps {
            what.push(mutate_text(&mut r, &mut t, &seeds.scenes));
        }
        Case {
            index,
            what: what.join("; "),
            scene: t,
            file: None,
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Running a case.

/// Bounds on one case.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    /// Wall-clock bound: catches a prism blocked without using the CPU (a deadlock, a read
    /// that never ends). Generous, since a loaded machine stretches wall time.
    pub timeout: Duration,
    /// CPU-time bound of a spawned prism (`prlimit --cpu`, SIGXCPU past it): catches a busy
    /// loop whatever the machine's load (a 20 s wall bound flagged an 8×32768 film at 1.9 s
    /// of CPU as a hang under a load average of 20).
    pub cpu_seconds: u64,
    /// Address-space limit of a spawned prism (`prlimit --as`), bytes.
    pub address_space: u64,
    /// `--max-memory` given to prism.
    pub max_memory: &'static str,
}

pub const LIMITS: Limits = Limits {
    timeout: Duration::from_secs(120),
    cpu_seconds: 20,
    address_space: 4 << 30,
    max_memory: "1GiB",
};

/// Writes `case` into `dir` (emptied first); returns the scene's path.
pub fn materialise(case: &Case, dir: &Path, repo: &Path) -> PathBuf {
    let _ = std::fs::remove_dir_all(dir);
    std::fs::create_dir_all(dir).unwrap();
    let fill = |t: &str| {
        t.replace("@REPO@", &repo.display().to_string())
            .replace("@CASE@", &dir.display().to_string())
    };
    let scene = dir.join("scene.ron");
    std::fs::write(&scene, fill(&case.scene)).unwrap();
    if let Some((name, bytes)) = &case.file {
        std::fs::write(dir.join(name), bytes).unwrap();
    }
    scene
}

fn args(scene: &Path, dir: &Path, limits: &Limits) -> Vec<String> {
    let s = |p: PathBuf| p.display().to_string();
    vec![
        "render".into(),
        scene.display().to_string(),
        "-o".into(),
        s(dir.join("out.exr")),
        "--preview".into(),
        s(dir.join("out.png")),
        "--spp".into(),
        "1".into(),
        "--threads".into(),
        "1".into(),
        "--max-memory".into(),
        limits.max_memory.into(),
        "-q".into(),
    ]
}

/// Runs the prism binary `bin` on the case in `dir`, under the limits.
pub fn run_binary(bin: &Path, scene: &Path, dir: &Path, limits: &Limits) -> (Verdict, String) {
    let mut child = Command::new("prlimit")
        .arg(format!("--as={}", limits.address_space))
        // Soft limit first: SIGXCPU (below), a second later the hard limit's SIGKILL.
        .arg(format!(
            "--cpu={}:{}",
            limits.cpu_seconds,
            limits.cpu_seconds + 1
        ))
        .arg("--")
        .arg(bin)
        .args(args(scene, dir, limits))
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("prlimit and prism run");
    let start = Instant::now();
    let mut stderr = child.stderr.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut s = String::new();
        use std::io::Read;
        let _ = stderr.read_to_string(&mut s);
        s
    });
    let status = loop {
        if let Some(st) = child.try_wait().unwrap() {
            break Some(st);
        }
        if start.elapsed() > limits.timeout {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(2));
    };
    let err = reader.join().unwrap_or_default();
    let v = match status {
        None => Verdict::Hang,
        Some(st) => match st.code() {
            _ if err.contains("panicked") => Verdict::Panic(tail(&err)),
            Some(c @ (0 | 2)) => Verdict::Ok(c),
            Some(101) => Verdict::Panic(tail(&err)),
            Some(c) => Verdict::WrongExit(c, tail(&err)),
            None => {
                use std::os::unix::process::ExitStatusExt;
                match st.signal() {
                    Some(libc::SIGXCPU) => Verdict::Hang,
                    s => Verdict::Signal(format!("signal {s:?}: {}", tail(&err))),
                }
            }
        },
    };
    (v, err)
}

fn tail(s: &str) -> String {
    let lines: Vec<&str> = s.lines().collect();
    lines[lines.len().saturating_sub(6)..].join("\n")
}

static PANIC: Mutex<Option<String>> = Mutex::new(None);

/// Makes in-process panics quiet and records the last message (call once).
pub fn install_panic_hook() {
    std::panic::set_hook(Box::new(|info| {
        let msg = format!("{info}");
        if info.location().is_some_and(|l| l.file().contains("fuzz")) {
            eprintln!("the fuzzer itself panicked: {msg}");
        }
        *PANIC.lock().unwrap_or_else(|e| e.into_inner()) = Some(msg);
    }));
}

/// Runs the case in `dir` through `prism::cli::run` in this process, catching panics. Hangs
/// and memory are not bounded here (the binary runs are for those).
pub fn run_in_process(scene: &Path, dir: &Path, limits: &Limits) -> Verdict {
    let mut a = vec!["prism".to_string()];
    a.extend(args(scene, dir, limits));
    match std::panic::catch_unwind(|| prism::cli::run(a)) {
        Ok(c @ (0 | 2)) => Verdict::Ok(c),
        Ok(c) => Verdict::WrongExit(c, String::new()),
        Err(_) => Verdict::Panic(
            PANIC
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .take()
                .unwrap_or_default(),
        ),
    }
}

/// A regression case of tests/fuzz_corpus/: a directory with `scene.ron` (placeholders as
/// above) and at most one other file, the input it reads.
pub fn load_corpus_case(dir: &Path) -> Case {
    let scene = std::fs::read_to_string(dir.join("scene.ron")).unwrap();
    let mut file = None;
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        let name = p.file_name().unwrap().to_string_lossy().into_owned();
        if !matches!(name.as_str(), "scene.ron" | "README" | "expect") {
            file = Some((name, std::fs::read(&p).unwrap()));
        }
    }
    Case {
        index: 0,
        what: dir.display().to_string(),
        scene,
        file,
    }
}

/// Saves a failing case as a corpus-style directory under `out`.
pub fn save_finding(case: &Case, verdict: &Verdict, stderr: &str, out: &Path) -> PathBuf {
    let d = out.join(format!("{}-{}", verdict.label(), case.index));
    let _ = std::fs::create_dir_all(&d);
    std::fs::write(d.join("scene.ron"), &case.scene).unwrap();
    if let Some((n, b)) = &case.file {
        std::fs::write(d.join(n), b).unwrap();
    }
    std::fs::write(
        d.join("README"),
        format!("{}\n{verdict:?}\n{stderr}\n", case.what),
    )
    .unwrap();
    d
}
