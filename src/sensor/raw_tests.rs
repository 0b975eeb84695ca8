//! Tests of the raw sensor model (raw.rs): per-site flat-field moments and Poisson counts against
//! their closed forms, clipping, the Bayer mosaic and seeded, thread-independent noise.

use super::*;
use crate::math::chi2::{chi2_test, ln_gamma};
use crate::math::portable;

fn model(pattern: BayerPattern) -> RawModel {
    RawModel {
        pattern,
        slot: 0,
        dark_e: 5.0,
        full_well: 30000.0,
        read_noise: 3.0,
        gain: 0.4,
        black: 512.0,
        white: 16383.0,
        noise: true,
    }
}

/// A flat field: every pixel's three slots hold `s`.
fn flat(s: [f32; 3], n: usize) -> Vec<f32> {
    (0..n).flat_map(|_| s).collect()
}

/// Per Bayer site (0..4, row-major in the 2×2 tile): the values there.
fn sites(data: &[u32], width: usize) -> [Vec<f64>; 4] {
    let mut out: [Vec<f64>; 4] = Default::default();
    for (i, &v) in data.iter().enumerate() {
        let (x, y) = (i % width, i / width);
        out[(y & 1) * 2 + (x & 1)].push(v as f64);
    }
    out
}

/// Sample mean, variance, and their standard errors (√(s²/M); √((m4 − s⁴)/M), m4 the
/// sample fourth central moment).
fn moments(v: &[f64]) -> (f64, f64, f64, f64) {
    let m = v.len() as f64;
    let mean = v.iter().sum::<f64>() / m;
    let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (m - 1.0);
    let m4 = v.iter().map(|x| (x - mean).powi(4)).sum::<f64>() / m;
    (mean, var, (var / m).sqrt(), ((m4 - var * var) / m).sqrt())
}

/// Each site's DN mean and variance on a flat field against the closed forms of the module
/// docs (mean g(S+D)+b, variance g²(S+D+σ²)+1/12), within 4 standard errors each (16384
/// pixels per site; 4σ: a false alarm per check of 6e-5), for a bright and a dark field.
#[test]
fn flat_field_mean_and_variance_per_site() {
    let (w, h) = (256u32, 256u32);
    for (signal, gain, read) in [
        ([2000.0, 5000.0, 800.0], 0.4, 3.0),
        ([3.0, 10.0, 1.0], 2.0, 1.5),
    ] {
        let m = RawModel {
            gain,
            read_noise: read,
            ..model(BayerPattern::Rggb)
        };
        let raw = m.mosaic(&flat(signal, (w * h) as usize), 3, w, h, 11);
        // RGGB: sites 0 R, 1 and 2 G, 3 B.
        for (site, v) in sites(&raw.data, w as usize).iter().enumerate() {
            let s = signal[[0, 1, 1, 2][site]] as f64;
            let want_mean = gain * (s + m.dark_e) + m.black;
            let want_var = gain * gain * (s + m.dark_e + read * read) + 1.0 / 12.0;
            let (mean, var, se_mean, se_var) = moments(v);
            assert!(
                (mean - want_mean).abs() < 4.0 * se_mean,
                "site {site}, S {s}: mean {mean} vs {want_mean} (se {se_mean})"
            );
            assert!(
                (var - want_var).abs() < 4.0 * se_var,
                "site {site}, S {s}: var {var} vs {want_var} (se {se_var})"
            );
        }
    }
}

/// Gain 1, no read noise, no black level: the DN are the electron counts, whose histogram
/// must be Poisson(4.5) (the pmf from its closed form; chi-square p > 1e-3 over 65536
/// pixels).
#[test]
fn counts_are_poisson() {
    let m = RawModel {
        dark_e: 0.5,
        read_noise: 0.0,
        gain: 1.0,
        black: 0.0,
        ..model(BayerPattern::Rggb)
    };
    let (w, h) = (256u32, 256u32);
    let raw = m.mosaic(&flat([4.0; 3], (w * h) as usize), 3, w, h, 3);
    let lambda: f64 = 4.5;
    let kmax = 14;
    let mut observed = vec![0.0; kmax + 1];
    for &v in &raw.data {
        observed[(v as usize).min(kmax)] += 1.0;
    }
    let n = raw.data.len() as f64;
    let pmf = |k: usize| {
        portable::exp(k as f64 * portable::ln(lambda) - lambda - ln_gamma(k as f64 + 1.0))
    };
    let mut expected: Vec<f64> = (0..kmax).map(|k| n * pmf(k)).collect();
    expected.push(n - expected.iter().sum::<f64>());
    let (p, stat, dof) = chi2_test(&observed, &expected);
    assert!(p > 1e-3, "chi2 {stat} (dof {dof}), p {p}");
}

/// Past the full well the charge clips (no read noise: every DN is round(g·FW + b)); past
/// the white level the DN clamp to 2^bits − 1; a negative read-out clamps to 0.
#[test]
fn full_well_and_bit_depth_clip() {
    let m = RawModel {
        read_noise: 0.0,
        ..model(BayerPattern::Rggb)
    };
    let raw = m.mosaic(&flat([1e6, 4e4, 1e20], 64), 3, 8, 8, 1);
    assert!(raw.data.iter().all(|&v| v == 12512), "{:?}", &raw.data[..8]);
    let ten = RawModel {
        gain: 1.0,
        white: 1023.0,
        ..m.clone()
    };
    let raw = ten.mosaic(&flat([5000.0; 3], 64), 3, 8, 8, 1);
    assert!(raw.data.iter().all(|&v| v == 1023));
    let dark = RawModel {
        black: 0.0,
        dark_e: 0.0,
        read_noise: 50.0,
        ..m
    };
    let raw = dark.mosaic(&flat([0.0; 3], 4096), 3, 64, 64, 1);
    let zeros = raw.data.iter().filter(|&&v| v == 0).count();
    // About half the read-outs are negative (then 0); none wraps around.
    assert!(zeros > 1700 && zeros < 2400, "{zeros}");
    assert!(raw.data.iter().all(|&v| v < 100));
}

/// Without noise each pixel reads its own site's channel: R, G, B differ by decades, so
/// the DN tells which one was read; the expected tile comes from the pattern's name.
#[test]
fn mosaic_picks_each_sites_channel() {
    let s = [10000.0f32, 1000.0, 100.0];
    for p in BayerPattern::ALL {
        let m = RawModel {
            noise: false,
            gain: 1.0,
            black: 0.0,
            dark_e: 0.0,
            ..model(p)
        };
        let raw = m.mosaic(&flat(s, 48), 3, 8, 6, 1);
        let name = pattern_name(p).as_bytes();
        for (i, &v) in raw.data.iter().enumerate() {
            let (x, y) = (i % 8, i / 8);
            let want = match name[(y % 2) * 2 + x % 2] {
                b'R' => 10000,
                b'G' => 1000,
                _ => 100,
            };
            assert_eq!(v, want, "{p:?} at ({x}, {y})");
        }
    }
}

/// The same seed gives the same bits at 1 and 3 threads; another seed other noise.
#[test]
fn noise_is_seeded_and_thread_independent() {
    let m = model(BayerPattern::Gbrg);
    let means = flat([800.0, 1200.0, 300.0], 97 * 31);
    let at = |threads: usize, seed: u64| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| m.mosaic(&means, 3, 97, 31, seed))
    };
    let one = at(1, 5);
    assert_eq!(one, at(3, 5));
    let other = at(3, 6);
    let differ = one
        .data
        .iter()
        .zip(&other.data)
        .filter(|(a, b)| a != b)
        .count();
    assert!(differ > one.data.len() * 9 / 10, "{differ}");
}
