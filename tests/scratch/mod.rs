//! A test's own folder under the system's temporary directory, removed when the test passes and
//! kept (its path printed) when it fails, so a failure can be looked at and a passing run leaves
//! nothing behind. The `tempfile` crate makes the folder (a unique name, no clash between test
//! binaries or runs); this wrapper adds keep-on-failure and reads as a `Path`.
#![allow(dead_code)]

use std::ops::Deref;
use std::path::Path;

pub struct Scratch(Option<tempfile::TempDir>);

/// A new empty folder whose name starts with `prism-{prefix}-{name}-`.
pub fn scratch(prefix: &str, name: &str) -> Scratch {
    let clean: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    let dir = tempfile::Builder::new()
        .prefix(&format!("prism-{prefix}-{clean}-"))
        .tempdir()
        .expect("a folder under the system's temporary directory");
    Scratch(Some(dir))
}

impl Scratch {
    pub fn path(&self) -> &Path {
        self.0.as_ref().expect("present until dropped").path()
    }
}

impl Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        self.path()
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        self.path()
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        if let Some(dir) = self.0.take() {
            if std::thread::panicking() {
                eprintln!("test folder kept for inspection: {}", dir.keep().display());
            }
        }
    }
}
