//! The files a scene load reads (the scene, meshes, images, spectrum files), so that the CLI can
//! refuse an output path that would overwrite one of them. Each reader calls `record`; `collect`
//! gathers what was recorded on this thread while it ran (a scene loads on one thread).

use std::cell::RefCell;
use std::path::{Path, PathBuf};

thread_local! {
    static READ: RefCell<Option<Vec<PathBuf>>> = const { RefCell::new(None) };
}

/// Notes that `path` is read as an input (a no-op outside `collect`).
pub fn record(path: &Path) {
    READ.with(|r| {
        if let Some(v) = r.borrow_mut().as_mut() {
            if !v.iter().any(|p| p == path) {
                v.push(path.to_path_buf());
            }
        }
    });
}

/// `err` with `hint` (where relative paths are anchored) if `full` was not found; a file that
/// was found but is broken gets no such hint.
pub fn missing_hint(
    err: crate::error::InputError,
    full: &Path,
    hint: &str,
) -> crate::error::InputError {
    if full.exists() {
        err
    } else {
        err.hint(hint)
    }
}

/// Runs `f`, returning its result and the input files recorded while it ran.
pub fn collect<T>(f: impl FnOnce() -> T) -> (T, Vec<PathBuf>) {
    let outer = READ.with(|r| r.borrow_mut().replace(Vec::new()));
    let out = f();
    let files = READ.with(|r| std::mem::replace(&mut *r.borrow_mut(), outer));
    (out, files.unwrap_or_default())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_only_inside_collect_and_once_per_file() {
        record(Path::new("ignored.ron"));
        let ((), files) = collect(|| {
            record(Path::new("a.ron"));
            record(Path::new("m.obj"));
            record(Path::new("a.ron"));
        });
        assert_eq!(files, [PathBuf::from("a.ron"), PathBuf::from("m.obj")]);
    }
}
