//! External buffer and image URIs, checked before the crate reads them: the file must be a
//! regular file within its kind's limit, and lie in the model's folder. A model from elsewhere
//! naming `../../.ssh/id_rsa`, `%2e%2e/x.bin`, `/etc/passwd` or `file:///etc/passwd` would
//! otherwise have prism read any file the user can (and a texture's pixels end up in the
//! render); the scene's `Gltf(..., allow_outside: true)` lifts the confinement.

use super::err;
use crate::error::InputError;
use crate::io::input_file::{self, Kind};
use std::path::{Path, PathBuf};

/// Checks the file an external buffer or image URI names: a regular file within `kind`'s
/// limit (a FIFO or `/dev/zero` would block or be read until memory runs out), a relative URI
/// whose percent-decoding is UTF-8 (the crate unwraps that decoding), and unless
/// `allow_outside`, a file inside `base` (the model's folder) once `..` and symlinks are
/// resolved. A URI of another scheme is left to the crate, which refuses it.
pub(super) fn check_external(
    path: &Path,
    base: &Path,
    uri: &str,
    kind: Kind,
    field: &str,
    allow_outside: bool,
) -> Result<(), InputError> {
    let file = if let Some(rest) = uri.strip_prefix("file://").or(uri.strip_prefix("file:")) {
        PathBuf::from(rest)
    } else if uri.contains(':') {
        return Ok(());
    } else {
        match urlencoding::decode(uri) {
            Ok(p) => base.join(&*p),
            Err(_) => {
                return Err(err(
                    path,
                    field,
                    format!("the URI \"{uri}\" does not decode to UTF-8 text"),
                )
                .hint("URIs are percent-encoded UTF-8 (RFC 3986): re-export the model, or rename the file it names"))
            }
        }
    };
    if !allow_outside {
        confine(path, base, uri, &file, field)?;
    }
    input_file::open(&file, kind).map(drop).map_err(|e| {
        err(path, field, e)
            .hint("external files are relative to the glTF file: keep them beside it")
    })
}

/// Refuses `file` (named by `uri`) unless it lies under `base`. Both are resolved
/// (`canonicalize`: `..`, symlinks).
fn confine(
    path: &Path,
    base: &Path,
    uri: &str,
    file: &Path,
    field: &str,
) -> Result<(), InputError> {
    let base = if base.as_os_str().is_empty() {
        Path::new(".")
    } else {
        base
    };
    let Ok(root) = base.canonicalize() else {
        return Ok(());
    };
    // A missing file is judged by its folder, a missing folder by the path's own `..`s.
    let resolved = file
        .canonicalize()
        .or_else(|_| {
            let parent = file.parent().ok_or(())?.canonicalize().map_err(drop)?;
            Ok::<_, ()>(parent.join(file.file_name().ok_or(())?))
        })
        .unwrap_or_else(|_| lexical(&root.join(file.strip_prefix(base).unwrap_or(file))));
    if resolved.starts_with(&root) {
        return Ok(());
    }
    Err(err(
        path,
        field,
        format!(
            "the URI \"{uri}\" names `{}`, outside the model's folder `{}`",
            resolved.display(),
            root.display()
        ),
    )
    .hint("copy the file beside the model and name it relatively, or, if you trust the model, set `allow_outside: true` on its `Gltf(...)` shape in a RON scene"))
}

/// `p` with its `.` and `..` components resolved as text (for a path that does not exist).
fn lexical(p: &Path) -> PathBuf {
    use std::path::Component;
    let mut out = PathBuf::new();
    for c in p.components() {
        match c {
            Component::ParentDir => {
                out.pop();
            }
            Component::CurDir => {}
            c => out.push(c),
        }
    }
    out
}
