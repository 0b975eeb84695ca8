//! Reading a scene file: RON syntax errors come back with line and column.

use super::SceneConfig;
use crate::error::{Error, InputError};
use ron::extensions::Extensions;
use std::path::Path;

/// Parses scene text; `file` names it in errors.
/// A UTF-8 byte order mark (some Windows editors write one) is accepted and skipped.
pub fn parse_str(text: &str, file: &Path) -> Result<SceneConfig, InputError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    // IMPLICIT_SOME: optional fields are written without `Some(...)`.
    let opts = ron::Options::default().with_default_extension(Extensions::IMPLICIT_SOME);
    opts.from_str::<SceneConfig>(text).map_err(|e| {
        let (line, mut col) = (e.span.start.line, e.span.start.col);
        let (message, hint) = match explain(&e.code, text, line, &mut col) {
            Some((m, h)) => (m, Some(h)),
            None => (e.code.to_string(), hint_for(&e.code)),
        };
        let hint = hint.unwrap_or_else(|| {
            "scenes/README.md documents every field of a scene file".to_string()
        });
        InputError::new(file, message).at(line, col).hint(hint)
    })
}

/// Reads and parses a scene file.
pub fn parse_file(path: &Path) -> Result<SceneConfig, Error> {
    crate::io::inputs::record(path);
    let bytes =
        crate::io::input_file::read(path, crate::io::input_file::Kind::Scene).map_err(|m| {
            InputError::new(path, m).hint("give the path of a scene file (RON, or glTF 2.0)")
        })?;
    let text = utf8(bytes, path)?;
    Ok(parse_str(&text, path)?)
}

/// `bytes` as text, or an error giving the byte offset (and line) of the first invalid byte.
pub fn utf8(bytes: Vec<u8>, path: &Path) -> Result<String, InputError> {
    String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        let bytes = e.as_bytes();
        let line = 1 + bytes[..at].iter().filter(|&&b| b == b'\n').count();
        InputError::new(
            path,
            format!(
                "the file is not UTF-8 text: byte {at} (0x{:02X}, on line {line}) is not valid UTF-8",
                bytes[at]
            ),
        )
        .hint("save it as UTF-8 (plain text; any editor's \"UTF-8\" encoding)")
    })
}

/// Plainer words for the RON errors a user trips over most, with the fix.
/// `col` moves to the start of the value the message is about.
fn explain(
    code: &ron::Error,
    text: &str,
    line: usize,
    col: &mut usize,
) -> Option<(String, String)> {
    use ron::Error as E;
    match code {
        E::ExceededRecursionLimit => Some((
            "the scene is nested too deeply (more than 128 brackets inside each other)".into(),
            "materials such as Blend, Mask and Twosided nest, but not this deeply; check for \
             brackets that are opened and never closed"
                .into(),
        )),
        // `spp: 1.5`: the parser reads the integer 1 and then trips over `.5`.
        _ => {
            let (start, number) = number_at(text, line, *col)?;
            *col = start;
            Some((
                format!("expected an integer, got {number}"),
                "this value counts something (pixels, samples, depth): write a whole number, \
                 e.g. 2"
                    .into(),
            ))
        }
    }
}

/// The number around (line, col) if the error points into one at its fraction or exponent
/// (`1.5`, `2e3`), which means an integer field was given a fractional number; with the
/// number's first column.
fn number_at(text: &str, line: usize, col: usize) -> Option<(usize, String)> {
    let l: Vec<char> = text.lines().nth(line.checked_sub(1)?)?.chars().collect();
    let i = col.checked_sub(1)?;
    let (&c, &next) = (l.get(i)?, l.get(i + 1)?);
    if !(matches!(c, '.' | 'e' | 'E') && i > 0 && l[i - 1].is_ascii_digit()) {
        return None;
    }
    if !(next.is_ascii_digit() || (c != '.' && matches!(next, '+' | '-'))) {
        return None;
    }
    let num = |ch: char| ch.is_ascii_digit() || matches!(ch, '.' | 'e' | 'E' | '+' | '-' | '_');
    let start = (0..i).rev().take_while(|&k| num(l[k])).last()?;
    let end = (i..l.len()).find(|&k| !num(l[k])).unwrap_or(l.len());
    Some((start + 1, l[start..end].iter().collect()))
}

fn hint_for(code: &ron::Error) -> Option<String> {
    use ron::Error as E;
    match code {
        E::NoSuchStructField { .. } => {
            Some("check the spelling; scenes/README.md lists every field".into())
        }
        E::NoSuchEnumVariant { .. } => {
            Some("check the spelling; variant names are case-sensitive".into())
        }
        E::ExpectedFloat | E::ExpectedInteger => {
            Some("numbers are written plainly, e.g. 0.5 or 256".into())
        }
        _ => None,
    }
}
