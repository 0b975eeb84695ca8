//! Sine and cosine of the angles samplers make: a fraction of a turn (2π u, the azimuth of
//! every direction warp) or of an eighth of one (π t / 4, the concentric disk map's angle); and
//! the way back, a direction's angle in turns (an environment map's or a sphere's uv).
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

/// atan(a) / 2π for a in [0, 1]: a minimax polynomial in a² (fitted as `sin_cos_eighth`'s),
/// within 3.2·10⁻⁸ turns of the true value in f32.
#[inline(always)]
fn atan_turns_unit(a: f32) -> f32 {
    let z = a * a;
    let p = -7.469_771_7e-4;
    let p = 3.859_951_9e-3 + z * p;
    let p = -9.467_632_5e-3 + z * p;
    let p = 1.577_913_6e-2 + z * p;
    let p = -2.231_271_2e-2 + z * p;
    let p = 3.178_280_6e-2 + z * p;
    let p = -5.304_951_2e-2 + z * p;
    a * (0.159_154_92 + z * p)
}

/// The angle of (x, y) in turns, in [−½, ½]: `atan2(y, x) / 2π` within 8·10⁻⁸ turns, without
/// the library's branches on the octant (0 at the origin, NaN for NaN and for two infinities).
#[inline(always)]
pub fn atan2_turns(y: f32, x: f32) -> f32 {
    let (ax, ay) = (x.abs(), y.abs());
    // The smaller over the larger, so the polynomial sees [0, 1].
    let steep = ay > ax;
    let (n, d) = if steep { (ax, ay) } else { (ay, ax) };
    let a = if d == 0.0 { 0.0 } else { n / d };
    let t = atan_turns_unit(a);
    let t = if steep { 0.25 - t } else { t };
    let t = if x < 0.0 { 0.5 - t } else { t };
    if y < 0.0 {
        -t
    } else {
        t
    }
}

/// `atan2_turns` moved to [0, 1]: an azimuth as a texture coordinate (1 only where a tiny
/// negative angle rounds up).
#[inline(always)]
pub fn azimuth_turns(y: f32, x: f32) -> f32 {
    let t = atan2_turns(y, x);
    if t < 0.0 {
        t + 1.0
    } else {
        t
    }
}

/// acos(c) / π for c in [−1, 1] (a polar angle as a fraction of half a turn), as the angle of
/// (c, √((1 − c)(1 + c))): accurate near the poles, where 1 − c² would cancel.
#[inline(always)]
pub fn acos_half_turns(c: f32) -> f32 {
    let c = c.clamp(-1.0, 1.0);
    2.0 * atan2_turns(((1.0 - c) * (1.0 + c)).sqrt(), c)
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

    #[test]
    fn angles_in_turns_match_f64_in_every_octant() {
        // Points on circles of radius 1e-30 to 1e30 every 2π/2¹⁶, the axes and the diagonals
        // (octant edges) with their neighbours: within 8·10⁻⁸ turns (the fit's 3.2·10⁻⁸ and
        // two roundings of the octant's 0.25 − t and 0.5 − t, each at most 1.5·10⁻⁸).
        let n = 1 << 16;
        let mut pts = Vec::new();
        for r in [1e-30f32, 1e-3, 1.0, 7.5, 1e30] {
            for i in 0..n {
                let (s, c) = portable::sin_cos(2.0 * std::f64::consts::PI * i as f64 / n as f64);
                pts.push(((r as f64 * s) as f32, (r as f64 * c) as f32));
            }
        }
        for (y, x) in [(1.0f32, 1.0f32), (0.0, 1.0), (1.0, 0.0)] {
            for sy in [1.0, -1.0] {
                for sx in [1.0, -1.0] {
                    pts.push((sy * y, sx * x));
                    pts.push((sy * y * (1.0 + f32::EPSILON), sx * x));
                    pts.push((sy * y, sx * x * (1.0 + f32::EPSILON)));
                }
            }
        }
        for (y, x) in pts {
            let want = portable::atan2(y as f64, x as f64) / (2.0 * std::f64::consts::PI);
            let got = atan2_turns(y, x) as f64;
            // ±½ turn is one angle: compare on the circle.
            let d = (got - want).abs().min(1.0 - (got - want).abs());
            assert!(d <= 8e-8, "atan2({y}, {x}): {got} vs {want} turns");
        }
        assert_eq!(atan2_turns(0.0, 0.0), 0.0);
        assert!(atan2_turns(f32::NAN, 1.0).is_nan() && atan2_turns(1.0, f32::NAN).is_nan());
    }

    #[test]
    fn polar_angles_match_f64_up_to_the_poles() {
        // Every 2⁻²⁰ of [−1, 1] and the floats next to ±1, within 1.6·10⁻⁷ half turns (twice
        // `atan2_turns`'s bound, as the result is doubled); out of range clamps.
        let n = 1 << 20;
        let near_poles = (1..64).flat_map(|k| {
            let c = 1.0 - k as f32 * f32::EPSILON / 2.0;
            [c, -c]
        });
        for c in (-n..=n).map(|i| i as f32 / n as f32).chain(near_poles) {
            let want = portable::acos(c as f64) / std::f64::consts::PI;
            let got = acos_half_turns(c) as f64;
            assert!(
                (got - want).abs() <= 1.6e-7,
                "acos({c}): {got} vs {want} half turns"
            );
        }
        assert_eq!(acos_half_turns(1.5), 0.0);
        assert_eq!(acos_half_turns(-1.5), 1.0);
    }
}
