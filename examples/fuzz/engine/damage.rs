//! Damages to a finished dataset run's folder (issue 27 item 5): what a crash, a user or another
//! tool can leave in OUT (torn or forged manifest lines, parts of the wrong file type, foreign
//! files, stale temporaries, a damaged frame), drawn per case and applied before the case runs.
//! Applying them must never hang or exhaust the fuzzer itself: an earlier damage can leave a
//! FIFO or a link to /dev/zero where a later one reads or writes.

use super::dataset::OutState;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// A damage to a finished run's folder.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Damage {
    /// The manifest's last `n` bytes cut (a torn line).
    TornTail(usize),
    /// A line of these bytes appended (garbage, invalid UTF-8).
    AppendLine(Vec<u8>),
    /// Frame 1's line and files removed, then a forged line appended: frame 1 naming frame
    /// 0's files ("other"), frame 1 with `"files": []` ("empty"), or frame 99 of 2 with copies
    /// of frame 0's files ("past").
    Forge(String),
    /// `name` (relative to OUT) replaced by a directory, a file, a FIFO (a directory
    /// in-process, where a blocked open would stop the fuzzer), a dangling link or a link to
    /// /dev/zero.
    WrongType(String, String),
    /// A temporary of a dead process (`.NAME.<pid>.tmp.EXT`) beside a frame and the JSON.
    StaleTemp,
    /// A file of the user's in OUT or in frames/.
    ForeignFile(String),
    /// Frame 0's EXR with a byte flipped at this offset (same size).
    CorruptFrame(usize),
    /// dataset.json cut to this many bytes.
    TruncateIdentity(usize),
    /// Frame 1's EXR removed.
    RemoveFrame,
}

const TARGETS: &[&str] = &[
    "manifest.jsonl",
    "frames",
    ".prism-dataset.lock",
    "dataset.json",
    "frames/000000.exr",
    "frames/000001.json",
];
const KINDS: &[&str] = &["dir", "file", "fifo", "dangling", "devzero"];

/// A random state (`pick(n)` is uniform in 0..n).
pub fn random_state(pick: &mut dyn FnMut(usize) -> usize) -> OutState {
    match pick(10) {
        0 => OutState::Absent,
        1 => OutState::Empty,
        2 => OutState::Foreign,
        3 => [OutState::IsFile, OutState::DanglingLink][pick(2)].clone(),
        _ => {
            let n = pick(3);
            let d = (0..n)
                .map(|_| match pick(9) {
                    0 => Damage::TornTail(1 + pick(60)),
                    1 => Damage::AppendLine(
                        [
                            &b"{\"frame\":1,\xff\xfe}"[..],
                            &b"{\"frame\":0"[..],
                            &b"garbage"[..],
                            &b"\0\0\0"[..],
                        ][pick(4)]
                        .to_vec(),
                    ),
                    2 => Damage::Forge(["other", "empty", "past"][pick(3)].into()),
                    3 => Damage::WrongType(
                        TARGETS[pick(TARGETS.len())].into(),
                        KINDS[pick(KINDS.len())].into(),
                    ),
                    4 => Damage::StaleTemp,
                    5 => Damage::ForeignFile(["notes.txt", "frames/notes.txt"][pick(2)].into()),
                    6 => Damage::CorruptFrame(pick(400)),
                    7 => Damage::TruncateIdentity(pick(200)),
                    _ => Damage::RemoveFrame,
                })
                .collect();
            OutState::Primed(d)
        }
    }
}

pub fn damage(out: &Path, d: &Damage, fifo: bool) {
    let m = out.join("manifest.jsonl");
    let text = read_regular(&m).unwrap_or_default();
    let frame0 = |t: &[u8]| -> Option<String> {
        String::from_utf8_lossy(t)
            .lines()
            .find(|l| l.starts_with("{\"frame\":0,"))
            .map(String::from)
    };
    match d {
        Damage::TornTail(n) => {
            write_regular(&m, &text[..text.len().saturating_sub(*n)]);
        }
        Damage::AppendLine(b) => {
            let mut t = text.clone();
            t.extend_from_slice(b);
            t.push(b'\n');
            write_regular(&m, t);
        }
        Damage::Forge(kind) => {
            let Some(line0) = frame0(&text) else { return };
            let keep: String = String::from_utf8_lossy(&text)
                .lines()
                .filter(|l| !l.starts_with("{\"frame\":1,"))
                .map(|l| format!("{l}\n"))
                .collect();
            for e in ["exr", "json", "png"] {
                let _ = std::fs::remove_file(out.join(format!("frames/000001.{e}")));
            }
            let forged = match kind.as_str() {
                "other" => line0.replacen("\"frame\":0", "\"frame\":1", 1),
                "empty" => {
                    let head = line0.split("\"files\":[").next().unwrap_or("");
                    let tail = line0.find("],\"seconds\"").map_or("}", |i| &line0[i + 1..]);
                    format!(
                        "{}\"files\":[]{tail}",
                        head.replacen("\"frame\":0", "\"frame\":1", 1)
                    )
                }
                _ => {
                    for e in ["exr", "json", "png"] {
                        if let Some(b) = read_regular(&out.join(format!("frames/000000.{e}"))) {
                            write_regular(&out.join(format!("frames/000099.{e}")), b);
                        }
                    }
                    line0
                        .replacen("\"frame\":0", "\"frame\":99", 1)
                        .replace("frames/000000.", "frames/000099.")
                }
            };
            write_regular(&m, format!("{keep}{forged}\n"));
        }
        Damage::WrongType(name, kind) => {
            let p = out.join(name);
            if p.is_dir() {
                let _ = std::fs::remove_dir_all(&p);
            } else {
                let _ = std::fs::remove_file(&p);
            }
            let _ = match (kind.as_str(), fifo) {
                ("dir", _) | ("fifo", false) => std::fs::create_dir(&p),
                ("file", _) => std::fs::write(&p, "x"),
                ("fifo", true) => {
                    let c = std::ffi::CString::new(p.display().to_string()).unwrap();
                    // SAFETY: a NUL-terminated path of our own.
                    unsafe { libc::mkfifo(c.as_ptr(), 0o644) };
                    Ok(())
                }
                ("dangling", _) => std::os::unix::fs::symlink(out.join("nowhere/x"), &p),
                _ => std::os::unix::fs::symlink("/dev/zero", &p),
            };
        }
        Damage::StaleTemp => {
            write_regular(&out.join("frames/.000000.exr.999999.tmp.exr"), "half");
            write_regular(&out.join(".dataset.json.999999.tmp.json"), "{");
        }
        Damage::ForeignFile(name) => {
            write_regular(&out.join(name), "mine");
        }
        Damage::CorruptFrame(at) => {
            let p = out.join("frames/000000.exr");
            if let Some(mut b) = read_regular(&p) {
                if !b.is_empty() {
                    let i = at % b.len();
                    b[i] ^= 0x5a;
                    write_regular(&p, b);
                }
            }
        }
        Damage::TruncateIdentity(n) => {
            let p = out.join("dataset.json");
            if let Some(b) = read_regular(&p) {
                write_regular(&p, &b[..(*n).min(b.len())]);
            }
        }
        Damage::RemoveFrame => {
            let _ = std::fs::remove_file(out.join("frames/000001.exr"));
        }
    }
}

/// The bytes of `p` when it is a regular file (links not followed), else None. An earlier
/// damage may have made it a FIFO (whose open blocks) or a link to /dev/zero (whose read never
/// ends): run 11 of the long fuzz (seed 20261204) hung on the one and was OOM-killed at 22 GB on
/// the other, in the fuzzer's own damage step, not in prism.
pub fn read_regular(p: &Path) -> Option<Vec<u8>> {
    let m = std::fs::symlink_metadata(p).ok()?;
    if !m.file_type().is_file() {
        return None;
    }
    std::fs::read(p).ok()
}

/// Writes `b` to `p` only where `p` is absent or a regular file, for the same reason (an open
/// for writing blocks on a FIFO with no reader).
fn write_regular(p: &Path, b: impl AsRef<[u8]>) {
    if std::fs::symlink_metadata(p).is_ok_and(|m| !m.file_type().is_file()) {
        return;
    }
    let _ = std::fs::write(p, b);
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::mpsc;
    use std::time::Duration;

    /// Every damage after a part of OUT became a FIFO, or a link to one, returns: before
    /// `read_regular`/`write_regular`, the torn-tail and corrupt-frame damages blocked on the
    /// FIFO's open (fuzz run 11, case 553). A link to a FIFO stands for the link to /dev/zero
    /// (the same link check), which cannot be tried here without exhausting memory if broken.
    /// 10 s: each damage is a few small file operations (milliseconds).
    #[test]
    fn damages_return_over_fifos_and_links_to_them() {
        let every = || {
            vec![
                Damage::TornTail(5),
                Damage::AppendLine(b"garbage".to_vec()),
                Damage::Forge("other".into()),
                Damage::Forge("empty".into()),
                Damage::Forge("past".into()),
                Damage::StaleTemp,
                Damage::ForeignFile("frames/notes.txt".into()),
                Damage::CorruptFrame(3),
                Damage::TruncateIdentity(4),
                Damage::RemoveFrame,
            ]
        };
        for target in [
            "manifest.jsonl",
            "dataset.json",
            "frames/000000.exr",
            "frames/000000.json",
        ] {
            for link in [false, true] {
                let tmp = tempfile::tempdir().unwrap();
                let out = tmp.path().join("out");
                std::fs::create_dir_all(out.join("frames")).unwrap();
                let line0 = r#"{"frame":0,"files":[{"path":"frames/000000.exr"}],"seconds":1}"#;
                std::fs::write(out.join("manifest.jsonl"), format!("{line0}\n")).unwrap();
                std::fs::write(out.join("dataset.json"), "{}").unwrap();
                for f in ["000000.exr", "000000.json", "000001.exr"] {
                    std::fs::write(out.join("frames").join(f), "pixels").unwrap();
                }
                let p = out.join(target);
                std::fs::remove_file(&p).unwrap();
                let fifo = if link {
                    tmp.path().join("fifo")
                } else {
                    p.clone()
                };
                let c = std::ffi::CString::new(fifo.display().to_string()).unwrap();
                // SAFETY: a NUL-terminated path of our own.
                assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o644) }, 0);
                if link {
                    std::os::unix::fs::symlink(&fifo, &p).unwrap();
                }
                let (tx, rx) = mpsc::channel();
                let o = out.clone();
                std::thread::spawn(move || {
                    for d in every() {
                        damage(&o, &d, true);
                    }
                    let _ = tx.send(());
                });
                assert!(
                    rx.recv_timeout(Duration::from_secs(10)).is_ok(),
                    "a damage blocked on {target} as a FIFO (through a link: {link})"
                );
            }
        }
    }
}
