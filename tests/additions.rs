//! What a new BSDF, emitter, AOV, sensor stage and dataset variation touch, counted from the
//! code (docs/ARCHITECTURE.md, "What an addition touches"): for an existing example of each
//! kind, the files under src/ whose code (comments and test modules left out) names it. Each
//! budget is the count at the time it was written down, so a change that spreads a kind over
//! more files fails here and has to say why there.

mod source;

use source::{ident, rust_files, strip};
use std::path::PathBuf;

struct Kind {
    addition: &'static str,
    example: &'static str,
    /// The example's names in code: its types, variants, module and field paths.
    tokens: &'static [&'static str],
    budget: usize,
    /// Folders the kind must not reach (a sensor stage stays out of the integrator).
    never_in: &'static [&'static str],
}

const KINDS: &[Kind] = &[
    Kind {
        addition: "BSDF",
        example: "RoughPlastic",
        tokens: &["RoughPlastic", "RoughPlasticParams", "roughplastic"],
        // 3: own file, the list in bsdf/mod.rs (the `Lobe`, `Material` and `MaterialConfig`
        // enums, their dispatch and the config's field roles are generated from it; see
        // docs/ARCHITECTURE.md) and the loader (load/materials.rs).
        budget: 3,
        never_in: &["src/integrator", "src/dataset", "src/export.rs"],
    },
    Kind {
        addition: "emitter",
        example: "Spot",
        tokens: &["Spot"],
        // 7: six under src/ and python/src/params.rs (which field holds each emitter's power),
        // counted since the count reads python/src/ too.
        budget: 7,
        never_in: &["src/integrator"],
    },
    Kind {
        addition: "AOV",
        example: "normal",
        tokens: &["Aov::Normal"],
        budget: 2,
        never_in: &[],
    },
    Kind {
        addition: "sensor stage",
        example: "raw read-out",
        tokens: &["RawModel", "RawConfig", "RawSetup", "raw::", "sensor.raw"],
        // 7: several sensors per render (sensor/multi.rs) develop each extra sensor's mosaic.
        budget: 7,
        never_in: &["src/integrator"],
    },
    Kind {
        addition: "dataset variation",
        example: "envmap",
        tokens: &["EnvmapVariation", "Stream::Envmap", ".envmap"],
        budget: 5,
        never_in: &["src/integrator", "src/load", "src/config"],
    },
];

/// True if `text` names `token` with no identifier character joined to either end.
fn names(text: &str, token: &str) -> bool {
    let joined = |c: Option<char>| c.is_some_and(|c| c.is_alphanumeric() || c == '_');
    text.match_indices(token).any(|(i, _)| {
        let before = text[..i].chars().next_back();
        let after = text[i + token.len()..].chars().next();
        let starts_ident = !ident(token).is_empty();
        let ends_ident = token.ends_with(|c: char| c.is_alphanumeric() || c == '_');
        !(starts_ident && joined(before) || ends_ident && joined(after))
    })
}

/// The files under src/ and python/src/ (the Python module; relative paths, sorted) whose code
/// names one of `tokens`.
/// `PRISM_COUNT_ROOT` counts another checkout (to measure a commit before a change).
fn touched(tokens: &[&str]) -> Vec<String> {
    let root = std::env::var_os("PRISM_COUNT_ROOT")
        .map_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")), PathBuf::from);
    let root = root.as_path();
    let mut files = Vec::new();
    rust_files(&root.join("src"), &mut files);
    rust_files(&root.join("python/src"), &mut files);
    let mut out: Vec<String> = files
        .iter()
        .filter(|f| {
            let name = f.file_name().unwrap().to_string_lossy();
            !(name == "tests.rs" || name.ends_with("_tests.rs"))
        })
        .filter(|f| {
            let text = strip(&std::fs::read_to_string(f).unwrap());
            tokens.iter().any(|t| names(&text, t))
        })
        .map(|f| f.strip_prefix(root).unwrap().display().to_string())
        .collect();
    out.sort();
    out
}

/// Prints each kind's files (`-- --nocapture`) and holds each to its budget.
#[test]
fn each_addition_stays_within_its_files() {
    let mut problems = Vec::new();
    for k in KINDS {
        let files = touched(k.tokens);
        println!(
            "{} ({}): {} files: {}",
            k.addition,
            k.example,
            files.len(),
            files.join(", ")
        );
        // Fewer than two: the example was renamed and the count measures nothing.
        if files.len() < 2 || files.len() > k.budget {
            problems.push(format!(
                "{} ({}): {} files, budget {}: {}",
                k.addition,
                k.example,
                files.len(),
                k.budget,
                files.join(", ")
            ));
        }
        for f in &files {
            if let Some(dir) = k.never_in.iter().find(|d| f.starts_with(*d)) {
                problems.push(format!("{} ({}) reaches {dir}: {f}", k.addition, k.example));
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// The token reader: whole names only, paths and field accesses as written.
#[test]
fn names_match_whole_identifiers() {
    assert!(names("Lobe::RoughPlastic(b)", "RoughPlastic"));
    assert!(!names("RoughPlasticTable", "RoughPlastic"));
    assert!(!names("SpotLight", "Spot"));
    assert!(names("use crate::sensor::raw::Gain;", "raw::"));
    assert!(!names("draw::x", "raw::"));
    assert!(names("self.sensor.raw {", "sensor.raw"));
    assert!(!names("self.sensor.raw_x", "sensor.raw"));
}
