//! Writing results: multi-channel OpenEXR and PNG previews, always atomically (a temporary
//! file in the same directory, then a rename), so an interrupted run never leaves a truncated
//! image behind and never replaces a good one with a broken one.

pub mod exr;
pub mod exr_header;
mod exr_zip;
pub mod guard;
pub mod interrupt;
pub mod png;
pub mod sidecar;

use crate::error::{Error, InputError};
use std::path::Path;

/// Writes `path` by calling `write` on a temporary sibling file, then renaming it into place.
/// The temporary is removed on failure, and on SIGINT/SIGTERM once `interrupt::install` ran.
/// Failures are the user's to fix (a full disk, a directory made read-only meanwhile): exit 2.
pub fn write_atomic(
    path: &Path,
    write: impl FnOnce(&Path) -> Result<(), String>,
) -> Result<(), Error> {
    let err = |m: String| -> Error {
        InputError::new(path, format!("cannot write the output: {m}"))
            .hint("check that its directory is writable and the disk has space")
            .into()
    };
    let dir = guard::dir_of(path);
    if !dir.is_dir() {
        std::fs::create_dir_all(&dir).map_err(|e| err(format!("`{}`: {e}", dir.display())))?;
    }
    let tmp = guard::temp_path(path).ok_or_else(|| err("it is not a file path".into()))?;
    let tmp = interrupt::Temp::create(&tmp).map_err(|e| err(e.to_string()))?;
    write(tmp.path()).map_err(err)?;
    tmp.rename(path).map_err(|e| err(e.to_string()))
}

/// The rule for every render: an output holding NaN or ±inf (bar `distance`/`depth`'s +inf
/// background) is not written; the run fails with exit 2 naming the scene and the channel.
/// Every sample is already checked, so such a value comes from a factor past f32's range.
pub fn check_finite(film: &crate::film::Film, scene: &Path) -> Result<(), Error> {
    let Some((channel, x, y, v, n)) = film.first_nonfinite() else {
        return Ok(());
    };
    Err(InputError::new(
        scene,
        format!("the render holds non-finite values in {n} pixels (first: {v} in channel {channel} at pixel ({x}, {y})); nothing was written"),
    )
    .hint("a factor of the scene or sensor exceeds single precision: lower the emitter strengths, the sensor's exposure (iso · shutter / f_number²) or its gain")
    .into())
}
