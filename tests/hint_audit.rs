//! Hint audit (issue 27 item 7): every exit-2 message should name the fix. This lists each
//! `InputError::new(` in src/ whose statement (up to the `;` that ends it) adds no `.hint(`,
//! and fails if there is any, so a new message without a hint is caught (the count reached
//! 0 on 2026-12-03, issue 27 item 7: helpers that build errors for many callers carry a
//! pointer to the field's documentation, which a caller's own hint replaces). Messages built
//! by helpers that add the hint at their callers count as hintless here (a false alarm on the
//! safe side); messages built without `InputError::new` are not seen.

use std::path::{Path, PathBuf};

fn rust_files(d: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(d).unwrap().flatten() {
        let p = e.path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// Where the statement starting `rest` ends: its first `;` outside a string literal (messages
/// often hold a `;`).
fn statement_end(rest: &str) -> usize {
    let (mut in_str, mut escaped) = (false, false);
    for (i, c) in rest.char_indices() {
        match c {
            _ if escaped => escaped = false,
            '\\' if in_str => escaped = true,
            '"' => in_str = !in_str,
            ';' if !in_str => return i,
            _ => {}
        }
    }
    rest.len()
}

/// (file:line, first line) of each hintless constructor, tests modules left out.
fn hintless() -> Vec<(String, String)> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    files.sort();
    let mut found = Vec::new();
    for f in files {
        let text = std::fs::read_to_string(&f).unwrap();
        // Up to the tests module: a `#[cfg(test)]` on a statement (a counter in `gltf::open`)
        // once hid the rest of its file from the audit.
        let text = match text.find("#[cfg(test)]\nmod ") {
            Some(i) => &text[..i],
            None => &text[..],
        };
        for (i, _) in text.match_indices("InputError::new(") {
            let rest = &text[i..];
            let end = statement_end(rest);
            if !rest[..end].contains(".hint(") {
                let line = text[..i].matches('\n').count() + 1;
                let first = rest.lines().next().unwrap_or("").trim().to_string();
                let name = f.strip_prefix(&src).unwrap().display().to_string();
                found.push((format!("src/{name}:{line}"), first));
            }
        }
    }
    found
}

#[test]
fn every_exit_2_message_has_a_hint() {
    let found = hintless();
    for (at, first) in &found {
        eprintln!("{at}: {first}");
    }
    assert!(
        found.is_empty(),
        "{} `InputError::new` statements without a `.hint(`: give each a hint naming the fix",
        found.len()
    );
}

/// The audit can fail: a constructor without a hint is seen, one with a hint is not.
#[test]
fn the_audit_sees_a_missing_hint() {
    let text = "fn a() { InputError::new(p, \"x\").field(\"f\"); }\n\
                fn b() { InputError::new(p, \"y\").field(\"f\").hint(\"fix\"); }\n";
    let hits: Vec<usize> = text
        .match_indices("InputError::new(")
        .filter(|(i, _)| {
            let rest = &text[*i..];
            !rest[..rest.find(';').unwrap()].contains(".hint(")
        })
        .map(|(i, _)| i)
        .collect();
    assert_eq!(hits, vec![9]);
}
