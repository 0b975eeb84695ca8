//! Claiming the output folder for a run: a new or empty folder gets the dataset's identity,
//! one holding the same dataset is resumed, one holding another dataset (or a user's files) is
//! refused, unless `--force`, which starts the dataset over there. A run holds the folder (a
//! shared lock on the folder itself) from its claim to its end, and `--force` takes the folder
//! exclusively to start over: while another run of any config is writing into it, `--force` is
//! refused, so that run's frames cannot end up listed under the new dataset (issue 27 item 7).
//! Every refusal comes before anything is made in the folder.

use super::{diff, folder_error, Out, DATASET_JSON, LOCK, MANIFEST};
use crate::error::{Error, InputError};
use fs4::fs_std::FileExt;
use serde_json::Value;
use std::path::Path;

/// The folder held by a run (a shared lock on it; dropping it releases the lock).
pub struct Hold(#[allow(dead_code)] std::fs::File);

/// What the folder holds, against the dataset's identity.
enum Found {
    /// The same dataset: resume.
    Same,
    /// Nothing (a new or empty folder): claim it.
    Nothing,
    /// Another dataset or a user's files: the refusal, unless `--force`.
    Other(Error),
}

impl Out {
    /// Makes the folder hold `identity` (`{prism_version, config, scene, hash}`), as above;
    /// returns the hold the run keeps until it ends.
    pub fn prepare(
        &self,
        identity: &Value,
        force: bool,
        config_file: &Path,
    ) -> Result<Hold, Error> {
        if std::fs::symlink_metadata(&self.root).is_ok_and(|m| !m.is_dir()) {
            return Err(folder_error(
                &self.root,
                "the output folder is not a directory".into(),
            ));
        }
        for (name, dir) in [(MANIFEST, false), ("frames", true), (DATASET_JSON, false)] {
            let p = self.root.join(name);
            if std::fs::symlink_metadata(&p)
                .is_ok_and(|m| m.is_dir() != dir || m.file_type().is_symlink())
            {
                let what = if dir { "a directory" } else { "a regular file" };
                return Err(folder_error(
                    &p,
                    format!("`{name}` in the output folder is not {what}"),
                ));
            }
        }
        self.outputs_are_files()?;
        // Refused before the folder or its lock file is made: a refusal leaves it as it was.
        let first = self.found(identity, config_file)?;
        let overwrite = match first {
            Found::Other(e) if !force => return Err(e),
            Found::Other(_) => true,
            _ => false,
        };
        std::fs::create_dir_all(&self.root).map_err(|e| {
            folder_error(&self.root, format!("cannot create the output folder: {e}"))
        })?;
        let hold = std::fs::File::open(&self.root)
            .map_err(|e| folder_error(&self.root, format!("cannot open the output folder: {e}")))?;
        let busy = || -> Error {
            InputError::new(
                &self.root,
                "another `prism dataset` run is writing into this folder: starting over under it would list its frames under this dataset",
            )
            .field("--force")
            .hint("wait for that run to end (or stop it), then run again with --force; or give a new -o folder")
            .into()
        };
        if overwrite {
            if !FileExt::try_lock_exclusive(&hold).unwrap_or(false) {
                return Err(busy());
            }
        } else {
            FileExt::lock_shared(&hold).map_err(|e| {
                folder_error(&self.root, format!("cannot lock the output folder: {e}"))
            })?;
        }
        let _lock = self.lock()?;
        match self.found(identity, config_file)? {
            Found::Same => self.compact()?,
            Found::Other(e) if !force => return Err(e),
            // Another run claimed or changed the folder since the first look.
            Found::Other(_) if !overwrite => return Err(busy()),
            _ => {
                let path = self.root.join(DATASET_JSON);
                let text =
                    serde_json::to_string_pretty(identity).expect("JSON values serialise") + "\n";
                crate::output::write_atomic(&path, |tmp| {
                    std::fs::write(tmp, &text).map_err(|e| e.to_string())
                })?;
                let m = self.root.join(MANIFEST);
                crate::output::write_atomic(&m, |tmp| {
                    std::fs::write(tmp, "").map_err(|e| e.to_string())
                })?;
            }
        }
        if overwrite {
            // Started over: from here on a run like any other.
            FileExt::lock_shared(&hold).map_err(|e| {
                folder_error(&self.root, format!("cannot lock the output folder: {e}"))
            })?;
        }
        Ok(Hold(hold))
    }

    /// What the folder holds (read only: nothing is made).
    /// Every path a run writes (a frame's `NNNNNN.exr|json|png|ron` in frames/, the contact
    /// sheet) is absent or a regular file. A directory, FIFO, device or link there is not
    /// prism's to replace, and writing a frame onto it fails only after rendering (exit 1, the
    /// long fuzz run of seed 20261204, cases 4738 and 6743): refused up front, with `--force`
    /// too, since starting over does not remove what is not prism's.
    fn outputs_are_files(&self) -> Result<(), Error> {
        let is_output = |name: &str| {
            name.split_once('.').is_some_and(|(stem, ext)| {
                stem.len() >= 6
                    && stem.bytes().all(|b| b.is_ascii_digit())
                    && matches!(ext, "exr" | "json" | "png" | "ron")
            })
        };
        let frames = std::fs::read_dir(self.frames_dir()).into_iter().flatten();
        let mut paths: Vec<_> = frames
            .flatten()
            .filter(|e| e.file_name().to_str().is_some_and(is_output))
            .map(|e| e.path())
            .collect();
        paths.sort();
        paths.push(self.root.join("contact_sheet.png"));
        for p in paths {
            if std::fs::symlink_metadata(&p).is_ok_and(|m| !m.is_file()) {
                let rel = p
                    .strip_prefix(&self.root)
                    .unwrap_or(&p)
                    .display()
                    .to_string();
                return Err(folder_error(
                    &p,
                    format!("`{rel}` in the output folder is not a regular file, and a run writes it: prism replaces only its own files"),
                ));
            }
        }
        Ok(())
    }

    fn found(&self, identity: &Value, config_file: &Path) -> Result<Found, Error> {
        let path = self.root.join(DATASET_JSON);
        if path.is_file() {
            let old: Value = std::fs::read_to_string(&path)
                .ok()
                .and_then(|t| serde_json::from_str(&t).ok())
                .unwrap_or(Value::Null);
            if old.get("hash") == identity.get("hash")
                && old.get("prism_version") == identity.get("prism_version")
            {
                return Ok(Found::Same);
            }
            let hint =
                "choose a new output folder, or pass --force to start this dataset over in it";
            if !old.is_object() {
                return Ok(Found::Other(
                    InputError::new(
                        config_file,
                        format!(
                            "the output folder `{}` has a {DATASET_JSON} that is not prism's (it does not parse as one)",
                            self.root.display()
                        ),
                    )
                    .field("-o")
                    .hint(hint)
                    .into(),
                ));
            }
            let mut changes = Vec::new();
            diff(&old, identity, "", &mut changes);
            let more = changes.len().saturating_sub(6);
            changes.truncate(6);
            let mut msg = format!(
                "the output folder `{}` holds another dataset; changed: {}",
                self.root.display(),
                changes.join("; ")
            );
            if more > 0 {
                msg += &format!(" (and {more} more)");
            }
            return Ok(Found::Other(
                InputError::new(config_file, msg)
                    .field("-o")
                    .hint(hint)
                    .into(),
            ));
        }
        if std::fs::symlink_metadata(&self.root).is_err() {
            return Ok(Found::Nothing);
        }
        let foreign: Vec<String> = std::fs::read_dir(&self.root)
            .map_err(|e| folder_error(&self.root, format!("cannot read the output folder: {e}")))?
            .filter_map(|e| e.ok())
            .map(|e| e.file_name().to_string_lossy().into_owned())
            // The lock, and temporary files of a run killed while claiming the folder.
            .filter(|n| n != LOCK && !(n.starts_with('.') && n.contains(".tmp.")))
            .collect();
        if foreign.is_empty() {
            return Ok(Found::Nothing);
        }
        Ok(Found::Other(
            InputError::new(
                config_file,
                format!(
                    "the output folder `{}` is not empty and holds no {DATASET_JSON} (it has {})",
                    self.root.display(),
                    foreign.join(", ")
                ),
            )
            .field("-o")
            .hint("give a new or empty folder: prism never writes over files it did not make")
            .into(),
        ))
    }
}
