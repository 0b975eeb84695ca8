//! Writing results: multi-channel OpenEXR and PNG previews, always atomically (a temporary
//! file in the same directory, then a rename), so an interrupted run never leaves a truncated
//! image behind and never replaces a good one with a broken one.

pub mod exr;
pub mod png;
pub mod sidecar;

use crate::error::Error;
use std::path::{Path, PathBuf};

/// Writes `path` by calling `write` on a temporary sibling file, then renaming it into place.
pub fn write_atomic(
    path: &Path,
    write: impl FnOnce(&Path) -> Result<(), String>,
) -> Result<(), Error> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    if !dir.is_dir() {
        std::fs::create_dir_all(&dir).map_err(|e| Error::io(&dir, e))?;
    }
    let name = path
        .file_name()
        .ok_or_else(|| Error::Other(format!("`{}` is not a file path", path.display())))?;
    // Keep the extension last: some writers pick the format from it.
    let tmp = dir.join(format!(
        ".{}.{}.tmp.{}",
        name.to_string_lossy(),
        std::process::id(),
        ext_of(path)
    ));
    if let Err(message) = write(&tmp) {
        let _ = std::fs::remove_file(&tmp);
        return Err(Error::Other(format!(
            "writing {}: {message}",
            path.display()
        )));
    }
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        Error::io(path, e)
    })
}

fn ext_of(path: &Path) -> String {
    path.extension()
        .map(|e| e.to_string_lossy().into_owned())
        .unwrap_or_default()
}
