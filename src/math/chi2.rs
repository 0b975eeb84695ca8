//! Pearson's chi-square goodness-of-fit test and the incomplete gamma function behind its
//! p-value, for the statistical tests of every sampling routine (the crate's own unit tests and
//! tests/). Written here because the test suites need only these few functions, not a
//! statistics crate.

use crate::math::portable;
/// ln Γ(x) for x > 0 (Lanczos approximation, g = 7, n = 9; relative error < 1e-13).
pub fn ln_gamma(x: f64) -> f64 {
    const G: f64 = 7.0;
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        return portable::ln(std::f64::consts::PI / portable::sin(std::f64::consts::PI * x))
            - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut a = C[0];
    let t = x + G + 0.5;
    for (i, c) in C.iter().enumerate().skip(1) {
        a += c / (x + i as f64);
    }
    0.5 * portable::ln(2.0 * std::f64::consts::PI) + (x + 0.5) * portable::ln(t) - t
        + portable::ln(a)
}

/// Regularised upper incomplete gamma Q(a, x) = Γ(a, x) / Γ(a): series for x < a + 1, Lentz's
/// continued fraction otherwise (both converge fast in their regions).
pub fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    let ln_pre = -x + a * portable::ln(x) - ln_gamma(a);
    if x < a + 1.0 {
        let (mut sum, mut term, mut ap) = (1.0 / a, 1.0 / a, a);
        for _ in 0..10_000 {
            ap += 1.0;
            term *= x / ap;
            sum += term;
            if term.abs() < sum.abs() * 1e-15 {
                break;
            }
        }
        1.0 - sum * portable::exp(ln_pre)
    } else {
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..10_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let delta = d * c;
            h *= delta;
            if (delta - 1.0).abs() < 1e-15 {
                break;
            }
        }
        portable::exp(ln_pre) * h
    }
}

/// P(χ²_dof ≥ stat).
pub fn chi2_sf(stat: f64, dof: f64) -> f64 {
    gamma_q(0.5 * dof, 0.5 * stat)
}

/// Pearson's test of observed counts against expected counts. Cells expecting fewer than 5
/// samples (zero included) are pooled into one cell (the χ² approximation needs ≥ 5 per cell).
/// Returns (p-value, statistic, degrees of freedom).
pub fn chi2_test(observed: &[f64], expected: &[f64]) -> (f64, f64, usize) {
    assert_eq!(observed.len(), expected.len());
    let mut stat = 0.0;
    let mut cells = 0usize;
    let (mut pool_o, mut pool_e) = (0.0, 0.0);
    for (&o, &e) in observed.iter().zip(expected) {
        if e < 5.0 {
            pool_o += o;
            pool_e += e;
        } else {
            stat += (o - e) * (o - e) / e;
            cells += 1;
        }
    }
    if pool_e > 0.0 {
        stat += (pool_o - pool_e) * (pool_o - pool_e) / pool_e;
        cells += 1;
    } else if pool_o > 0.0 {
        return (0.0, f64::INFINITY, 0);
    }
    let dof = cells.saturating_sub(1).max(1);
    (chi2_sf(stat, dof as f64), stat, dof)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chi2_tail_matches_tables() {
        // Tabulated critical values: P(χ²₁ ≥ 3.841) = 0.05, P(χ²₁₀ ≥ 23.209) = 0.01,
        // P(χ²₁₀₀ ≥ 124.342) = 0.05.
        assert!((chi2_sf(3.841, 1.0) - 0.05).abs() < 1e-4);
        assert!((chi2_sf(23.209, 10.0) - 0.01).abs() < 1e-4);
        assert!((chi2_sf(124.342, 100.0) - 0.05).abs() < 1e-4);
    }
}
