//! The manifest's lines: which frames it lists, which of them are done (their files intact),
//! appending a finished frame's line under the lock, and compacting it after a crash.

use super::{folder_error, Entry, FileSum, Out, MANIFEST};
use crate::error::Error;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::io::{BufRead, Read, Seek, SeekFrom, Write};

impl Out {
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
    pub(super) fn compact(&self) -> Result<(), Error> {
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
}
