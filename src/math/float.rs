//! Floating-point error bounds (Higham's γ_n) and ulp steps, used to offset ray origins off
//! surfaces by exactly as much as the hit point's rounding error, at any scene scale.

/// Unit roundoff of f32 (half an ulp of 1).
pub const MACHINE_EPSILON: f32 = f32::EPSILON * 0.5;

/// γ_n = nε / (1 − nε): bounds the relative error of n chained f32 operations.
#[inline]
pub const fn gamma(n: i32) -> f32 {
    (n as f32 * MACHINE_EPSILON) / (1.0 - n as f32 * MACHINE_EPSILON)
}

/// The next representable f32 above `v` (+∞ and NaN stay put).
#[inline(always)]
pub fn next_float_up(v: f32) -> f32 {
    if v.is_nan() || v == f32::INFINITY {
        return v;
    }
    // Integer steps on the bit pattern: +1 moves away from zero for positives, towards zero for
    // negatives; −0 and +0 both step to the smallest positive subnormal.
    let bits = v.to_bits();
    f32::from_bits(if v == 0.0 {
        1
    } else if v > 0.0 {
        bits + 1
    } else {
        bits - 1
    })
}

/// The next representable f32 below `v` (−∞ and NaN stay put).
#[inline(always)]
pub fn next_float_down(v: f32) -> f32 {
    -next_float_up(-v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ulp_steps() {
        assert!(next_float_up(1.0) > 1.0 && next_float_down(1.0) < 1.0);
        assert!(next_float_up(-1.0) > -1.0 && next_float_down(-1.0) < -1.0);
        assert!(next_float_up(0.0) > 0.0 && next_float_down(0.0) < 0.0);
        assert_eq!(next_float_up(f32::INFINITY), f32::INFINITY);
        assert!(gamma(3) > 3.0 * MACHINE_EPSILON);
    }
}
