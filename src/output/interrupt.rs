//! Ctrl-C (SIGINT) and SIGTERM: prism exits at once with 128 + the signal number (130 for
//! Ctrl-C), first removing the temporary file it is writing, so an interrupted run leaves
//! neither a truncated image nor a hidden temporary behind; a finished output is only ever
//! replaced by the final rename, so the old one stays intact.
//!
//! Temporaries are registered under one lock, which is held from the check for a pending
//! signal through the file's creation, and again through the rename. The signal thread takes
//! that lock, removes what is registered and exits while holding it, so no writer can create
//! or rename a file after the removal.

use std::path::{Path, PathBuf};
use std::sync::Mutex;

static TEMPS: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn temps() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
    TEMPS.lock().unwrap_or_else(|e| e.into_inner())
}

/// Starts the thread that handles SIGINT and SIGTERM (once per process). Only the CLI calls
/// it: in a host process (Python) the handler would outlive the call, turn Ctrl-C into an exit
/// and leave forked children deaf to SIGTERM, their handler thread not being forked.
#[cfg(unix)]
pub fn install() {
    use signal_hook::consts::{SIGINT, SIGTERM};
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM]) else {
            // Without the handler the default action (terminate) applies; the next run's
            // sweep removes a temporary left behind.
            return;
        };
        std::thread::spawn(move || {
            if let Some(sig) = signals.forever().next() {
                let temps = temps();
                for t in temps.iter() {
                    let _ = std::fs::remove_file(t);
                }
                let name = if sig == SIGINT { "SIGINT" } else { "SIGTERM" };
                crate::error::note(format_args!(
                    "\nerror: interrupted by {name}; no unfinished output file left behind"
                ));
                std::process::exit(128 + sig);
            }
        });
    });
}

#[cfg(not(unix))]
pub fn install() {}

/// A registered temporary file: removed (and unregistered) when dropped, unless renamed.
pub(super) struct Temp {
    path: PathBuf,
}

impl Temp {
    /// Registers `path` and creates it empty (truncating a leftover of ours).
    pub(super) fn create(path: &Path) -> std::io::Result<Temp> {
        let mut t = temps();
        std::fs::File::create(path)?;
        t.push(path.to_path_buf());
        Ok(Temp {
            path: path.to_path_buf(),
        })
    }

    pub(super) fn path(&self) -> &Path {
        &self.path
    }

    /// Renames the temporary to `to`, under the lock (a signal waits for the rename).
    pub(super) fn rename(self, to: &Path) -> std::io::Result<()> {
        let mut t = temps();
        let r = std::fs::rename(&self.path, to);
        if r.is_ok() {
            t.retain(|p| p != &self.path);
        }
        drop(t);
        // On failure, drop removes the temporary.
        r
    }
}

impl Drop for Temp {
    fn drop(&mut self) {
        let mut t = temps();
        if let Some(i) = t.iter().position(|p| p == &self.path) {
            let _ = std::fs::remove_file(&self.path);
            t.remove(i);
        }
    }
}
