//! The floors (docs/ARCHITECTURE.md): every top-level module of src/ sits on one floor and may
//! import (`crate::NAME`) only modules on its own floor or below; the modules form no circle.
//! `FLOORS` is the one list of the allowed order. The check reads text as
//! ../shared/tools/layers.py does: comments, a file's trailing `#[cfg(test)]` module and files
//! named `tests.rs` / `*_tests.rs` are left out (a test may build what its module cannot).

mod source;

use source::{ident, rust_files, strip};
use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// Lowest floor first. A module not listed here fails the test: place a new module on purpose.
const FLOORS: &[(&str, &[&str])] = &[
    (
        "base",
        &[
            "error",
            "math",
            "spectrum",
            "film",
            "ray",
            "io",
            "resources",
        ],
    ),
    (
        "engine",
        &[
            "interaction",
            "motion",
            "sampler",
            "filter",
            "texture",
            "shape",
            "accel",
            "bsdf",
            "emitter",
            "camera",
            "sensor",
            "scene",
        ],
    ),
    ("render", &["integrator"]),
    ("describe", &["config"]),
    ("load", &["load"]),
    ("pipeline", &["pipeline", "output", "export"]),
    ("product", &["dataset"]),
    ("front", &["cli", "probe"]),
];

/// The top-level modules a file's text names through `crate::`.
fn names(text: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for (i, _) in text.match_indices("crate::") {
        let rest = &text[i + "crate::".len()..];
        if let Some(group) = rest.strip_prefix('{') {
            // `use crate::{a::X, b, c::{..}}`: the first name of each top-level item.
            let mut depth = 0;
            let mut start = true;
            for (k, c) in group.char_indices() {
                match c {
                    '{' => depth += 1,
                    '}' if depth == 0 => break,
                    '}' => depth -= 1,
                    ',' if depth == 0 => start = true,
                    c if start && (c.is_alphanumeric() || c == '_') => {
                        out.insert(ident(&group[k..]).to_string());
                        start = false;
                    }
                    c if c.is_whitespace() => {}
                    _ => start = false,
                }
            }
        } else {
            let n = ident(rest);
            if !n.is_empty() {
                out.insert(n.to_string());
            }
        }
    }
    out
}

/// Top-level module → the modules it imports → the files that do.
fn graph(src: &Path) -> BTreeMap<String, BTreeMap<String, BTreeSet<String>>> {
    let mut files = Vec::new();
    rust_files(src, &mut files);
    let mut edges: BTreeMap<String, BTreeMap<String, BTreeSet<String>>> = BTreeMap::new();
    for f in files {
        let name = f.file_name().unwrap().to_string_lossy().into_owned();
        if name == "tests.rs" || name.ends_with("_tests.rs") {
            continue;
        }
        let rel = f.strip_prefix(src).unwrap();
        let first = rel
            .components()
            .next()
            .unwrap()
            .as_os_str()
            .to_string_lossy();
        let a = first.trim_end_matches(".rs").to_string();
        if a == "main" || a == "lib" {
            continue;
        }
        let text = strip(&std::fs::read_to_string(&f).unwrap());
        for b in names(&text) {
            if b != a && b != "self" {
                edges
                    .entry(a.clone())
                    .or_default()
                    .entry(b)
                    .or_default()
                    .insert(rel.display().to_string());
            }
        }
    }
    edges
}

fn floor_of(module: &str) -> Option<usize> {
    FLOORS.iter().position(|(_, ms)| ms.contains(&module))
}

/// Every import between top-level modules points to the importer's floor or one below it.
#[test]
fn no_module_imports_a_higher_floor() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut problems = Vec::new();
    for e in std::fs::read_dir(&src).unwrap() {
        let name = e.unwrap().file_name().to_string_lossy().into_owned();
        let m = name.trim_end_matches(".rs");
        let test_file = m == "tests" || m.ends_with("_tests");
        if !matches!(m, "main" | "lib") && !test_file && floor_of(m).is_none() {
            problems.push(format!(
                "src/{name}: module `{m}` is on no floor (add it to FLOORS)"
            ));
        }
    }
    for (a, targets) in graph(&src) {
        for (b, files) in targets {
            match (floor_of(&a), floor_of(&b)) {
                (Some(fa), Some(fb)) if fb > fa => problems.push(format!(
                    "{a} ({}) imports {b} ({}), a higher floor: {}",
                    FLOORS[fa].0,
                    FLOORS[fb].0,
                    files.iter().cloned().collect::<Vec<_>>().join(", ")
                )),
                _ => {}
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// No circle among top-level modules, within a floor either (as layers.py reports).
#[test]
fn top_level_modules_form_no_circle() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let edges = graph(&src);
    // Depth-first search with colours: reaching a module still on the stack closes a circle.
    fn visit<'a>(
        v: &'a str,
        edges: &'a BTreeMap<String, BTreeMap<String, BTreeSet<String>>>,
        state: &mut BTreeMap<&'a str, u8>,
        stack: &mut Vec<&'a str>,
    ) -> Option<Vec<String>> {
        state.insert(v, 1);
        stack.push(v);
        for w in edges.get(v).into_iter().flat_map(|t| t.keys()) {
            match state.get(w.as_str()) {
                Some(1) => {
                    let i = stack.iter().position(|s| s == w).unwrap();
                    let mut c: Vec<String> = stack[i..].iter().map(|s| s.to_string()).collect();
                    c.push(w.clone());
                    return Some(c);
                }
                None => {
                    if let Some(c) = visit(w, edges, state, stack) {
                        return Some(c);
                    }
                }
                _ => {}
            }
        }
        stack.pop();
        state.insert(v, 2);
        None
    }
    let mut state = BTreeMap::new();
    for v in edges.keys() {
        if !state.contains_key(v.as_str()) {
            if let Some(c) = visit(v, &edges, &mut state, &mut Vec::new()) {
                panic!("import circle: {}", c.join(" -> "));
            }
        }
    }
}

/// The reader itself: group imports, comments and test modules as layers.py reads them.
#[test]
fn the_reader_sees_groups_and_skips_comments_and_tests() {
    let text = "use crate::{a::X, b, c::{d, e}};\nuse crate::f::G; // crate::h\n/* crate::i */\n\
                #[cfg(test)]\nmod tests {\n    use crate::j;\n}\n";
    let got: Vec<String> = names(&strip(text)).into_iter().collect();
    assert_eq!(got, ["a", "b", "c", "f"]);
    // Comment markers inside strings and character literals are text; block comments nest.
    let text = "let p = \"meshes/*.ply\"; let c = '/'; let r = r#\"//\"#;\n\
                /* a /* nested */ crate::k */ use crate::l; fn f<'a>(x: &'a u8) {}";
    let got: Vec<String> = names(&strip(text)).into_iter().collect();
    assert_eq!(got, ["l"]);
}

/// What `config` may name from below: settings enums and structs the schema deserialises into,
/// the BSDF list (whose entries carry each BSDF's schema), the error type, and the one door for
/// reading the scene file itself. An engine value that is built (a `Curve`, a texture, an `Ior`) is the loader's: its name here fails the test.
const CONFIG_MAY_NAME: &[&str] = &[
    "accel::AccelKind",
    "camera::FovAxis",
    "filter::FilterConfig",
    "integrator::Dispersion",
    "integrator::PathSettings",
    "integrator::RenderSettings",
    "integrator::adaptive::AdaptiveSpp",
    "integrator::adaptive::ErrorTarget",
    "sampler::SamplerKind",
    "sampler::SOBOL_MAX_SPP",
    "spectrum::WavelengthSampling",
    "bsdf::microfacet::Distribution",
    // The BSDF list: each entry writes its BSDF's schema, which config expands (builds nothing).
    "bsdf::for_each_bsdf",
    "texture::TexFilter",
    "texture::Wrap",
    "sensor::raw::BayerPattern",
    "sensor::raw::Gain",
    "sensor::Observer",
    "sensor::RgbSpace",
    "error::Error",
    "error::InputError",
    "io::inputs::record",
    "io::input_file::read",
    "io::input_file::Kind",
];

/// The full paths after `crate::` in `text`, groups expanded (`a::{b, c::d}` → `a::b`, `a::c::d`).
fn crate_paths(text: &str) -> Vec<String> {
    fn expand(prefix: &str, s: &str, out: &mut Vec<String>) -> usize {
        // Reads one path starting at s; returns the bytes consumed.
        let mut path = prefix.to_string();
        let mut i = 0;
        loop {
            let rest = &s[i..];
            let rest_trim = rest.trim_start();
            i += rest.len() - rest_trim.len();
            if let Some(group) = rest_trim.strip_prefix('{') {
                i += 1;
                let mut k = 0;
                loop {
                    let g = &group[k..];
                    let t = g.trim_start_matches(|c: char| c.is_whitespace() || c == ',');
                    k += g.len() - t.len();
                    if t.starts_with('}') || t.is_empty() {
                        return i + k + 1;
                    }
                    k += expand(&path, t, out);
                }
            }
            let id = ident(rest_trim);
            if id.is_empty() {
                break;
            }
            if !path.is_empty() {
                path.push_str("::");
            }
            path.push_str(id);
            i += id.len();
            match s[i..].strip_prefix("::") {
                Some(_) => i += 2,
                None => break,
            }
        }
        out.push(path);
        i
    }
    let mut out = Vec::new();
    for (i, _) in text.match_indices("crate::") {
        expand("", &text[i + "crate::".len()..], &mut out);
    }
    out
}

/// `config` is the RON schema and builds nothing: every engine name it uses is a settings type
/// in `CONFIG_MAY_NAME` (the resolvers of spectra, textures and indices live in `load/`).
#[test]
fn config_names_settings_and_builds_nothing() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/config");
    let mut files = Vec::new();
    rust_files(&dir, &mut files);
    let mut problems = Vec::new();
    for f in files {
        for p in crate_paths(&strip(&std::fs::read_to_string(&f).unwrap())) {
            // `crate::io::input_file::Kind::Scene` names the variant of an allowed enum.
            let allowed = CONFIG_MAY_NAME
                .iter()
                .any(|a| p == *a || p.starts_with(&format!("{a}::")));
            if !p.starts_with("config") && !allowed {
                problems.push(format!("{}: crate::{p}", f.display()));
            }
        }
    }
    assert!(
        problems.is_empty(),
        "config builds engine values:\n{}",
        problems.join("\n")
    );
}

/// The path reader: groups, nesting and a path that ends in a call.
#[test]
fn crate_paths_expand_groups() {
    let got = crate_paths("use crate::a::{B, c::{D, e::F}};\nlet x = crate::g::h(1);");
    assert_eq!(got, ["a::B", "a::c::D", "a::c::e::F", "g::h"]);
}
