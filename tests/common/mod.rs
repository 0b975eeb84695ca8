//! Shared test helpers: Pearson's chi-square goodness-of-fit test, and a receiving point for
//! emitter sampling.
#![allow(dead_code)]

pub mod scenes;

/// Mean and standard error of the mean of a set of values (pixels of one channel).
pub fn mean_se(data: &[f32]) -> (f64, f64) {
    let n = data.len() as f64;
    let m = data.iter().map(|&v| v as f64).sum::<f64>() / n;
    let var = data.iter().map(|&v| (v as f64 - m).powi(2)).sum::<f64>() / (n - 1.0);
    (m, (var / n).sqrt())
}

// Not every test binary uses every helper (as dead_code above).
#[allow(unused_imports)]
pub use prism::math::chi2::{chi2_sf, chi2_test, gamma_q, ln_gamma};
use prism::math::portable;

/// Significance level of each test: 1% overall, split over the `tests` a file runs (Šidák).
pub fn alpha(tests: usize) -> f64 {
    1.0 - portable::powf(1.0 - 0.01f64, 1.0 / tests as f64)
}

/// A receiving point for emitter sampling: at `p`, facing +y, on no shape.
pub fn receiver(p: glam::Vec3) -> prism::interaction::SurfaceInteraction {
    prism::interaction::SurfaceInteraction {
        p,
        p_error: glam::Vec3::ZERO,
        ng: glam::Vec3::Y,
        frame: prism::math::Frame::from_normal(glam::Vec3::Y),
        uv: glam::Vec2::ZERO,
        t: 1.0,
        shape: u32::MAX,
        prim: 0,
        time: 0.0,
        bary: glam::Vec2::ZERO,
    }
}

/// Regularised incomplete beta function I_x(a, b) (continued fraction, modified Lentz; the
/// symmetry I_x(a, b) = 1 − I_{1−x}(b, a) keeps it in its fast region).
pub fn beta_inc(a: f64, b: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    if x >= 1.0 {
        return 1.0;
    }
    if x > (a + 1.0) / (a + b + 2.0) {
        return 1.0 - beta_inc(b, a, 1.0 - x);
    }
    let ln_front = ln_gamma(a + b) - ln_gamma(a) - ln_gamma(b)
        + a * portable::ln(x)
        + b * portable::ln(1.0 - x);
    let tiny = 1e-300;
    let (mut c, mut d) = (1.0, 1.0 - (a + b) * x / (a + 1.0));
    if d.abs() < tiny {
        d = tiny;
    }
    d = 1.0 / d;
    let mut h = d;
    for m in 1..10_000 {
        let m = m as f64;
        for num in [
            m * (b - m) * x / ((a + 2.0 * m - 1.0) * (a + 2.0 * m)),
            -(a + m) * (a + b + m) * x / ((a + 2.0 * m) * (a + 2.0 * m + 1.0)),
        ] {
            d = 1.0 + num * d;
            if d.abs() < tiny {
                d = tiny;
            }
            c = 1.0 + num / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            h *= d * c;
        }
        if (d * c - 1.0).abs() < 1e-15 {
            break;
        }
    }
    portable::exp(ln_front) * h / a
}

/// Two-sided P(|T| ≥ |t|) for Student's t with `dof` degrees of freedom (any real dof > 0).
pub fn t_two_sided(t: f64, dof: f64) -> f64 {
    beta_inc(0.5 * dof, 0.5, dof / (dof + t * t))
}

/// Welch's test of two independent means with standard errors `se_a`, `se_b` from `n_a`, `n_b`
/// samples: (t, Welch–Satterthwaite degrees of freedom, two-sided p).
pub fn welch(
    mean_a: f64,
    se_a: f64,
    n_a: f64,
    mean_b: f64,
    se_b: f64,
    n_b: f64,
) -> (f64, f64, f64) {
    let (va, vb) = (se_a * se_a, se_b * se_b);
    let t = (mean_a - mean_b) / (va + vb).sqrt();
    let dof = (va + vb).powi(2) / (va * va / (n_a - 1.0) + vb * vb / (n_b - 1.0));
    (t, dof, t_two_sided(t, dof))
}

#[test]
fn t_tail_matches_tables() {
    // Two-sided 5% critical values: t(1) = 12.706, t(10) = 2.228, t(30) = 2.042; 0.1% at
    // t(7) = 5.408; and the normal limit 1.960.
    for (t, dof, p) in [
        (12.706, 1.0, 0.05),
        (2.228, 10.0, 0.05),
        (2.042, 30.0, 0.05),
        (5.408, 7.0, 0.001),
        (1.960, 1e7, 0.05),
    ] {
        let got = t_two_sided(t, dof);
        assert!(
            (got / p - 1.0).abs() < 2e-3,
            "t = {t}, dof {dof}: p = {got}, table {p}"
        );
    }
    // Equal variances and sizes: Welch's dof is 2(n − 1); one side exact: n − 1 of the other.
    let (_, dof, _) = welch(1.0, 0.1, 8.0, 1.2, 0.1, 8.0);
    assert!((dof - 14.0).abs() < 1e-9);
    let (_, dof, _) = welch(1.0, 0.0, 8.0, 1.2, 0.1, 8.0);
    assert!((dof - 7.0).abs() < 1e-9);
}

/// Peak resident memory (bytes) and exit code of a prism run, from wait4(2) (which reaps the
/// child).
#[allow(clippy::zombie_processes)]
pub fn peak_rss(args: &[&str]) -> (u64, i32) {
    let child = std::process::Command::new(env!("CARGO_BIN_EXE_prism"))
        .args(args)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let mut status = 0;
    // SAFETY: wait4 on our own child, with valid pointers to locals.
    let ru = unsafe {
        let mut ru: libc::rusage = std::mem::zeroed();
        let r = libc::wait4(child.id() as i32, &mut status, 0, &mut ru);
        assert_eq!(r, child.id() as i32);
        ru
    };
    assert!(libc::WIFEXITED(status), "prism {args:?} did not exit");
    (ru.ru_maxrss as u64 * 1024, libc::WEXITSTATUS(status))
}

/// Asserts that an instanced render's radiance channel matches its flattened twin's: finite, the
/// means within 0.2% and 97% of pixels within 0.1% (relative, or 1e-3 absolute near black). The
/// two traverse different BVHs, so hit points differ in the last float bits and a few edge
/// pixels flip between neighbours; same-seed sampling keeps everything else equal.
pub fn assert_same_radiance(instanced: &[f32], flattened: &[f32]) {
    let (ri, rf) = (instanced, flattened);
    let n = ri.len();
    assert_eq!(n, rf.len());
    assert!(ri.iter().chain(rf).all(|v| v.is_finite()));
    let mean = |v: &[f32]| v.iter().map(|&x| x as f64).sum::<f64>() / v.len() as f64;
    let (mi, mf) = (mean(ri), mean(rf));
    let close = (0..n)
        .filter(|&k| (ri[k] - rf[k]).abs() <= 1e-3 * rf[k].abs().max(1e-3))
        .count();
    eprintln!("mean R {mi} instanced, {mf} flattened; {close} of {n} pixels within 0.1%");
    assert!((mi - mf).abs() <= 2e-3 * mf, "means {mi} and {mf}");
    assert!(close * 100 >= 97 * n, "only {close} of {n} pixels agree");
}
