//! The contents of the files a dataset reads besides its two configs (meshes, textures,
//! spectra, envmaps, sensor files): their SHA-256 goes into `dataset.json`, so that a resume
//! after an asset changed is refused naming the file, as a changed config is, instead of
//! mixing frames of the old and the new asset.

use super::base::Base;
use crate::error::Error;
use crate::io::paths::{normal, relative};
use std::collections::BTreeMap;
use std::path::Path;

/// `{path: sha256}` of `base.inputs`, each path relative to the dataset config's folder (so the
/// key does not depend on the directory prism runs in).
pub fn hashes(base: &Base) -> Result<BTreeMap<String, String>, Error> {
    let dir = normal(base.file.parent().unwrap_or(Path::new(".")));
    let mut out = BTreeMap::new();
    for p in &base.inputs {
        let key = relative(&normal(p), &dir);
        if let std::collections::btree_map::Entry::Vacant(e) = out.entry(key) {
            let (sha, _) = super::manifest::sha256(p).map_err(|err| {
                crate::error::InputError::new(&base.file, err).hint(
                    "every file a dataset reads must be a regular file (not a FIFO or device)",
                )
            })?;
            e.insert(sha);
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_are_relative_to_the_config_folder_whatever_their_spelling() {
        let dir = normal(Path::new("/data/configs/datasets"));
        let cases = [
            (
                "/data/configs/datasets/scenes/../../../scenes/sky.exr",
                "../../scenes/sky.exr",
            ),
            ("/data/configs/datasets/./tex/a.png", "tex/a.png"),
            ("/data/configs/sensors/x.ron", "../sensors/x.ron"),
            ("/other/m.obj", "../../../other/m.obj"),
        ];
        for (p, want) in cases {
            assert_eq!(relative(&normal(Path::new(p)), &dir), want, "{p}");
        }
        // A bare config name's folder is the current one, not "" (which made every key an
        // absolute path, so a resume from elsewhere saw another dataset).
        let here = std::env::current_dir().unwrap();
        assert_eq!(normal(Path::new("a.ron").parent().unwrap()), normal(&here));
    }
}
