//! The raw sensor's random draws, Poisson photo-electron counts and normal read noise, made
//! with `math::portable`'s functions and IEEE arithmetic only, so a mosaic has the same bits on
//! every CPU and C library (rand_distr's samplers reach the host's `exp` and `ln` through
//! num-traits, whose `std` feature another dependency switches on). The uniform numbers come
//! from the caller's generator (ChaCha8 in raw.rs), which is integer arithmetic.
//!
//! Poisson: below a mean of 10, inversion by sequential search (Devroye, "Non-Uniform Random
//! Variate Generation", 1986, X.3.3: the pmf by its recurrence p(k + 1) = p(k) μ / (k + 1));
//! from 10 up, Hörmann's transformed rejection with squeeze, PTRS (W. Hörmann, "The transformed
//! rejection method for generating Poisson random variables", Insurance: Mathematics and
//! Economics 12 (1993) 39–45; its constants as published), under 1.2 uniform pairs a draw.
//! Normal: Marsaglia's polar method (Marsaglia & Bray, SIAM Review 6 (1964) 260–264).

use crate::math::portable;
use rand::Rng;

/// Means below this are drawn by inversion (PTRS is valid from 10 up).
const INVERSION_BELOW: f64 = 10.0;

/// A Poisson count of mean `mean` (> 0 and finite), as an f64 (exact below 2^53).
pub fn poisson<R: Rng + ?Sized>(mean: f64, rng: &mut R) -> f64 {
    debug_assert!(mean > 0.0 && mean.is_finite());
    if mean < INVERSION_BELOW {
        inversion(mean, rng)
    } else {
        ptrs(mean, rng)
    }
}

/// The smallest k whose cdf reaches a uniform u. Past the point where the cdf stops growing in
/// f64 (about 10⁻¹⁶ of mass left) it stops there rather than loop.
fn inversion<R: Rng + ?Sized>(mean: f64, rng: &mut R) -> f64 {
    let u: f64 = rng.random();
    let mut p = portable::exp(-mean);
    let mut cdf = p;
    let mut k = 0u32;
    while u > cdf {
        k += 1;
        p *= mean / k as f64;
        let next = cdf + p;
        if next == cdf {
            break;
        }
        cdf = next;
    }
    k as f64
}

/// Hörmann's PTRS.
fn ptrs<R: Rng + ?Sized>(mean: f64, rng: &mut R) -> f64 {
    let slam = mean.sqrt();
    let loglam = portable::ln(mean);
    let b = 0.931 + 2.53 * slam;
    let a = -0.059 + 0.02483 * b;
    let inv_alpha = 1.1239 + 1.1328 / (b - 3.4);
    let vr = 0.9277 - 3.6224 / (b - 2.0);
    let ln_inv_alpha = portable::ln(inv_alpha);
    loop {
        let u = rng.random::<f64>() - 0.5;
        let v: f64 = rng.random();
        let us = 0.5 - u.abs();
        let k = ((2.0 * a / us + b) * u + mean + 0.43).floor();
        // The squeeze: most draws end here.
        if us >= 0.07 && v <= vr {
            return k;
        }
        // NaN: us = 0 (u = −½) makes 2a/us infinite.
        if k.is_nan() || k < 0.0 || (us < 0.013 && v > us) {
            continue;
        }
        let lhs = portable::ln(v) + ln_inv_alpha - portable::ln(a / (us * us) + b);
        if lhs <= -mean + k * loglam - portable::ln_gamma(k + 1.0) {
            return k;
        }
    }
}

/// A standard normal number.
pub fn standard_normal<R: Rng + ?Sized>(rng: &mut R) -> f64 {
    loop {
        let x = 2.0 * rng.random::<f64>() - 1.0;
        let y = 2.0 * rng.random::<f64>() - 1.0;
        let s = x * x + y * y;
        if s > 0.0 && s < 1.0 {
            return x * (-2.0 * portable::ln(s) / s).sqrt();
        }
    }
}

#[cfg(test)]
#[path = "noise_tests.rs"]
mod tests;
