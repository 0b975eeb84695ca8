//! The files of a folder that a dataset draws from (asset meshes and models, texture images):
//! one listing for every such folder, so each takes the same files in the same order.

use crate::error::InputError;
use std::path::{Path, PathBuf};

/// The regular files of `folder` whose extension is one of `extensions` (lower case, matched
/// without regard to case), as (file name, path), sorted by name: the file system's order is
/// not stable across machines, and the frames draw by index. `err` makes an error of the
/// caller's file and field from a message; `what` names the files in messages and hints
/// ("OBJ, PLY or glTF").
pub fn list_files(
    folder: &Path,
    extensions: &[&str],
    what: &str,
    err: impl Fn(String) -> InputError,
) -> Result<Vec<(String, PathBuf)>, InputError> {
    let hint = format!("give a folder of {what} files, relative to the dataset config");
    let entries = std::fs::read_dir(folder)
        .map_err(|e| err(format!("cannot list `{}`: {e}", folder.display())).hint(hint.clone()))?;
    let mut files = Vec::new();
    for e in entries {
        let e = e.map_err(|e| {
            err(format!("cannot list `{}`: {e}", folder.display())).hint(hint.clone())
        })?;
        let p = e.path();
        let ext = p
            .extension()
            .and_then(|x| x.to_str())
            .map(str::to_ascii_lowercase);
        if p.is_file() && ext.is_some_and(|x| extensions.contains(&x.as_str())) {
            let name = p
                .file_name()
                .expect("a listed file")
                .to_string_lossy()
                .into_owned();
            files.push((name, p));
        }
    }
    files.sort();
    if files.is_empty() {
        return Err(err(format!("`{}` holds no {what} file", folder.display())).hint(hint));
    }
    Ok(files)
}
