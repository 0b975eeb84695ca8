//! Sine and cosine of the angles samplers make: a fraction of a turn (2π u, the azimuth of
//! every direction warp) or of an eighth of one (π t / 4, the concentric disk map's angle).
//!
//! Why by hand: `libm` (musl) has no `sinpi`/`cospi`, so callers multiplied by 2π and its
//! `sincosf` reduced the product again and branched on its octant, a branch a random azimuth
//! mispredicts half the time (`sincosf` was 2.3% of a Cornell render's cycles). An angle in
//! turns reduces exactly: 4u − round(4u) is computed without rounding error, so one polynomial
//! pair on an eighth of a turn and a quadrant swap do the rest, without branches. Plain f32
//! arithmetic (no FMA, no run-time choice): the same bits on every machine and at every width.

use std::f32::consts::FRAC_PI_4;

/// (sin(π t / 4), cos(π t / 4)) for |t| ≤ 1: minimax polynomials in t² (Lawson's iteration on
/// the relative error, fitted in f64), within 1.7 ulp (sine) and 1.3 ulp (cosine) of the true
/// values when evaluated in f32 (`tests::eighth_turn_is_within_two_ulp`).
#[inline(always)]
pub fn sin_cos_eighth(t: f32) -> (f32, f32) {
    let z = t * t;
    let s = t * (FRAC_PI_4 + z * (-0.080_745_436 + z * (0.002_490_001 + z * -3.595_05e-5)));
    let c =
        1.0 + z * (-0.308_425_13 + z * (0.015_854_327 + z * (-3.259_401e-4 + z * 3.530_341e-6)));
    (s, c)
}

/// (sin 2πu, cos 2πu) for |u| < 2²⁰ (samplers pass u in [0, 1]; NaN gives NaN).
#[inline(always)]
pub fn sin_cos_turns(u: f32) -> (f32, f32) {
    // Quarter turns, rounded to the nearest by the 1.5 · 2²³ trick (exact for |x| < 2²²;
    // `f32::round` is a library call on baseline x86-64). x − q is then exact.
    const ROUND: f32 = 12_582_912.0;
    let x = 4.0 * u;
    let q = (x + ROUND) - ROUND;
    let (s, c) = sin_cos_eighth(2.0 * (x - q));
    let quadrant = q as i32;
    // sin(qπ/2 + θ), cos(qπ/2 + θ): an odd quadrant swaps the pair, quadrants 2 and 3 negate it.
    let (s, c) = if quadrant & 1 != 0 { (c, -s) } else { (s, c) };
    if quadrant & 2 != 0 {
        (-s, -c)
    } else {
        (s, c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::portable;

    /// The distance from `got` to `want` in ulps of `want` (at least the ulp of 2⁻²⁴ near 0).
    fn ulps(got: f32, want: f64) -> f64 {
        let w = want as f32;
        let ulp = (f32::from_bits(w.abs().to_bits() + 1) - w.abs()).max(f32::EPSILON / 2.0);
        (got as f64 - want).abs() / ulp as f64
    }

    #[test]
    fn eighth_turn_is_within_two_ulp() {
        // Every 2⁻²⁰ step of [-1, 1] and its end points: the fit's worst case was measured at
        // 1.7 ulp (sine) and 1.3 (cosine); 2 ulp allows nothing more.
        let n = 1 << 20;
        let (mut worst_s, mut worst_c) = (0.0f64, 0.0f64);
        for i in -n..=n {
            let t = i as f32 / n as f32;
            let (s, c) = sin_cos_eighth(t);
            let a = std::f64::consts::FRAC_PI_4 * t as f64;
            worst_s = worst_s.max(ulps(s, portable::sin(a)));
            worst_c = worst_c.max(ulps(c, portable::cos(a)));
        }
        assert!(worst_s <= 2.0, "sine {worst_s} ulp");
        assert!(worst_c <= 2.0, "cosine {worst_c} ulp");
    }

    #[test]
    fn whole_turns_match_f64_in_every_quadrant() {
        // Every 2⁻¹⁸ of [-2, 2] turns (each quadrant of both signs many times over), the quarter
        // turns themselves and their neighbouring floats: the error is the eighth turn's, as
        // the reduction is exact. Absolute error within 2 ulp of 1 (values are at most 1).
        let mut us: Vec<f32> = (-(1 << 19)..=(1 << 19))
            .map(|i| i as f32 / (1 << 18) as f32)
            .collect();
        for k in -8..=8 {
            let q = k as f32 * 0.25;
            // The floats beside q (beside 0: tiny ones).
            let d = q.abs().max(1e-30) * f32::EPSILON;
            us.extend([q, q + d, q - d, q + 0.125, q - 0.125]);
        }
        for u in us {
            let (s, c) = sin_cos_turns(u);
            let a = 2.0 * std::f64::consts::PI * u as f64;
            let tol = 2.0 * f32::EPSILON as f64;
            assert!(
                (s as f64 - portable::sin(a)).abs() <= tol,
                "sin 2π·{u}: {s} vs {}",
                portable::sin(a)
            );
            assert!(
                (c as f64 - portable::cos(a)).abs() <= tol,
                "cos 2π·{u}: {c} vs {}",
                portable::cos(a)
            );
        }
        let (s, c) = sin_cos_turns(f32::NAN);
        assert!(s.is_nan() && c.is_nan());
    }
}
