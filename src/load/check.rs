//! The loader's two smallest checks, a leaf its builders share (they lived in `build.rs`,
//! which imports the builders: a circle between files).

use crate::error::InputError;
use std::path::Path;

pub(super) fn check(
    cond: bool,
    file: &Path,
    field: &str,
    message: impl Into<String>,
) -> Result<(), InputError> {
    if cond {
        Ok(())
    } else {
        // The message states the values allowed; the documentation says what the field does.
        Err(InputError::new(file, message).field(field).hint(format!(
            "scenes/README.md documents `{field}` and its range"
        )))
    }
}

pub(super) fn finite3(v: [f32; 3]) -> bool {
    v.iter().all(|x| x.is_finite())
}
