//! Reading a scene file: RON syntax errors come back with line and column.

use super::SceneConfig;
use crate::error::{Error, InputError};
use ron::extensions::Extensions;
use std::path::Path;

/// Parses scene text; `file` names it in errors.
pub fn parse_str(text: &str, file: &Path) -> Result<SceneConfig, InputError> {
    // IMPLICIT_SOME: optional fields are written without `Some(...)`.
    let opts = ron::Options::default().with_default_extension(Extensions::IMPLICIT_SOME);
    opts.from_str::<SceneConfig>(text).map_err(|e| {
        let hint = hint_for(&e.code);
        let mut err =
            InputError::new(file, e.code.to_string()).at(e.span.start.line, e.span.start.col);
        if let Some(h) = hint {
            err = err.hint(h);
        }
        err
    })
}

/// Reads and parses a scene file.
pub fn parse_file(path: &Path) -> Result<SceneConfig, Error> {
    let bytes = super::input_file::read(path, super::input_file::Kind::Scene)
        .map_err(|m| InputError::new(path, m))?;
    let text = String::from_utf8(bytes).map_err(|e| {
        InputError::new(path, format!("the scene file is not UTF-8 text: {e}"))
            .hint("save it as UTF-8")
    })?;
    Ok(parse_str(&text, path)?)
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
