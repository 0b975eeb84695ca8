//! Paths as outputs record them: absolute and lexically normal, or relative to a folder, so a
//! file's text never depends on the directory prism runs in.

use std::path::{Component, Path, PathBuf};

/// `p` made absolute and lexically normal (no `.`, `..` folded into its parent); the empty
/// path (the folder of a bare file name, `Path::new("a.ron").parent()`) is the current one.
pub fn normal(p: &Path) -> PathBuf {
    let p = if p.as_os_str().is_empty() {
        Path::new(".")
    } else {
        p
    };
    let abs = std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
    let mut out = PathBuf::new();
    for c in abs.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            c => out.push(c),
        }
    }
    out
}

/// `p` relative to `dir` (both normal), with `..` where `p` lies outside `dir`, `/`-separated.
pub fn relative(p: &Path, dir: &Path) -> String {
    let (a, b): (Vec<_>, Vec<_>) = (p.components().collect(), dir.components().collect());
    let common = a.iter().zip(&b).take_while(|(x, y)| x == y).count();
    if common == 0 {
        // Another drive (Windows): nothing to be relative to.
        return p.to_string_lossy().replace('\\', "/");
    }
    let up = std::iter::repeat_n("..".to_string(), b.len() - common);
    let down = a[common..]
        .iter()
        .map(|c| c.as_os_str().to_string_lossy().into_owned());
    up.chain(down).collect::<Vec<_>>().join("/")
}
