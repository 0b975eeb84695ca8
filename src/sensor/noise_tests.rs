//! Tests of the raw sensor's draws (noise.rs) against their closed forms: chi-square of the
//! Poisson counts against the pmf at means on both sides of the inversion/PTRS switch, moments
//! where the count is too wide to bin, and chi-square of the normal against its cdf. Each test
//! draws a fixed-seed sample; p > 1e-3 is the bar (a correct sampler fails one with probability
//! 1e-3, and the seeds are fixed, so a pass stays a pass).

use super::*;
use crate::math::chi2::chi2_test;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

const DRAWS: usize = 200_000;

/// ln of the Poisson pmf at k.
fn ln_pmf(mean: f64, k: f64) -> f64 {
    -mean + k * portable::ln(mean) - portable::ln_gamma(k + 1.0)
}

#[test]
fn counts_follow_the_poisson_pmf() {
    // Tiny, small, on both sides of the switch at 10, and large means.
    for (i, mean) in [0.05f64, 1.0, 4.5, 9.99, 10.0, 25.0, 300.0, 1e5]
        .into_iter()
        .enumerate()
    {
        let mut rng = ChaCha8Rng::seed_from_u64(100 + i as u64);
        let top = (mean + 12.0 * mean.sqrt() + 20.0) as usize;
        let mut observed = vec![0.0; top + 1];
        for _ in 0..DRAWS {
            let k = poisson(mean, &mut rng);
            assert!(
                k >= 0.0 && k.fract() == 0.0,
                "mean {mean}: {k} is not a count"
            );
            observed[(k as usize).min(top)] += 1.0;
        }
        let mut expected: Vec<f64> = (0..top)
            .map(|k| DRAWS as f64 * portable::exp(ln_pmf(mean, k as f64)))
            .collect();
        // The last cell takes the tail.
        expected.push((DRAWS as f64 - expected.iter().sum::<f64>()).max(0.0));
        let (p, stat, dof) = chi2_test(&observed, &expected);
        assert!(p > 1e-3, "mean {mean}: chi2 {stat} (dof {dof}), p {p}");
    }
}

#[test]
fn huge_means_have_the_poisson_moments() {
    // Mean and variance μ; the sample mean's standard error is √(μ/M), the variance's
    // √((μ + 2μ²)/M) (fourth central moment μ + 3μ²). Within 5 of them.
    for (i, mean) in [1e7f64, 1e9, 1e12].into_iter().enumerate() {
        let mut rng = ChaCha8Rng::seed_from_u64(200 + i as u64);
        let v: Vec<f64> = (0..DRAWS).map(|_| poisson(mean, &mut rng)).collect();
        let m = DRAWS as f64;
        let avg = v.iter().sum::<f64>() / m;
        let var = v.iter().map(|x| (x - avg) * (x - avg)).sum::<f64>() / (m - 1.0);
        let se_mean = (mean / m).sqrt();
        let se_var = ((mean + 2.0 * mean * mean) / m).sqrt();
        assert!(
            (avg - mean).abs() < 5.0 * se_mean,
            "mean {mean}: sample mean {avg}"
        );
        assert!(
            (var - mean).abs() < 5.0 * se_var,
            "mean {mean}: sample variance {var}"
        );
    }
}

#[test]
fn normal_follows_its_cdf() {
    let mut rng = ChaCha8Rng::seed_from_u64(300);
    // Cells of width ¼ over ±5, and the two tails.
    let edges: Vec<f64> = (-20..=20).map(|k| k as f64 * 0.25).collect();
    let cdf = |x: f64| 0.5 * (1.0 + libm::erf(x / std::f64::consts::SQRT_2));
    let mut observed = vec![0.0; edges.len() + 1];
    let (mut sum, mut sum2) = (0.0, 0.0);
    for _ in 0..DRAWS {
        let x = standard_normal(&mut rng);
        assert!(x.is_finite());
        observed[edges.partition_point(|&e| e <= x)] += 1.0;
        sum += x;
        sum2 += x * x;
    }
    let mut expected = Vec::with_capacity(observed.len());
    let mut below = 0.0;
    for &e in &edges {
        expected.push(DRAWS as f64 * (cdf(e) - below));
        below = cdf(e);
    }
    expected.push(DRAWS as f64 * (1.0 - below));
    let (p, stat, dof) = chi2_test(&observed, &expected);
    assert!(p > 1e-3, "chi2 {stat} (dof {dof}), p {p}");
    let m = DRAWS as f64;
    // Mean 0 (se 1/√M) and variance 1 (se √(2/M)), within 5 of them.
    assert!((sum / m).abs() < 5.0 / m.sqrt());
    assert!((sum2 / m - 1.0).abs() < 5.0 * (2.0 / m).sqrt());
}

#[test]
fn draws_repeat_for_a_seed() {
    let draw = |seed| {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        [
            poisson(3.0, &mut rng),
            poisson(1e4, &mut rng),
            standard_normal(&mut rng),
        ]
    };
    assert_eq!(draw(7).map(f64::to_bits), draw(7).map(f64::to_bits));
    assert_ne!(draw(7).map(f64::to_bits), draw(8).map(f64::to_bits));
}
