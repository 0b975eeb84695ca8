//! Memory a render will need, estimated from the scene before the large allocations (the film's
//! accumulators, the acceleration structure), and checked against what the machine has: a film
//! too large for the machine is refused at load with the figure and the fix, instead of growing
//! until the kernel kills the process.
//!
//! The estimate follows the buffers the code allocates (integrator/mod.rs, caustics/mod.rs,
//! film.rs, output/exr.rs): per pixel, `slots` accumulators (X, Y, Z and one per spectral band)
//! as f32 twice while tiles are gathered (plus f64 ones for caustic light tracing), then the
//! film's channels, then a copy of them and the compressed blocks for the EXR encoder. What is already loaded (meshes,
//! textures, tables) is the process's resident memory at the check. The test
//! `tests/input_limits.rs` holds the estimate against a measured peak.

use crate::error::InputError;
use std::path::Path;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};

static MAX_MEMORY: AtomicU64 = AtomicU64::new(0);
static THREADS: AtomicUsize = AtomicUsize::new(0);

/// Sets the memory limit (`--max-memory`; `None`: what the machine has available) and the
/// render's thread count (`None`: one per core) for the checks of later scene loads.
pub fn configure(max_memory: Option<u64>, threads: Option<usize>) {
    MAX_MEMORY.store(max_memory.unwrap_or(0), Ordering::Relaxed);
    THREADS.store(threads.unwrap_or(0), Ordering::Relaxed);
}

/// Bytes per primitive of the acceleration structure while it is built and kept (the BVH's
/// build references and nodes, the primitives' boxes and triangle records). Measured: a
/// 1,002,528-triangle binary PLY (a 708² grid) at an 8×8 film peaked at 343 MiB resident with
/// 23 MiB loaded before the build (`/usr/bin/time -f %M`), 335 B per triangle; rounded up.
pub const BVH_BYTES_PER_PRIM: u64 = 352;

/// What the render will allocate, by part, in bytes.
#[derive(Clone, Debug, PartialEq)]
pub struct Estimate {
    pub parts: Vec<(String, u64)>,
}

impl Estimate {
    pub fn total(&self) -> u64 {
        self.parts.iter().map(|p| p.1).sum()
    }
}

/// What a render is made of, for the estimate.
#[derive(Clone, Copy, Debug)]
pub struct Plan {
    pub width: u32,
    pub height: u32,
    /// Accumulator slots per pixel (3 + spectral bands).
    pub slots: usize,
    /// Output channels (R, G, B, X, Y, Z as enabled, plus the bands).
    pub channels: usize,
    pub caustics: bool,
    /// Wavelengths per path.
    pub lanes: usize,
    pub threads: usize,
    /// Primitives the acceleration structure is built over.
    pub prims: u64,
}

/// The memory `plan` needs beyond what is loaded already.
pub fn estimate(p: &Plan) -> Estimate {
    let px = p.width as u64 * p.height as u64;
    let slots = p.slots as u64;
    let ch = p.channels as u64;
    // Rendering: the means and the tiles' results (f32), the caustic accumulators (f64).
    let render = px * slots * (4 + 4 + if p.caustics { 8 } else { 0 });
    // Making the film: the means, the RGB conversion's temporary (3 f32) and the channels.
    let film = px * (slots * 4 + 12 + ch * 4);
    // Writing the EXR: the film, the encoder's copy of it and its compressed blocks (at most
    // their raw size).
    let write = px * ch * 4 * 3;
    let image = render.max(film).max(write);
    let tile = 16 * 16 * slots * 4 + slots * 8;
    let mut parts = vec![(
        format!(
            "film: {}×{} pixels, {} accumulators and {} output channels each",
            p.width, p.height, p.slots, p.channels
        ),
        image,
    )];
    parts.push((
        format!("tile buffers of {} thread(s)", p.threads),
        p.threads as u64 * tile,
    ));
    if p.caustics {
        // A batch of light paths' splats (integrator/caustics/mod.rs: 64 chunks of 4096 paths), two
        // per path on average: pixel, radiance, wavelengths and pdfs.
        parts.push((
            "caustic light paths' splats".into(),
            64 * 4096 * 2 * (4 + 12 * p.lanes as u64),
        ));
    }
    if p.prims > 0 {
        parts.push((
            format!("acceleration structure over {} primitives", p.prims),
            p.prims * BVH_BYTES_PER_PRIM,
        ));
    }
    Estimate { parts }
}

/// Threads the render will use (`configure`'s, else one per core).
pub fn threads() -> usize {
    match THREADS.load(Ordering::Relaxed) {
        0 => std::thread::available_parallelism().map_or(1, |n| n.get()),
        n => n,
    }
}

/// Refuses `plan` if it will not fit: with `--max-memory`, what is loaded plus the estimate
/// must fit in it; otherwise the estimate must fit in the machine's available memory (Linux:
/// `MemAvailable` in /proc/meminfo; elsewhere no check).
pub fn check(plan: &Plan, file: &Path) -> Result<(), InputError> {
    let est = estimate(plan);
    let need = est.total();
    let limit = MAX_MEMORY.load(Ordering::Relaxed);
    let (loaded, have, what) = if limit > 0 {
        let rss = resident().unwrap_or(0);
        (rss, limit, "the --max-memory limit of".to_string())
    } else {
        match available() {
            Some(a) => (0, a, "available on this machine:".to_string()),
            None => return Ok(()),
        }
    };
    if loaded.saturating_add(need) <= have {
        return Ok(());
    }
    let mut detail: Vec<String> = est
        .parts
        .iter()
        .map(|(name, b)| format!("{name}: {}", human(*b)))
        .collect();
    if loaded > 0 {
        detail.push(format!("already loaded: {}", human(loaded)));
    }
    // The part that needs the most names the field and the fix.
    let geometry = plan.prims * BVH_BYTES_PER_PRIM > est.parts[0].1;
    let (field, fix) = if geometry {
        ("shapes", "use fewer or smaller meshes")
    } else {
        (
            "film",
            "make the film smaller (film.width, film.height), write fewer spectral bands \
             (outputs.bands, 0 for none)",
        )
    };
    Err(InputError::new(
        file,
        format!(
            "the render needs about {} of memory ({}), more than {what} {}",
            human(loaded.saturating_add(need)),
            detail.join("; "),
            human(have)
        ),
    )
    .field(field)
    .hint(format!(
        "{fix}, or, if the memory will be there, raise the limit with --max-memory (e.g. \
         --max-memory 64GiB)"
    )))
}

/// `MemAvailable` from /proc/meminfo, in bytes.
pub fn available() -> Option<u64> {
    kib_field("/proc/meminfo", "MemAvailable:")
}

/// This process's resident memory (`VmRSS` in /proc/self/status), in bytes.
pub fn resident() -> Option<u64> {
    kib_field("/proc/self/status", "VmRSS:")
}

fn kib_field(file: &str, key: &str) -> Option<u64> {
    let text = std::fs::read_to_string(file).ok()?;
    let line = text.lines().find(|l| l.starts_with(key))?;
    let kib: u64 = line[key.len()..]
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse()
        .ok()?;
    Some(kib * 1024)
}

/// A byte count for people: `455.0 GiB`.
pub fn human(b: u64) -> String {
    let units = ["B", "KiB", "MiB", "GiB", "TiB"];
    let mut v = b as f64;
    let mut u = 0;
    while v >= 1024.0 && u + 1 < units.len() {
        v /= 1024.0;
        u += 1;
    }
    if u == 0 {
        format!("{b} B")
    } else {
        format!("{v:.1} {}", units[u])
    }
}

/// Parses a size for `--max-memory`: a number with an optional unit, `K`/`KiB`, `M`/`MiB`,
/// `G`/`GiB`, `T`/`TiB` (powers of 1024) or `KB`, `MB`, `GB`, `TB` (powers of 1000), e.g.
/// `8GiB`, `512M`, `1.5G`, `2000000000`.
pub fn parse_size(s: &str) -> Result<u64, String> {
    let t = s.trim();
    let split = t
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .unwrap_or(t.len());
    let (num, unit) = t.split_at(split);
    let v: f64 = num
        .parse()
        .map_err(|_| format!("`{s}` is not a size; write e.g. 8GiB, 512MiB or 2000000000"))?;
    let k: f64 = match unit.trim().to_ascii_lowercase().as_str() {
        "" | "b" => 1.0,
        "k" | "kib" => 1024.0,
        "m" | "mib" => 1024f64.powi(2),
        "g" | "gib" => 1024f64.powi(3),
        "t" | "tib" => 1024f64.powi(4),
        "kb" => 1e3,
        "mb" => 1e6,
        "gb" => 1e9,
        "tb" => 1e12,
        u => {
            return Err(format!(
                "unknown unit `{u}` in `{s}`; use KiB, MiB, GiB or TiB"
            ))
        }
    };
    let bytes = v * k;
    if !(bytes.is_finite() && bytes >= 1.0 && bytes < 2f64.powi(63)) {
        return Err(format!("`{s}` is not a usable memory size"));
    }
    Ok(bytes as u64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes() {
        assert_eq!(parse_size("8GiB"), Ok(8 << 30));
        assert_eq!(parse_size("512M"), Ok(512 << 20));
        assert_eq!(parse_size("1.5g"), Ok(3 << 29));
        assert_eq!(parse_size("2GB"), Ok(2_000_000_000));
        assert_eq!(parse_size("4096"), Ok(4096));
        assert!(parse_size("8 parsecs").is_err());
        assert!(parse_size("0").is_err());
        assert!(parse_size("-1G").is_err());
        assert!(parse_size("1e400").is_err());
        assert_eq!(human(3 << 29), "1.5 GiB");
    }

    /// The documented largest film, with the default 47 bands: 2^30 pixels × 53 f32 channels
    /// × 3 (the film, the EXR encoder's copy, its compressed blocks) = 2^30 × 636 B = 636 GiB,
    /// counted by hand from the allocations listed in the module docs.
    #[test]
    fn largest_film_is_hundreds_of_gib() {
        let e = estimate(&Plan {
            width: 32768,
            height: 32768,
            slots: 50,
            channels: 53,
            caustics: false,
            lanes: 8,
            threads: 2,
            prims: 0,
        });
        assert_eq!(e.parts[0].1, (1u64 << 30) * 53 * 4 * 3);
        assert!(
            human(e.total()).starts_with("636.0 GiB"),
            "{}",
            human(e.total())
        );
    }
}
