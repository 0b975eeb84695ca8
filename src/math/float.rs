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

/// ⌊x⌋, exactly as `f32::floor` (signed zeros, NaN and infinities included, tested), inline:
/// `f32::floor` is a call to libm's `floorf` on baseline x86-64 (SSE4.1's `roundss` is not
/// baseline), one per texel axis of every texture and environment-map lookup.
#[inline(always)]
pub fn floor(x: f32) -> f32 {
    // From 2²³ on every f32 is an integer (NaN and ±∞ pass through here too).
    if x.abs() >= 8_388_608.0 || x.is_nan() {
        return x;
    }
    // Truncation, with the sign of x kept (−0.3 truncates to −0).
    let t = (x as i32 as f32).copysign(x);
    if t > x {
        t - 1.0
    } else {
        t
    }
}

/// `i` wrapped into [0, n) (`rem_euclid`), without the 64-bit division where it is in range
/// already, as texel and map-column indices nearly always are.
#[inline(always)]
pub fn wrap_index(i: i64, n: usize) -> usize {
    if (0..n as i64).contains(&i) {
        i as usize
    } else {
        i.rem_euclid(n as i64) as usize
    }
}

#[cfg(test)]
mod floor_tests {
    /// Every f32 near the integers up to 2²⁴ and beyond, signed zeros, tiny values, the
    /// largest finite ones, infinities and NaN: the same bits as `f32::floor`.
    #[test]
    fn floor_is_f32_floor_bit_for_bit() {
        let mut xs = vec![
            0.0f32,
            -0.0,
            1e-45,
            -1e-45,
            f32::MAX,
            f32::MIN,
            f32::INFINITY,
        ];
        xs.extend([
            f32::NEG_INFINITY,
            f32::NAN,
            0.3,
            -0.3,
            8_388_607.5,
            -8_388_607.5,
        ]);
        for k in (-20_000_000i64..20_000_000).step_by(9_973).chain(-300..300) {
            let v = k as f32;
            xs.extend([v, v.next_up(), v.next_down(), v + 0.5, v - 0.5]);
        }
        for x in xs {
            assert_eq!(super::floor(x).to_bits(), x.floor().to_bits(), "{x}");
        }
    }

    #[test]
    fn wrap_index_is_rem_euclid() {
        for n in [1usize, 2, 7, 128] {
            for i in -300i64..300 {
                assert_eq!(super::wrap_index(i, n), i.rem_euclid(n as i64) as usize);
            }
        }
    }
}
