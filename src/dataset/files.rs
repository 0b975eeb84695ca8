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

#[cfg(test)]
mod tests {
    use super::*;

    /// Only the named extensions (any case), sorted by name; an empty or missing folder is an
    /// error that names it.
    #[test]
    fn lists_matching_files_sorted() {
        let dir = std::env::temp_dir().join(format!("prism-list-files-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("sub.obj")).unwrap();
        for n in ["b.OBJ", "a.ply", "c.txt", "d.gltf"] {
            std::fs::write(dir.join(n), "x").unwrap();
        }
        let err = |m: String| InputError::new(Path::new("d.ron"), m);
        let got = list_files(&dir, &["obj", "ply"], "OBJ or PLY", err).unwrap();
        let names: Vec<&str> = got.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["a.ply", "b.OBJ"]);
        let none = list_files(&dir, &["exr"], "EXR", err).unwrap_err();
        assert!(none.message.contains("holds no EXR file"), "{none}");
        assert!(none.hint.is_some());
        let gone = list_files(&dir.join("gone"), &["exr"], "EXR", err).unwrap_err();
        assert!(gone.message.contains("cannot list"), "{gone}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
