//! The output folder's bookkeeping: `dataset.json` (which dataset this folder holds) and
//! `manifest.jsonl` (one line per finished frame, appended after the frame's files are in
//! place), both guarded by a lock file so many processes (shards, Ray tasks) can share a folder.
//!
//! A frame is done when its manifest line is present and every file it lists has the listed
//! SHA-256; anything else (a kill between rename and append, a torn last line, a damaged file)
//! is rendered again. A file whose size and modification time are the ones its line records
//! is trusted without reading it, and a process reads any other file at most once (so a
//! resume's I/O does not grow with the frames listed times the processes); `--verify` reads
//! every listed file in full.
//!
//! This file holds the folder's types, its lock and the checksums of the frames' files;
//! `manifest/lines.rs` reads and appends the manifest's lines, `manifest/claim.rs` claims the
//! folder for a run and `manifest/diff.rs` names what changed in its `dataset.json`.

use crate::error::{Error, InputError};

mod claim;
mod diff;
mod lines;
pub use claim::Hold;
use diff::diff;
use fs4::fs_std::FileExt;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

pub const DATASET_JSON: &str = "dataset.json";
pub const MANIFEST: &str = "manifest.jsonl";
pub(crate) const LOCK: &str = ".prism-dataset.lock";

/// One finished frame, as a manifest line.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Entry {
    pub frame: u32,
    pub files: Vec<FileSum>,
    pub seconds: f64,
    pub invalid_samples: u64,
}

/// A file of a frame, relative to the output folder, with its checksum.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FileSum {
    pub path: String,
    pub sha256: String,
    pub bytes: u64,
    /// Modification time (ns since the Unix epoch) when it was listed: with `bytes`, what a
    /// resume trusts without reading the file. Absent in older manifests (then it is read).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mtime_ns: Option<u64>,
}

/// The output folder.
pub struct Out {
    pub root: PathBuf,
    /// Read every listed file in full (`--verify`) rather than trust sizes and mtimes.
    pub verify: bool,
    /// The dataset's frame count: a line of a frame at or past it is not a finished frame.
    pub frames: u32,
    /// The files this process has hashed: path → (size, mtime, SHA-256), reused while the
    /// size and mtime stay.
    hashed: std::sync::Mutex<BTreeMap<PathBuf, Hashed>>,
}

/// A file's size, mtime and SHA-256 when this process read it.
type Hashed = (u64, Option<u64>, String);

/// A file's modification time in ns since the Unix epoch.
fn mtime_ns(m: &std::fs::Metadata) -> Option<u64> {
    let t = m
        .modified()
        .ok()?
        .duration_since(std::time::UNIX_EPOCH)
        .ok()?;
    u64::try_from(t.as_nanos()).ok()
}

/// Held while the lock file is locked; dropping it closes the file, which releases the lock.
pub struct Lock(#[allow(dead_code)] std::fs::File);

impl Out {
    pub fn new(root: PathBuf, verify: bool) -> Out {
        Out {
            root,
            verify,
            frames: u32::MAX,
            hashed: Default::default(),
        }
    }

    /// SHA-256 and size of `p`, from this process's record while its size and mtime stay
    /// (`fresh`: read it anyway, for a file just written).
    fn hash(&self, p: &Path, fresh: bool) -> Result<(String, u64), String> {
        let stat = std::fs::metadata(p).ok().map(|m| (m.len(), mtime_ns(&m)));
        let mut seen = self.hashed.lock().unwrap_or_else(|e| e.into_inner());
        if let (false, Some((n, t)), Some((n0, t0, sha))) = (fresh, stat, seen.get(p)) {
            if (n, t) == (*n0, *t0) && t.is_some() {
                return Ok((sha.clone(), n));
            }
        }
        let (sha, n) = sha256(p)?;
        if let Some((_, t)) = stat {
            seen.insert(p.to_path_buf(), (n, t, sha.clone()));
        }
        Ok((sha, n))
    }

    /// Whether a listed file is there as listed: trusted on its size and mtime (a regular
    /// file, not a link), else (and always with `verify`) by its SHA-256.
    fn file_intact(&self, f: &FileSum) -> bool {
        let p = self.root.join(&f.path);
        if !self.verify && f.mtime_ns.is_some() {
            let m = std::fs::symlink_metadata(&p);
            if m.as_ref()
                .is_ok_and(|m| m.is_file() && m.len() == f.bytes && mtime_ns(m) == f.mtime_ns)
            {
                return true;
            }
        }
        self.hash(&p, false)
            .is_ok_and(|(s, n)| s == f.sha256 && n == f.bytes)
    }

    pub fn frames_dir(&self) -> PathBuf {
        self.root.join("frames")
    }

    /// The path stem of frame `i`: `OUT/frames/000017`.
    pub fn stem(&self, i: u32) -> PathBuf {
        self.frames_dir().join(format!("{i:06}"))
    }

    pub fn lock(&self) -> Result<Lock, Error> {
        let p = self.root.join(LOCK);
        // Opening a FIFO for writing would wait for a reader: look before opening.
        if std::fs::symlink_metadata(&p).is_ok_and(|m| !m.is_file()) {
            return Err(folder_error(
                &p,
                "the lock file is not a regular file".into(),
            ));
        }
        let f = std::fs::OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&p)
            .map_err(|e| folder_error(&p, format!("cannot open the lock file: {e}")))?;
        FileExt::lock_exclusive(&f).map_err(|e| folder_error(&p, format!("cannot lock: {e}")))?;
        Ok(Lock(f))
    }

    /// The manifest entry of a frame whose files were just written.
    pub fn entry(
        &self,
        frame: u32,
        files: &[PathBuf],
        seconds: f64,
        invalid_samples: u64,
    ) -> Result<Entry, Error> {
        let mut sums = Vec::new();
        for f in files {
            let (sha, bytes) = self.hash(f, true).map_err(|e| {
                InputError::new(f, e)
                    .hint("the frame's file was replaced or removed while it was listed; run again")
            })?;
            let rel = f.strip_prefix(&self.root).unwrap_or(f);
            let mtime = std::fs::metadata(f).ok().and_then(|m| mtime_ns(&m));
            sums.push(FileSum {
                path: rel.to_string_lossy().replace('\\', "/"),
                sha256: sha,
                bytes,
                mtime_ns: mtime,
            });
        }
        Ok(Entry {
            frame,
            files: sums,
            seconds: (seconds * 1000.0).round() / 1000.0,
            invalid_samples,
        })
    }
}

/// An unusable output folder (or a file in it): the user's to fix, exit 2.
fn folder_error(path: &Path, message: String) -> Error {
    InputError::new(path, message)
        .field("-o")
        .hint("give a new or empty folder prism can write (prism makes frames/, manifest.jsonl, dataset.json and a lock file in it)")
        .into()
}

/// SHA-256 (hex) and size of a file: a regular file within the input-file limit, streamed
/// (config/input_file.rs); the error names the file and what it is.
pub fn sha256(path: &Path) -> Result<(String, u64), String> {
    use crate::io::input_file::{self, Kind};
    input_file::sha256(path, Kind::Asset)
}

pub fn hex(b: &[u8]) -> String {
    b.iter().map(|x| format!("{x:02x}")).collect()
}
