//! Checks on output paths before anything is rendered, so a mistake costs nothing: an EXR path
//! must end in `.exr` and a preview in `.png`, the two must differ, neither may be a file the
//! scene reads (the scene, a mesh, an image, a spectrum file), and each must be writable: its
//! directory is created if missing and a temporary file is created there and removed again.
//! Stale temporaries of earlier runs that were killed are swept from that directory.

use crate::error::InputError;
use std::fs;
use std::path::{Path, PathBuf};

/// The temporary sibling `write_atomic` writes before renaming: `.NAME.<pid>.tmp.EXT` (the
/// extension kept last: some writers choose the format from it).
pub fn temp_path(path: &Path) -> Option<PathBuf> {
    let name = path.file_name()?;
    let ext = path.extension().map(|e| e.to_string_lossy().into_owned());
    Some(dir_of(path).join(format!(
        ".{}.{}.tmp.{}",
        name.to_string_lossy(),
        std::process::id(),
        ext.unwrap_or_default()
    )))
}

/// The directory `path` is written in (`.` for a bare file name).
pub fn dir_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// The process id in a temporary file name of ours, if `name` is one.
fn temp_pid(name: &str) -> Option<u32> {
    let rest = name.strip_prefix('.')?;
    let i = rest.rfind(".tmp.")?;
    let (head, ext) = (&rest[..i], &rest[i + 5..]);
    let j = head.rfind('.')?;
    let (out, pid) = (&head[..j], &head[j + 1..]);
    let out_ext = Path::new(out)
        .extension()
        .map(|e| e.to_string_lossy().into_owned())
        .unwrap_or_default();
    let digits = !pid.is_empty() && pid.bytes().all(|b| b.is_ascii_digit());
    if out.is_empty() || !digits || out_ext != ext {
        return None;
    }
    pid.parse().ok().filter(|&p| p > 0 && p <= i32::MAX as u32)
}

#[cfg(unix)]
fn alive(pid: u32) -> bool {
    // Signal 0 only checks: 0 = exists; EPERM = exists but belongs to another user.
    // SAFETY: kill with signal 0 sends nothing; pid is positive (not a process group).
    let r = unsafe { libc::kill(pid as libc::pid_t, 0) };
    r == 0 || std::io::Error::last_os_error().raw_os_error() != Some(libc::ESRCH)
}

#[cfg(not(unix))]
fn alive(_pid: u32) -> bool {
    true
}

/// Removes temporaries of our naming in `dir` whose process is gone (a run killed while
/// writing); returns how many. Files of live processes, and anything else, are left alone.
pub fn sweep(dir: &Path) -> usize {
    let Ok(entries) = fs::read_dir(dir) else {
        return 0;
    };
    let mut n = 0;
    for e in entries.flatten() {
        let name = e.file_name();
        let Some(pid) = name.to_str().and_then(temp_pid) else {
            continue;
        };
        if pid == std::process::id() || alive(pid) {
            continue;
        }
        if e.file_type().is_ok_and(|t| t.is_file()) && fs::remove_file(e.path()).is_ok() {
            n += 1;
        }
    }
    n
}

fn has_ext(path: &Path, ext: &str) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case(ext))
}

/// The file names alone, before the scene loads: `exr` (named by `-o`, or the default) must
/// end in `.exr`, `preview` in `.png`, and they must differ.
pub fn check_names(exr: &Path, preview: Option<&Path>) -> Result<(), InputError> {
    if !has_ext(exr, "exr") {
        return Err(InputError::new(
            exr,
            "the output does not end in `.exr`, but prism writes OpenEXR there",
        )
        .field("-o")
        .hint(
            "name the EXR output `*.exr`; an 8-bit PNG preview is written with --preview out.png",
        ));
    }
    if let Some(p) = preview {
        if same_path(p, exr) {
            return Err(
                InputError::new(p, "the preview would overwrite the EXR output")
                    .field("--preview")
                    .hint("give the preview its own `*.png` path"),
            );
        }
        if !has_ext(p, "png") {
            return Err(InputError::new(
                p,
                "the preview does not end in `.png`, but prism writes PNG there",
            )
            .field("--preview")
            .hint("name the preview `*.png`"));
        }
    }
    Ok(())
}

/// An output path, once the scene has loaded: not one of `inputs` (the files the scene read,
/// the scene file first) and writable. `flag` names the option it came from.
pub fn check_output(path: &Path, flag: &str, inputs: &[PathBuf]) -> Result<(), InputError> {
    if let Some(k) = inputs.iter().position(|i| same_path(path, i)) {
        let what = if k == 0 {
            "the scene file being rendered".to_string()
        } else {
            format!("`{}`, a file this scene reads", inputs[k].display())
        };
        return Err(InputError::new(
            path,
            format!("the output is {what}; writing it would destroy it"),
        )
        .field(flag)
        .hint("choose another output path"));
    }
    check_writable(path, flag)
}

/// `path` can be written: it is not a directory or a special file, no parent of it is a
/// regular file, and a temporary can be created (and is removed again) in its directory.
pub fn check_writable(path: &Path, flag: &str) -> Result<(), InputError> {
    let err = |m: String| {
        InputError::new(path, m)
            .field(flag)
            .hint("give an output path in a folder prism can write")
    };
    // A link (dangling or not) would be replaced by the rename, not written through: refuse it
    // rather than guess which of the two the user meant.
    if fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink()) {
        return Err(
            err("the output is a symbolic link; writing would replace the link".into())
                .hint("give the path of the file itself, or remove the link"),
        );
    }
    match fs::metadata(path) {
        Ok(m) if m.is_dir() => {
            return Err(err("the output is a directory".into())
                .hint("give a file name inside it, e.g. `DIR/render.exr`"))
        }
        Ok(m) if !m.is_file() => {
            return Err(err("the output exists and is not a regular file".into())
                .hint("choose a path for a new or regular file"))
        }
        _ => {}
    }
    let dir = dir_of(path);
    let mut a = Some(dir.as_path());
    while let Some(p) = a {
        if let Ok(m) = fs::metadata(p) {
            if !m.is_dir() {
                return Err(err(format!(
                    "the output lies under `{}`, which is a file, not a directory",
                    p.display()
                ))
                .hint("choose a path in a directory"));
            }
            break;
        }
        a = p.parent().filter(|q| !q.as_os_str().is_empty());
    }
    fs::create_dir_all(&dir).map_err(|e| {
        err(format!(
            "cannot create the directory `{}`: {e}",
            dir.display()
        ))
        .hint("choose a writable location")
    })?;
    sweep(&dir);
    let tmp = temp_path(path).ok_or_else(|| err("the output is not a file path".into()))?;
    fs::File::create(&tmp).map_err(|e| {
        err(format!("cannot write in `{}`: {e}", dir.display())).hint("choose a writable directory")
    })?;
    let _ = fs::remove_file(&tmp);
    Ok(())
}

/// True if `a` and `b` are the same file (hard or symbolic links included) or, where neither
/// exists yet, the same path once the existing directories in it are resolved.
fn same_path(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let (Ok(x), Ok(y)) = (fs::metadata(a), fs::metadata(b)) {
            return x.dev() == y.dev() && x.ino() == y.ino();
        }
    }
    resolve(a) == resolve(b)
}

fn resolve(p: &Path) -> PathBuf {
    if let Ok(c) = p.canonicalize() {
        return c;
    }
    match (dir_of(p).canonicalize(), p.file_name()) {
        (Ok(d), Some(n)) => d.join(n),
        _ => std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recognises_only_our_temporary_names() {
        let pid = std::process::id();
        let ours = temp_path(Path::new("d/out.exr")).unwrap();
        assert_eq!(ours, Path::new(&format!("d/.out.exr.{pid}.tmp.exr")));
        assert_eq!(temp_pid(&format!(".out.exr.{pid}.tmp.exr")), Some(pid));
        assert_eq!(temp_pid(".a.b.png.77.tmp.png"), Some(77));
        assert_eq!(temp_pid(".noext.5.tmp."), Some(5));
        for other in [
            "out.exr.5.tmp.exr",  // not hidden
            ".out.exr.5.tmp.png", // extension differs from the output's
            ".out.exr.x5.tmp.exr",
            ".out.exr..tmp.exr",
            ".5.tmp.exr",
            ".out.exr.0.tmp.exr",
            ".out.exr.99999999999.tmp.exr",
            ".bashrc",
        ] {
            assert_eq!(temp_pid(other), None, "{other}");
        }
    }
}
