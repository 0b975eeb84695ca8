//! Opening a user's input file safely: every reader of scene, spectrum, mesh and texture files
//! goes through here, so a FIFO or a device (`/dev/zero`, `/dev/stdin`) given as a file is
//! refused instead of blocking or reading forever, and a file larger than its kind's limit is
//! refused with its size, the limit and the fix, before it is read.
//!
//! The limits (documented in scenes/README.md, "Input files") are far above real inputs and low
//! enough that one file cannot take the machine's memory by itself: a 64 MiB scene is millions
//! of lines of RON; a 4 GiB binary PLY holds about 130 million triangles.

use std::fs::File;
use std::io::Read;
use std::path::Path;

/// What an input file is, which sets its size limit and names it in messages.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Scene,
    Spectrum,
    Mesh,
    Texture,
    /// A `.gltf` or `.glb` file, or an external buffer (`.bin`) it names.
    Gltf,
    /// A sensor file (`--sensor`, `sensor: File(...)`, a dataset's `sensor.files`).
    Sensor,
    /// A dataset config (`prism dataset CONFIG`).
    Dataset,
    /// A dataset's `manifest.jsonl` (a line per frame: long datasets make it long).
    Manifest,
    /// Any other file a dataset hashes: its scene's assets, envmap files, its frames' outputs.
    Asset,
}

const MIB: u64 = 1 << 20;

impl Kind {
    /// The largest file of this kind prism reads, in bytes.
    pub const fn limit(self) -> u64 {
        match self {
            Kind::Scene => 64 * MIB,
            Kind::Spectrum => 16 * MIB,
            Kind::Mesh => 4096 * MIB,
            Kind::Texture => 1024 * MIB,
            Kind::Gltf => 4096 * MIB,
            Kind::Sensor => 16 * MIB,
            Kind::Dataset => 64 * MIB,
            Kind::Manifest | Kind::Asset => 4096 * MIB,
        }
    }

    fn noun(self) -> &'static str {
        match self {
            Kind::Scene => "scene file",
            Kind::Spectrum => "spectrum file",
            Kind::Mesh => "mesh file",
            Kind::Texture => "image file",
            Kind::Gltf => "glTF file",
            Kind::Sensor => "sensor file",
            Kind::Dataset => "dataset config",
            Kind::Manifest => "manifest",
            Kind::Asset => "input file",
        }
    }
}

/// The most texels an image may have (16384 × 8192): its decoded RGB and uplifted copies then
/// take 3 GiB. Checked from the header, before the pixels are allocated.
pub const MAX_TEXELS: u64 = 1 << 27;

/// Opens `path` for reading if it is a regular file within `kind`'s size limit; the error is a
/// message naming the file, what is wrong and the fix.
pub fn open(path: &Path, kind: Kind) -> Result<File, String> {
    let name = path.display();
    let noun = kind.noun();
    // `metadata` follows symlinks and never blocks, while opening a FIFO for reading waits for
    // a writer: so look first, then open.
    let meta = std::fs::metadata(path).map_err(|e| match e.kind() {
        std::io::ErrorKind::NotFound => format!("{noun} `{name}` does not exist"),
        _ => format!("cannot read the {noun} `{name}`: {e}"),
    })?;
    check(&meta, path, kind)?;
    let file = File::open(path).map_err(|e| format!("cannot read the {noun} `{name}`: {e}"))?;
    // The same check on the opened file, in case the path was replaced in between.
    let meta = file
        .metadata()
        .map_err(|e| format!("cannot read the {noun} `{name}`: {e}"))?;
    check(&meta, path, kind)?;
    Ok(file)
}

/// Reads the whole of `path` (see `open`); a file that grows past the limit while it is read
/// is refused too.
pub fn read(path: &Path, kind: Kind) -> Result<Vec<u8>, String> {
    let file = open(path, kind)?;
    let mut bytes = Vec::new();
    file.take(kind.limit() + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| format!("cannot read the {} `{}`: {e}", kind.noun(), path.display()))?;
    if bytes.len() as u64 > kind.limit() {
        return Err(too_large(path, kind, bytes.len() as u64));
    }
    Ok(bytes)
}

/// The SHA-256 (hex) and size of `path` (see `open`), read in blocks: a multi-GiB asset is
/// hashed in constant memory, and a FIFO or device is refused instead of read forever.
pub fn sha256(path: &Path, kind: Kind) -> Result<(String, u64), String> {
    use sha2::{Digest, Sha256};
    let file = open(path, kind)?;
    let mut h = Sha256::new();
    let n = std::io::copy(&mut file.take(kind.limit() + 1), &mut h)
        .map_err(|e| format!("cannot read the {} `{}`: {e}", kind.noun(), path.display()))?;
    if n > kind.limit() {
        return Err(too_large(path, kind, n));
    }
    let hex: String = h.finalize().iter().map(|x| format!("{x:02x}")).collect();
    Ok((hex, n))
}

fn check(meta: &std::fs::Metadata, path: &Path, kind: Kind) -> Result<(), String> {
    let name = path.display();
    let noun = kind.noun();
    let ft = meta.file_type();
    if !ft.is_file() {
        let what = if ft.is_dir() {
            "a directory".to_string()
        } else {
            use std::os::unix::fs::FileTypeExt;
            if ft.is_fifo() {
                "a FIFO (named pipe)".into()
            } else if ft.is_char_device() || ft.is_block_device() {
                "a device".into()
            } else if ft.is_socket() {
                "a socket".into()
            } else {
                "not a regular file".into()
            }
        };
        return Err(format!(
            "the {noun} `{name}` is {what}; prism reads {noun}s only from regular files \
             (save the data to a file and give its path)"
        ));
    }
    if meta.len() > kind.limit() {
        return Err(too_large(path, kind, meta.len()));
    }
    Ok(())
}

fn too_large(path: &Path, kind: Kind, len: u64) -> String {
    format!(
        "the {} `{}` is {:.1} MiB, more than the {} MiB prism reads for one (scenes/README.md, \
         \"Input files\"); use a smaller file",
        kind.noun(),
        path.display(),
        len as f64 / MIB as f64,
        kind.limit() / MIB
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir() -> std::path::PathBuf {
        let d = std::env::temp_dir().join(format!("prism-input-file-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn refuses_devices_fifos_and_directories() {
        let e = read(Path::new("/dev/zero"), Kind::Scene).unwrap_err();
        assert!(e.contains("`/dev/zero` is a device"), "{e}");
        let d = dir();
        let e = read(&d, Kind::Mesh).unwrap_err();
        assert!(e.contains("is a directory"), "{e}");
        let fifo = d.join("pipe.ron");
        let _ = std::fs::remove_file(&fifo);
        let made = std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap();
        assert!(made.success());
        // Would block forever if it were opened.
        let e = read(&fifo, Kind::Spectrum).unwrap_err();
        assert!(e.contains("is a FIFO"), "{e}");
        let e = read(&d.join("missing.txt"), Kind::Spectrum).unwrap_err();
        assert!(e.contains("does not exist"), "{e}");
    }

    #[test]
    fn refuses_files_over_the_limit_before_reading() {
        let p = dir().join("big.txt");
        let f = File::create(&p).unwrap();
        // A sparse file: one byte over the limit, no disk used.
        f.set_len(Kind::Spectrum.limit() + 1).unwrap();
        let e = read(&p, Kind::Spectrum).unwrap_err();
        assert!(e.contains("16.0 MiB, more than the 16 MiB"), "{e}");
        f.set_len(10).unwrap();
        assert_eq!(read(&p, Kind::Spectrum).unwrap(), vec![0u8; 10]);
    }
}
