//! The floors (docs/ARCHITECTURE.md): every top-level module of src/ sits on one floor and may
//! import (`crate::NAME`) only modules on its own floor or below; the modules form no circle.
//! `FLOORS` is the one list of the allowed order. The check reads text as
//! ../shared/tools/layers.py does: comments, a file's trailing `#[cfg(test)]` module and files
//! named `tests.rs` / `*_tests.rs` are left out (a test may build what its module cannot).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

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

/// Comments and the trailing test module removed, as layers.py does.
fn strip(text: &str) -> String {
    let mut t = text.to_string();
    if let Some(i) = t.find("#[cfg(test)]") {
        let rest = t[i + "#[cfg(test)]".len()..].trim_start();
        if rest.starts_with("mod ") && rest.contains('{') {
            let after_name =
                rest[4..].trim_start_matches(|c: char| c.is_alphanumeric() || c == '_');
            if after_name.trim_start().starts_with('{') {
                t.truncate(i);
            }
        }
    }
    while let Some(a) = t.find("/*") {
        match t[a..].find("*/") {
            Some(b) => t.replace_range(a..a + b + 2, ""),
            None => t.truncate(a),
        }
    }
    t.lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n")
}

fn ident(s: &str) -> &str {
    let end = s
        .find(|c: char| !(c.is_alphanumeric() || c == '_'))
        .unwrap_or(s.len());
    &s[..end]
}

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

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
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
}
