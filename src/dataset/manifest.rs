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

use crate::error::{Error, InputError};

mod claim;
pub use claim::Hold;
use fs4::fs_std::FileExt;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::collections::BTreeMap;
use std::io::{BufRead, Read, Seek, SeekFrom, Write};
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

    /// The manifest's bytes (none if it is missing), read through the input-file checks: a
    /// FIFO or device there is refused, not read forever.
    fn raw(&self) -> Result<Vec<u8>, Error> {
        use crate::io::input_file::{self, Kind};
        let p = self.root.join(MANIFEST);
        if std::fs::symlink_metadata(&p).is_err() {
            return Ok(Vec::new());
        }
        input_file::read(&p, Kind::Manifest).map_err(|e| folder_error(&p, e))
    }

    /// Every manifest line that parses, in order, whether or not its files are intact. A line
    /// that does not parse (torn, or not UTF-8) is skipped.
    fn lines(&self) -> Result<Vec<Entry>, Error> {
        Ok(self
            .raw()?
            .split(|&b| b == b'\n')
            .filter_map(|l| serde_json::from_slice::<Entry>(l).ok())
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
        if std::fs::symlink_metadata(&p).is_err() {
            return Ok(false);
        }
        let f = crate::io::input_file::open(&p, crate::io::input_file::Kind::Manifest)
            .map_err(|e| folder_error(&p, e))?;
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

    /// Whether `e` lists its own frame's files, the EXR among them, each there with its
    /// checksum. A line naming another frame's files, or none, is not this frame's record.
    pub fn intact(&self, e: &Entry) -> bool {
        if e.frame >= self.frames {
            return false;
        }
        let own = format!("frames/{:06}.", e.frame);
        let named = |f: &FileSum| {
            f.path
                .strip_prefix(&own)
                .is_some_and(|ext| !ext.is_empty() && !ext.contains(['/', '\\']))
        };
        e.files.iter().any(|f| named(f) && f.path.ends_with(".exr"))
            && e.files.iter().all(|f| named(f) && self.file_intact(f))
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
        let raw = String::from_utf8_lossy(&self.raw()?).into_owned();
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
        // The same f32 read back (configs are f32, JSON holds the f64 it widens to): no change.
        (Value::Number(x), Value::Number(y))
            if x.as_f64()
                .zip(y.as_f64())
                .is_some_and(|(u, v)| u as f32 == v as f32) => {}
        _ if a != b => {
            let short = |v: &Value| {
                // A config's f32 as written (0.3), not as JSON's f64 holds it (0.30000001…).
                let s = match v.as_f64() {
                    Some(x) if v.is_f64() && (x as f32) as f64 == x => (x as f32).to_string(),
                    _ => v.to_string(),
                };
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
