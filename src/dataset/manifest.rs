//! The output folder's bookkeeping: `dataset.json` (which dataset this folder holds) and
//! `manifest.jsonl` (one line per finished frame, appended after the frame's files are in
//! place), both guarded by a lock file so many processes (shards, Ray tasks) can share a folder.
//!
//! A frame is done when its manifest line is present and every file it lists has the listed
//! SHA-256; anything else (a kill between rename and append, a torn last line, a damaged file)
//! is rendered again.

use crate::error::{Error, InputError};
use fs4::fs_std::FileExt;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use sha2::{Digest, Sha256};
use std::collections::BTreeMap;
use std::io::{BufRead, Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

pub const DATASET_JSON: &str = "dataset.json";
pub const MANIFEST: &str = "manifest.jsonl";
const LOCK: &str = ".prism-dataset.lock";

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
}

/// The output folder.
pub struct Out {
    pub root: PathBuf,
}

/// Held while the lock file is locked; dropping it closes the file, which releases the lock.
pub struct Lock(#[allow(dead_code)] std::fs::File);

impl Out {
    pub fn frames_dir(&self) -> PathBuf {
        self.root.join("frames")
    }

    /// The path stem of frame `i`: `OUT/frames/000017`.
    pub fn stem(&self, i: u32) -> PathBuf {
        self.frames_dir().join(format!("{i:06}"))
    }

    pub fn lock(&self) -> Result<Lock, Error> {
        let p = self.root.join(LOCK);
        let f = std::fs::OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&p)
            .map_err(|e| Error::io(&p, e))?;
        FileExt::lock_exclusive(&f).map_err(|e| Error::io(&p, e))?;
        Ok(Lock(f))
    }

    /// Makes the folder hold `identity` (`{prism_version, config, scene, hash}`): a new or empty
    /// folder gets it; one holding the same dataset is resumed; one holding another dataset is
    /// refused naming what changed, unless `force`, which starts the dataset over there.
    pub fn prepare(&self, identity: &Value, force: bool, config_file: &Path) -> Result<(), Error> {
        std::fs::create_dir_all(&self.root).map_err(|e| Error::io(&self.root, e))?;
        let _lock = self.lock()?;
        let path = self.root.join(DATASET_JSON);
        let text = serde_json::to_string_pretty(identity).expect("JSON values serialise") + "\n";
        if path.is_file() {
            let old: Value = std::fs::read_to_string(&path)
                .ok()
                .and_then(|t| serde_json::from_str(&t).ok())
                .unwrap_or(Value::Null);
            if old.get("hash") == identity.get("hash")
                && old.get("prism_version") == identity.get("prism_version")
            {
                return self.compact();
            }
            if !force {
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
                return Err(InputError::new(config_file, msg)
                    .field("-o")
                    .hint("choose a new output folder, or pass --force to start this dataset over in it")
                    .into());
            }
        } else {
            let foreign: Vec<String> = std::fs::read_dir(&self.root)
                .map_err(|e| Error::io(&self.root, e))?
                .filter_map(|e| e.ok())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                // The lock, and temporary files of a run killed while claiming the folder.
                .filter(|n| n != LOCK && !(n.starts_with('.') && n.contains(".tmp.")))
                .collect();
            if !foreign.is_empty() && !force {
                return Err(InputError::new(
                    config_file,
                    format!(
                        "the output folder `{}` is not empty and holds no {DATASET_JSON} (it has {})",
                        self.root.display(),
                        foreign.join(", ")
                    ),
                )
                .field("-o")
                .hint("give a new or empty folder: prism never writes over files it did not make")
                .into());
            }
        }
        crate::output::write_atomic(&path, |tmp| {
            std::fs::write(tmp, &text).map_err(|e| e.to_string())
        })?;
        let m = self.root.join(MANIFEST);
        crate::output::write_atomic(&m, |tmp| std::fs::write(tmp, "").map_err(|e| e.to_string()))
    }

    /// Every manifest line that parses, in order, whether or not its files are intact.
    fn lines(&self) -> Result<Vec<Entry>, Error> {
        let p = self.root.join(MANIFEST);
        let text = match std::fs::read_to_string(&p) {
            Ok(t) => t,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => String::new(),
            Err(e) => return Err(Error::io(&p, e)),
        };
        Ok(text
            .lines()
            .filter_map(|l| serde_json::from_str::<Entry>(l).ok())
            .collect())
    }

    /// Whether the manifest lists `frame` with intact files. Read a line at a time, parsing
    /// only each line's frame number: holding the whole manifest once per frame made a run's
    /// peak memory grow with its length (1,000 frames: +4 MiB over 10).
    fn listed_intact(&self, frame: u32) -> Result<bool, Error> {
        #[derive(Deserialize)]
        struct FrameOnly {
            frame: u32,
        }
        let p = self.root.join(MANIFEST);
        let f = match std::fs::File::open(&p) {
            Ok(f) => f,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(false),
            Err(e) => return Err(Error::io(&p, e)),
        };
        let mut r = std::io::BufReader::new(f);
        let mut line = Vec::new();
        loop {
            line.clear();
            if r.read_until(b'\n', &mut line)
                .map_err(|e| Error::io(&p, e))?
                == 0
            {
                return Ok(false);
            }
            // A torn line is skipped, as `lines` skips what does not parse.
            let listed = serde_json::from_slice::<FrameOnly>(&line).is_ok_and(|x| x.frame == frame);
            if listed {
                if let Ok(x) = serde_json::from_slice::<Entry>(&line) {
                    if self.intact(&x) {
                        return Ok(true);
                    }
                }
            }
        }
    }

    /// Whether every file of `e` is there with its checksum.
    pub fn intact(&self, e: &Entry) -> bool {
        e.files.iter().all(|f| {
            sha256(&self.root.join(&f.path)).is_ok_and(|(s, n)| s == f.sha256 && n == f.bytes)
        })
    }

    /// The finished frames: listed, with intact files (the first such line per frame).
    pub fn done(&self) -> Result<BTreeMap<u32, Entry>, Error> {
        let mut done = BTreeMap::new();
        for e in self.lines()? {
            if !done.contains_key(&e.frame) && self.intact(&e) {
                done.insert(e.frame, e);
            }
        }
        Ok(done)
    }

    /// The frames the manifest lists (by any process: every shard's), whose files are not read.
    pub fn listed(&self) -> Result<std::collections::BTreeSet<u32>, Error> {
        Ok(self.lines()?.iter().map(|e| e.frame).collect())
    }

    /// Rewrites the manifest with only its intact, first-per-frame lines, if it has others
    /// (a torn last line after a crash, a frame whose files were damaged). Call under the lock.
    fn compact(&self) -> Result<(), Error> {
        let p = self.root.join(MANIFEST);
        let raw = std::fs::read_to_string(&p).unwrap_or_default();
        let done = self.done()?;
        let keep: Vec<String> = done
            .values()
            .map(|e| serde_json::to_string(e).expect("entries serialise"))
            .collect();
        let n_raw = raw.lines().filter(|l| !l.trim().is_empty()).count();
        if n_raw == keep.len() && (raw.is_empty() || raw.ends_with('\n')) {
            return Ok(());
        }
        let text: String = keep.iter().map(|l| format!("{l}\n")).collect();
        crate::output::write_atomic(&p, |tmp| {
            std::fs::write(tmp, &text).map_err(|e| e.to_string())
        })
    }

    /// Appends `e` unless its frame is already listed intact (another process finished it
    /// first); returns whether it was appended. Under the lock, one `write` of one line, synced.
    pub fn append(&self, e: &Entry) -> Result<bool, Error> {
        let _lock = self.lock()?;
        // Only this frame's files are verified: a full check per append would read the whole
        // dataset once per frame.
        if self.listed_intact(e.frame)? {
            return Ok(false);
        }
        let p = self.root.join(MANIFEST);
        let mut f = std::fs::OpenOptions::new()
            .create(true)
            .read(true)
            .append(true)
            .open(&p)
            .map_err(|err| Error::io(&p, err))?;
        let mut line = serde_json::to_string(e).expect("entries serialise");
        line.push('\n');
        // A torn line from a killed writer: end it, so this line parses on its own.
        let len = f.metadata().map_err(|err| Error::io(&p, err))?.len();
        if len > 0 {
            let mut last = [0u8];
            f.seek(SeekFrom::Start(len - 1))
                .and_then(|_| f.read_exact(&mut last))
                .map_err(|err| Error::io(&p, err))?;
            if last[0] != b'\n' {
                line.insert(0, '\n');
            }
        }
        f.write_all(line.as_bytes())
            .and_then(|_| f.sync_data())
            .map_err(|err| Error::io(&p, err))?;
        Ok(true)
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
            let (sha, bytes) = sha256(f).map_err(|e| Error::io(f, e))?;
            let rel = f.strip_prefix(&self.root).unwrap_or(f);
            sums.push(FileSum {
                path: rel.to_string_lossy().replace('\\', "/"),
                sha256: sha,
                bytes,
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

/// SHA-256 (hex) and size of a file.
pub fn sha256(path: &Path) -> std::io::Result<(String, u64)> {
    let bytes = std::fs::read(path)?;
    Ok((hex(&Sha256::digest(&bytes)), bytes.len() as u64))
}

pub fn hex(b: &[u8]) -> String {
    b.iter().map(|x| format!("{x:02x}")).collect()
}

/// The paths where `a` and `b` differ, as `path: old → new`.
fn diff(a: &Value, b: &Value, path: &str, out: &mut Vec<String>) {
    match (a, b) {
        // The input files' hashes: name the file, not its hash.
        (Value::Object(x), Value::Object(y)) if path == "inputs" => {
            let keys: std::collections::BTreeSet<&String> = x.keys().chain(y.keys()).collect();
            for k in keys {
                match (x.get(k), y.get(k)) {
                    (Some(u), Some(v)) if u != v => {
                        out.push(format!("the contents of the input file `{k}`"))
                    }
                    (None, Some(_)) => out.push(format!("a new input file `{k}`")),
                    (Some(_), None) => out.push(format!("the input file `{k}` is no longer read")),
                    _ => {}
                }
            }
        }
        (Value::Object(x), Value::Object(y)) => {
            let keys: std::collections::BTreeSet<&String> = x.keys().chain(y.keys()).collect();
            for k in keys {
                if k == "hash" {
                    continue;
                }
                let p = if path.is_empty() {
                    k.clone()
                } else {
                    format!("{path}.{k}")
                };
                diff(
                    x.get(k).unwrap_or(&Value::Null),
                    y.get(k).unwrap_or(&Value::Null),
                    &p,
                    out,
                );
            }
        }
        (Value::Array(x), Value::Array(y)) if x.len() == y.len() => {
            for (i, (u, v)) in x.iter().zip(y).enumerate() {
                diff(u, v, &format!("{path}[{i}]"), out);
            }
        }
        _ if a != b => {
            let short = |v: &Value| {
                let s = v.to_string();
                if s.chars().count() > 40 {
                    format!("{}…", s.chars().take(40).collect::<String>())
                } else {
                    s
                }
            };
            out.push(format!("{path}: {} → {}", short(a), short(b)));
        }
        _ => {}
    }
}
