//! The coefficient table: its fit over a grid of colours of an RGB space (continuation from
//! neighbour to neighbour, columns in parallel) and its binary form.

use super::FitData;
use std::sync::atomic::{AtomicUsize, Ordering};

/// The fitted table. Entry `(i, zi, yi, xi)` holds, in nm coefficients, the spectrum of the
/// colour whose largest component `i` is `scale[zi]` and whose next components (cyclically) are
/// `xi / (res - 1)` and `yi / (res - 1)` times it.
#[derive(Debug, Clone, PartialEq)]
pub struct CoeffTable {
    pub res: usize,
    /// The z sample positions, denser near 0 and 1 where spectra change fastest.
    pub scale: Vec<f32>,
    /// `data[(((i * res + zi) * res + yi) * res + xi) * 3 + c]`.
    pub data: Vec<f32>,
}

/// Identifies the binary format (and its version) of [`CoeffTable::to_bytes`].
const MAGIC: &[u8; 8] = b"PRSMSIG1";

impl CoeffTable {
    /// Serialises as: magic, `res` (u32), `scale`, `data` — all little-endian.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(12 + 4 * (self.scale.len() + self.data.len()));
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&(self.res as u32).to_le_bytes());
        for v in self.scale.iter().chain(&self.data) {
            out.extend_from_slice(&v.to_le_bytes());
        }
        out
    }

    /// Inverse of [`CoeffTable::to_bytes`]; checks the magic and that the size matches `res`.
    pub fn from_bytes(bytes: &[u8]) -> Result<CoeffTable, String> {
        if bytes.len() < 12 || &bytes[..8] != MAGIC {
            return Err("not a prism sigmoid coefficient table (bad magic)".into());
        }
        let res = u32::from_le_bytes(bytes[8..12].try_into().unwrap()) as usize;
        let (n_scale, n_data) = (res, 9 * res * res * res);
        if res < 2 || bytes.len() != 12 + 4 * (n_scale + n_data) {
            return Err(format!(
                "coefficient table: size {} does not match res {res}",
                bytes.len()
            ));
        }
        let floats: Vec<f32> = bytes[12..]
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
            .collect();
        Ok(CoeffTable {
            res,
            scale: floats[..n_scale].to_vec(),
            data: floats[n_scale..].to_vec(),
        })
    }
}

fn smoothstep(x: f64) -> f64 {
    x * x * (3.0 - 2.0 * x)
}

/// The z positions of the table: `smoothstep(smoothstep(k / (res - 1)))`.
pub fn scale(res: usize) -> Vec<f64> {
    (0..res)
        .map(|k| smoothstep(smoothstep(k as f64 / (res - 1) as f64)))
        .collect()
}

/// Fits the whole table. The 3 × `res` columns (i, xi) are independent and distributed over
/// `available_parallelism` threads; within a column, each solution starts from its neighbour's
/// (continuation), so Newton needs only a few iterations per entry. The result does not depend
/// on the thread count.
pub fn fit_table(data: &FitData, res: usize) -> CoeffTable {
    assert!(res >= 2, "table resolution must be at least 2");
    let scale = scale(res);
    let n_jobs = 3 * res;
    let next = AtomicUsize::new(0);
    let threads = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(n_jobs);
    let columns: Vec<(usize, Vec<[f32; 3]>)> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..threads)
            .map(|_| {
                s.spawn(|| {
                    let mut done = Vec::new();
                    loop {
                        let job = next.fetch_add(1, Ordering::Relaxed);
                        if job >= n_jobs {
                            break done;
                        }
                        done.push((job, fit_column(data, &scale, job / res, job % res)));
                    }
                })
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().expect("fit thread panicked"))
            .collect()
    });
    let mut table = vec![0.0f32; 9 * res * res * res];
    for (job, column) in columns {
        let (i, xi) = (job / res, job % res);
        for zi in 0..res {
            for yi in 0..res {
                let at = (((i * res + zi) * res + yi) * res + xi) * 3;
                table[at..at + 3].copy_from_slice(&column[zi * res + yi]);
            }
        }
    }
    CoeffTable {
        res,
        scale: scale.iter().map(|&v| v as f32).collect(),
        data: table,
    }
}

/// Fits the entries (zi, yi) of column (i, xi); returns nm coefficients indexed `zi * res + yi`.
fn fit_column(data: &FitData, scale: &[f64], i: usize, xi: usize) -> Vec<[f32; 3]> {
    let res = scale.len();
    // Continuation starts at a dark-but-not-black z, where the flat start (c = 0) is close
    // enough for Newton, then walks up and down in z.
    let start = res / 5;
    let x = xi as f64 / (res - 1) as f64;
    let mut out = vec![[0.0f32; 3]; res * res];
    // The start entry of each y row seeds the next row's start entry.
    let mut seed = [0.0; 3];
    for yi in 0..res {
        let y = yi as f64 / (res - 1) as f64;
        let mut solve = |zi: usize, from: [f64; 3]| {
            let z = scale[zi];
            let mut rgb = [0.0; 3];
            rgb[i] = z;
            rgb[(i + 1) % 3] = x * z;
            rgb[(i + 2) % 3] = y * z;
            let c = data.fit_one(rgb, from).coeffs;
            out[zi * res + yi] = FitData::to_nm(c).map(|v| v as f32);
            c
        };
        seed = solve(start, seed);
        // Plain continuation: linear extrapolation of the last two solutions starts closer but,
        // on the gamut boundary where the coefficient bound binds, it can steer neighbouring
        // entries onto different constrained optima, which then interpolate badly.
        let mut c = seed;
        for zi in start + 1..res {
            c = solve(zi, c);
        }
        c = seed;
        for zi in (0..start).rev() {
            c = solve(zi, c);
        }
    }
    out
}
