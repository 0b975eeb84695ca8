//! Mutations: structure-aware ones of RON and text (numbers, tokens, strings, fragments) and
//! byte-level ones of any file, and the case they make from a seed (deterministic in the run
//! seed and case index).

use super::{Case, FileKind, SeedScene, Seeds};
use prism::math::rng::{hash3, Pcg32};

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
        let texty = matches!(
            f.kind,
            FileKind::Spectrum | FileKind::Mesh | FileKind::Sensor
        ) || f.name.ends_with(".gltf");
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
            dataset: None,
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
                    dataset: None,
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
            dataset: None,
        }
    }
}

/// The dataset case `index` of the run seeded `seed`: a dataset seed's config mutated one to
/// three times (as text, or sometimes as bytes), its base scene sometimes too, an output
/// folder state and the command's flags (examples/fuzz/engine/dataset.rs).
pub fn make_dataset_case(seeds: &Seeds, seed: u64, index: u64) -> Case {
    use super::damage::random_state;
    use super::dataset::{DatasetCase, FLAGS};
    let mut r = Rng(Pcg32::new(hash3(seed, index, 0xda7a), index));
    let s = r.pick(&seeds.datasets).clone();
    let mut what = vec![s.name.clone()];
    let mut config = s.config.clone();
    let steps = r.below(4);
    for _ in 0..steps {
        if r.chance(0.15) {
            let mut b = config.into_bytes();
            what.push(mutate_bytes(&mut r, &mut b));
            config = String::from_utf8_lossy(&b).into_owned();
        } else {
            what.push(mutate_text(&mut r, &mut config, &[]));
        }
    }
    let mut scene = s.scene.clone();
    if r.chance(0.1) {
        what.push(format!(
            "scene: {}",
            mutate_text(&mut r, &mut scene, &seeds.scenes)
        ));
    }
    let state = random_state(&mut |n| r.below(n));
    let flags: Vec<String> = r.pick(FLAGS).iter().map(|f| f.to_string()).collect();
    what.push(format!("{state:?} {flags:?}"));
    Case {
        index,
        what: what.join("; "),
        scene,
        file: None,
        dataset: Some(DatasetCase {
            config,
            prime_config: s.config,
            prime_scene: s.scene,
            state,
            flags,
        }),
    }
}
