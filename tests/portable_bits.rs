//! The same bits on another CPU: `math::portable`'s functions, and every scene under scenes/,
//! give the same bits when the C library takes its code for CPUs without FMA (a mixed
//! cluster's older nodes).
//!
//! glibc chooses an FMA or a plain variant of `cos`, `exp`, `log`, … when the program starts,
//! and the two round differently now and then (f64 `exp` and `sin` on 0.07% of arguments here,
//! f32 `cosf` on a few in 10⁷). Its tunable `glibc.cpu.hwcaps=-AVX2,-FMA` makes it choose as on
//! a CPU without them, so one machine can play both nodes: this test evaluates every portable
//! function over a sweep of arguments and renders every scene here, then again in a child
//! process of itself under the tunable, and compares the bits (tolerance: none). The child also
//! evaluates the C library's `exp` at an argument whose two variants differ: if it gives the
//! same bits as here, the tunable was ignored and the test says so rather than pass. Broken on
//! purpose (`math::portable` calling std's methods) it fails at the f64 sweeps (`exp`, `sin`,
//! `cos`, …); the scenes alone did not tell, because prism's f32 results almost never land
//! where the variants round apart, but other C libraries (macOS, aarch64) differ more.

mod common;

use common::scenes::{job, render, scenes};
use prism::integrator::packet::Simd;
use sha2::{Digest, Sha256};
use std::collections::BTreeMap;

/// Set in the child: where it writes its digests.
const CHILD: &str = "PRISM_PORTABLE_BITS_OUT";
/// glibc's FMA and plain `exp` round this argument differently (found by comparing the two).
const PROBE: f64 = -0.42563874999999995;

/// The C library's own `exp`, on purpose: the probe of which variant the process runs.
#[allow(clippy::disallowed_methods)]
fn c_library_exp(x: f64) -> u64 {
    std::hint::black_box(x).exp().to_bits()
}

/// Every portable function over 2·10⁵ arguments in its domain, for f32 and f64, hashed.
fn sweeps() -> BTreeMap<String, String> {
    use prism::math::portable as p;
    const N: u32 = 200_000;
    let mut out = BTreeMap::new();
    let mut put = |name: &str, bits: &mut dyn FnMut(f64) -> u64| {
        let mut h = Sha256::new();
        for i in 0..N {
            // Arguments over (−8, 8) and its reciprocal range, on a grid that is not binary.
            let x = -8.0 + 16.0 * (i as f64 + 0.271) / N as f64;
            h.update(bits(x).to_le_bytes());
        }
        out.insert(name.to_string(), format!("{:x}", h.finalize()));
    };
    macro_rules! one {
        ($($f:ident),*) => {$(
            put(concat!(stringify!($f), " f64"), &mut |x| p::$f(x).to_bits());
            put(concat!(stringify!($f), " f32"), &mut |x| p::$f(x as f32).to_bits() as u64);
        )*};
    }
    one!(sin, cos, tan, exp, exp2, exp_m1, cbrt, cosh, tanh, atan);
    macro_rules! unit {
        ($($f:ident),*) => {$(
            put(concat!(stringify!($f), " f64"), &mut |x| p::$f(x / 8.0).to_bits());
            put(concat!(stringify!($f), " f32"), &mut |x| p::$f((x / 8.0) as f32).to_bits() as u64);
        )*};
    }
    unit!(asin, acos, atanh);
    macro_rules! positive {
        ($($f:ident),*) => {$(
            put(concat!(stringify!($f), " f64"), &mut |x| p::$f(x.abs() + 1e-3).to_bits());
            put(concat!(stringify!($f), " f32"), &mut |x| p::$f(x.abs() as f32 + 1e-3).to_bits() as u64);
        )*};
    }
    positive!(ln, log2);
    put("sin_cos f64", &mut |x| {
        p::sin_cos(x).0.to_bits() ^ p::sin_cos(x).1.to_bits().rotate_left(7)
    });
    put("sin_cos f32", &mut |x| {
        let (s, c) = p::sin_cos(x as f32);
        (s.to_bits() as u64) << 32 | c.to_bits() as u64
    });
    put("atan2 f64", &mut |x| p::atan2(x, 1.5 - x).to_bits());
    put("atan2 f32", &mut |x| {
        p::atan2(x as f32, (1.5 - x) as f32).to_bits() as u64
    });
    put("hypot f64", &mut |x| p::hypot(x, 0.7 * x + 1.0).to_bits());
    put("hypot f32", &mut |x| {
        p::hypot(x as f32, (0.7 * x + 1.0) as f32).to_bits() as u64
    });
    put("ln_gamma f64", &mut |x| {
        p::ln_gamma(x.abs() * 40.0 + 1e-3).to_bits()
    });
    put("powf f64", &mut |x| p::powf(x.abs() + 0.01, 2.4).to_bits());
    put("powf f32", &mut |x| {
        p::powf(x.abs() as f32 + 0.01, 1.0 / 2.4).to_bits() as u64
    });
    out
}

/// A raw sensor's mosaic with noise (its Poisson and normal draws) over signals from 10⁻³ to
/// 10⁹ electrons at one DN per electron, hashed.
fn raw_mosaic() -> String {
    use prism::sensor::raw::{BayerPattern, RawModel};
    let model = RawModel {
        pattern: BayerPattern::Rggb,
        slot: 0,
        dark_e: 0.5,
        full_well: 4e9,
        read_noise: 2.5,
        gain: 1.0,
        black: 64.0,
        white: 4_294_967_295.0,
        noise: true,
    };
    let (w, h) = (256u32, 64u32);
    let means: Vec<f32> = (0..w * h * 3)
        .map(|i| 10f32.powi(i as i32 % 13 - 3) * (1.0 + (i / 39) as f32 * 1e-3))
        .collect();
    let mosaic = model.mosaic(&means, 3, w, h, 2026);
    let mut hash = Sha256::new();
    for v in mosaic.data {
        hash.update(v.to_le_bytes());
    }
    format!("{:x}", hash.finalize())
}

/// Each scene's channels (names and bits), hashed, on 2 threads with the default packets.
fn digests() -> BTreeMap<String, String> {
    let mut out = BTreeMap::new();
    for scene in scenes() {
        let Ok(j) = job(&scene, Simd::Auto) else {
            continue; // bench/mesh.ron needs its generated mesh (tools/bench)
        };
        let mut h = Sha256::new();
        for (name, bits) in render(&j, 2) {
            h.update(name.as_bytes());
            for b in bits {
                h.update(b.to_le_bytes());
            }
        }
        out.insert(scene.display().to_string(), format!("{:x}", h.finalize()));
    }
    out.insert("raw mosaic".into(), raw_mosaic());
    out
}

#[test]
fn every_scene_has_the_same_bits_when_the_c_library_runs_its_code_for_cpus_without_fma() {
    if let Ok(path) = std::env::var(CHILD) {
        let mut d = digests();
        d.extend(sweeps());
        d.insert("probe".into(), c_library_exp(PROBE).to_string());
        std::fs::write(path, serde_json::to_string(&d).unwrap()).unwrap();
        return;
    }
    if !cfg!(all(
        target_os = "linux",
        target_env = "gnu",
        target_arch = "x86_64"
    )) {
        eprintln!("skipping: the variant switch is glibc's on x86-64");
        return;
    }
    #[cfg(target_arch = "x86_64")]
    if !std::is_x86_feature_detected!("fma") {
        eprintln!("skipping: this CPU has no FMA, so the C library already runs its plain code");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("digests.json");
    let status = std::process::Command::new(std::env::current_exe().unwrap())
        .args([
            "every_scene_has_the_same_bits_when_the_c_library_runs_its_code_for_cpus_without_fma",
            "--exact",
            "--test-threads=1",
        ])
        .env(CHILD, &out)
        .env(
            "GLIBC_TUNABLES",
            "glibc.cpu.hwcaps=-AVX2_Usable,-FMA_Usable,-AVX2,-FMA",
        )
        .status()
        .unwrap();
    assert!(status.success(), "the child render failed: {status}");
    let mut theirs: BTreeMap<String, String> =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let probe = theirs.remove("probe").unwrap();
    if probe == c_library_exp(PROBE).to_string() {
        // A C library that ignores the tunable (or runs one variant only) cannot play the
        // other node: say so loudly instead of passing on a comparison of equals.
        eprintln!(
            "skipping: GLIBC_TUNABLES was ignored (the C library's exp is the same in the child)"
        );
        return;
    }
    let mut ours = digests();
    assert!(ours.len() >= 25, "only {} scenes rendered", ours.len());
    ours.extend(sweeps());
    let differ: Vec<&String> = ours
        .iter()
        .filter(|(scene, d)| theirs.get(*scene) != Some(d))
        .map(|(scene, _)| scene)
        .collect();
    assert!(
        differ.is_empty(),
        "{} of {} functions and scenes have other bits where the C library runs its code for \
         CPUs without FMA: {differ:?}",
        differ.len(),
        ours.len()
    );
}
