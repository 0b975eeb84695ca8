//! Reading prism's own sources as text, shared by `layers.rs` and `additions.rs`: comments, a
//! file's trailing `#[cfg(test)]` module and files named `tests.rs` / `*_tests.rs` are left out
//! (as ../shared/tools/layers.py reads them).

use std::path::{Path, PathBuf};

/// Comments and the trailing test module removed, as layers.py does.
pub fn strip(text: &str) -> String {
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
    code(&t)
}

/// `text` without its comments, read as Rust's lexer reads it: `//` or `/*` inside a string is
/// text, block comments nest, and `'a` is a lifetime, not a character literal.
fn code(text: &str) -> String {
    let b = text.as_bytes();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    let mut keep = 0; // start of the code not yet copied
    while i < b.len() {
        match b[i] {
            b'/' if b.get(i + 1) == Some(&b'/') => {
                out.push_str(&text[keep..i]);
                i = text[i..].find('\n').map_or(b.len(), |n| i + n);
                keep = i;
            }
            b'/' if b.get(i + 1) == Some(&b'*') => {
                out.push_str(&text[keep..i]);
                let mut depth = 0;
                while i < b.len() {
                    if b[i..].starts_with(b"/*") {
                        depth += 1;
                        i += 2;
                    } else if b[i..].starts_with(b"*/") {
                        depth -= 1;
                        i += 2;
                        if depth == 0 {
                            break;
                        }
                    } else {
                        i += 1;
                    }
                }
                out.push(' ');
                keep = i;
            }
            b'"' => {
                // A raw string r"…" / r#"…"# ends at the quote followed by its hashes.
                let hashes = text[..i].bytes().rev().take_while(|&c| c == b'#').count();
                let raw = i > hashes && b[i - hashes - 1] == b'r';
                i += 1;
                while i < b.len() {
                    if !raw && b[i] == b'\\' {
                        i += 2;
                    } else if b[i] == b'"' && b[i + 1..].iter().take(hashes).all(|&c| c == b'#') {
                        i += 1 + if raw { hashes } else { 0 };
                        break;
                    } else {
                        i += 1;
                    }
                }
            }
            b'\'' if b.get(i + 2) == Some(&b'\'') || b.get(i + 1) == Some(&b'\\') => {
                // A character literal ('x', '\n', '\''); a lifetime has no closing quote.
                i += if b[i + 1] == b'\\' { 3 } else { 2 };
                while i < b.len() && b[i] != b'\'' {
                    i += 1;
                }
                i += 1;
            }
            _ => i += 1,
        }
    }
    out.push_str(&text[keep.min(b.len())..]);
    out
}

pub fn ident(s: &str) -> &str {
    let end = s
        .find(|c: char| !(c.is_alphanumeric() || c == '_'))
        .unwrap_or(s.len());
    &s[..end]
}

pub fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}
