//! Four triangles tested against one ray at once (SIMD lanes), bit for bit as the scalar
//! watertight test (`shape::triangle::intersect`) would test each.

use super::{near_hit_error, RayShear};
use glam::Vec3;
use wide::{f32x4, CmpEq, CmpGe, CmpGt, CmpLe, CmpLt, CmpNe};

/// Four triangles side by side, one per SIMD lane (structure of arrays), so one ray tests all
/// four with the same instructions the scalar test runs on one. Unused lanes hold NaN vertices,
/// which no ray hits.
#[derive(Clone, Copy, Debug)]
#[repr(C)]
pub struct Triangle4 {
    /// `v[3 * vertex + axis]`: one coordinate of one vertex, for the four lanes.
    v: [f32x4; 9],
    /// The caller's id of each lane's triangle.
    pub ids: [u32; 4],
}

impl Triangle4 {
    /// Packs one to four triangles with their ids.
    pub fn new(tris: &[([Vec3; 3], u32)]) -> Self {
        assert!(
            (1..=4).contains(&tris.len()),
            "Triangle4 holds 1 to 4 triangles"
        );
        let mut v = [[f32::NAN; 4]; 9];
        let mut ids = [u32::MAX; 4];
        for (lane, (verts, id)) in tris.iter().enumerate() {
            for (k, p) in verts.iter().enumerate() {
                for axis in 0..3 {
                    v[3 * k + axis][lane] = p[axis];
                }
            }
            ids[lane] = *id;
        }
        Self {
            v: v.map(f32x4::from),
            ids,
        }
    }

    /// The vertices of the triangle in `lane`.
    #[inline]
    pub fn vertices(&self, lane: usize) -> [Vec3; 3] {
        let c = |i: usize| self.v[i].as_array_ref()[lane];
        [0, 1, 2].map(|k| Vec3::new(c(3 * k), c(3 * k + 1), c(3 * k + 2)))
    }

    /// The watertight test on all four lanes at once, with the scalar test's operations in the
    /// same order, so every lane's result is bit-identical to `intersect`'s. Lanes with an edge
    /// function exactly zero are left to the caller (`Hits4::redo`), which runs `intersect` on
    /// them for its f64 refinement; they are rare (rays through edges and vertices).
    #[inline(always)]
    pub fn intersect(&self, s: &RayShear, t_max: f32) -> Hits4 {
        let [kx, ky, kz] = s.k;
        let [ox, oy, oz] = s.o.map(f32x4::splat);
        let (sx, sy, sz) = (f32x4::splat(s.sx), f32x4::splat(s.sy), f32x4::splat(s.sz));
        let project = |vertex: usize| {
            let x = self.v[3 * vertex + kx as usize] - ox;
            let y = self.v[3 * vertex + ky as usize] - oy;
            let z = self.v[3 * vertex + kz as usize] - oz;
            (x - sx * z, y - sy * z, z)
        };
        let (ax, ay, az) = project(0);
        let (bx, by, bz) = project(1);
        let (cx, cy, cz) = project(2);
        let u = cx * by - cy * bx;
        let w_ = ax * cy - ay * cx;
        let w = bx * ay - by * ax;
        let zero = f32x4::ZERO;
        let any_zero = u.cmp_eq(zero) | w_.cmp_eq(zero) | w.cmp_eq(zero);
        let same_sign = (u.cmp_ge(zero) & w_.cmp_ge(zero) & w.cmp_ge(zero))
            | (u.cmp_le(zero) & w_.cmp_le(zero) & w.cmp_le(zero));
        let det = u + w_ + w;
        let (az, bz, cz) = (sz * az, sz * bz, sz * cz);
        let t_scaled = u * az + w_ * bz + w * cz;
        // t_scaled · sign(det), as the scalar test; exact (a sign flip).
        let ts = t_scaled ^ (det & f32x4::splat(-0.0));
        let in_range = ts.cmp_gt(zero) & ts.cmp_lt(f32x4::splat(t_max) * det.abs());
        let mut mask = (same_sign & det.cmp_ne(zero) & in_range & !any_zero).move_mask() & 0xf;
        let redo = (any_zero.move_mask() & 0xf) as u32;
        if mask == 0 {
            return Hits4 {
                mask: 0,
                redo,
                t: [0.0; 4],
                b1: [0.0; 4],
                b2: [0.0; 4],
            };
        }
        let inv = f32x4::ONE / det;
        let t = t_scaled * inv;
        let err = near_hit_error(ax, ay, bx, by, cx, cy, [az, bz, cz], [u, w_, w], inv);
        // t > 0 and not NaN, beyond its own rounding error.
        mask &= (t.cmp_gt(zero) & !t.cmp_lt(err)).move_mask();
        Hits4 {
            mask: mask as u32,
            redo,
            t: t.to_array(),
            b1: (w_ * inv).to_array(),
            b2: (w * inv).to_array(),
        }
    }
}

/// What `Triangle4::intersect` found: `mask` has bit i set where lane i is hit (at `t[i]`, with
/// barycentrics `b1[i]`, `b2[i]`); `redo` marks lanes the caller must test with `intersect`.
#[derive(Clone, Copy, Debug)]
pub struct Hits4 {
    pub mask: u32,
    pub redo: u32,
    pub t: [f32; 4],
    pub b1: [f32; 4],
    pub b2: [f32; 4],
}

/// What `Triangle4::intersect_pair_avx2` found for two packets side by side: lanes 0–3 are the
/// first packet's, 4–7 the second's, each as `Triangle4::intersect` finds it at the same
/// `t_max`. `ts` and `det_abs` let a caller that shrank `t_max` after the first packet apply
/// the in-range test (`ts < t_max · |det|`) again to the second's lanes, as testing the second
/// packet afterwards would have.
#[derive(Clone, Copy, Debug)]
pub struct Hits8 {
    pub mask: u32,
    pub redo: u32,
    pub t: [f32; 8],
    pub b1: [f32; 8],
    pub b2: [f32; 8],
    pub ts: [f32; 8],
    pub det_abs: [f32; 8],
}

#[cfg(target_arch = "x86_64")]
impl Triangle4 {
    /// `intersect` of packets `a` and `b` in one pass of 8-wide AVX instructions: every lane
    /// does `intersect`'s IEEE operations in its order (the comparisons are the same
    /// predicates, NaN included), so each lane's result is bit for bit `intersect`'s at this
    /// `t_max` (tests/accel.rs::pair_test_matches_packet_test). A leaf of two packets costs
    /// about one test instead of two.
    ///
    /// Always inlined and without `#[target_feature]` (which forbids `inline(always)`): with
    /// it, rustc kept the function out of line, a call per two-packet leaf with its 8-lane
    /// result spilled. Inlined into `Tree::traverse_avx2`, its intrinsics get AVX2 encodings;
    /// called from code compiled for the baseline they stay calls (correct, slow).
    ///
    /// # Safety
    /// The CPU must have AVX2 (`is_x86_feature_detected!("avx2")`).
    #[inline(always)]
    pub unsafe fn intersect_pair_avx2(
        a: &Triangle4,
        b: &Triangle4,
        s: &RayShear,
        t_max: f32,
    ) -> Hits8 {
        use std::arch::x86_64::*;
        // Component i of both packets as one register (a's lanes low, b's high).
        let v = |i: usize| {
            let lo = _mm_loadu_ps(a.v[i].as_array_ref().as_ptr());
            let hi = _mm_loadu_ps(b.v[i].as_array_ref().as_ptr());
            _mm256_set_m128(hi, lo)
        };
        let sp = |x: f32| _mm256_set1_ps(x);
        let mul = |x: __m256, y: __m256| _mm256_mul_ps(x, y);
        let sub = |x: __m256, y: __m256| _mm256_sub_ps(x, y);
        let add = |x: __m256, y: __m256| _mm256_add_ps(x, y);
        let and = |x: __m256, y: __m256| _mm256_and_ps(x, y);
        let or = |x: __m256, y: __m256| _mm256_or_ps(x, y);
        let [kx, ky, kz] = s.k;
        let (ox, oy, oz) = (sp(s.o[0]), sp(s.o[1]), sp(s.o[2]));
        let (sx, sy, sz) = (sp(s.sx), sp(s.sy), sp(s.sz));
        // A macro, not a closure: rustc left the closure out of line (compiled for the
        // baseline, its intrinsics calls), 64·10⁶ instructions of a Cornell render.
        macro_rules! project {
            ($vertex:expr) => {{
                let x = _mm256_sub_ps(v(3 * $vertex + kx as usize), ox);
                let y = _mm256_sub_ps(v(3 * $vertex + ky as usize), oy);
                let z = _mm256_sub_ps(v(3 * $vertex + kz as usize), oz);
                (
                    _mm256_sub_ps(x, _mm256_mul_ps(sx, z)),
                    _mm256_sub_ps(y, _mm256_mul_ps(sy, z)),
                    z,
                )
            }};
        }
        let (ax, ay, az) = project!(0);
        let (bx, by, bz) = project!(1);
        let (cx, cy, cz) = project!(2);
        let u = sub(mul(cx, by), mul(cy, bx));
        let w_ = sub(mul(ax, cy), mul(ay, cx));
        let w = sub(mul(bx, ay), mul(by, ax));
        let zero = _mm256_setzero_ps();
        let any_zero = or(
            or(
                _mm256_cmp_ps::<_CMP_EQ_OQ>(u, zero),
                _mm256_cmp_ps::<_CMP_EQ_OQ>(w_, zero),
            ),
            _mm256_cmp_ps::<_CMP_EQ_OQ>(w, zero),
        );
        let ge = |x: __m256| _mm256_cmp_ps::<_CMP_GE_OQ>(x, zero);
        let le = |x: __m256| _mm256_cmp_ps::<_CMP_LE_OQ>(x, zero);
        let same_sign = or(
            and(and(ge(u), ge(w_)), ge(w)),
            and(and(le(u), le(w_)), le(w)),
        );
        let det = add(add(u, w_), w);
        let (az, bz, cz) = (mul(sz, az), mul(sz, bz), mul(sz, cz));
        let t_scaled = add(add(mul(u, az), mul(w_, bz)), mul(w, cz));
        let sign = _mm256_set1_ps(-0.0);
        let ts = _mm256_xor_ps(t_scaled, and(det, sign));
        let det_abs = _mm256_andnot_ps(sign, det);
        let in_range = and(
            _mm256_cmp_ps::<_CMP_GT_OQ>(ts, zero),
            _mm256_cmp_ps::<_CMP_LT_OQ>(ts, mul(_mm256_set1_ps(t_max), det_abs)),
        );
        let ok = and(
            and(same_sign, _mm256_cmp_ps::<_CMP_NEQ_UQ>(det, zero)),
            _mm256_andnot_ps(any_zero, in_range),
        );
        let mut mask = _mm256_movemask_ps(ok) as u32;
        let redo = _mm256_movemask_ps(any_zero) as u32;
        let store = |x: __m256| {
            let mut out = [0.0f32; 8];
            _mm256_storeu_ps(out.as_mut_ptr(), x);
            out
        };
        if mask == 0 {
            return Hits8 {
                mask,
                redo,
                t: [0.0; 8],
                b1: [0.0; 8],
                b2: [0.0; 8],
                ts: [0.0; 8],
                det_abs: [0.0; 8],
            };
        }
        let inv = _mm256_div_ps(_mm256_set1_ps(1.0), det);
        let t = mul(t_scaled, inv);
        // near_hit_error, written out for 8 lanes in its order (max as `fast_max`).
        let abs = |x: __m256| _mm256_andnot_ps(sign, x);
        let max3 =
            |p: __m256, q: __m256, r: __m256| _mm256_max_ps(_mm256_max_ps(abs(p), abs(q)), abs(r));
        let max_z = max3(az, bz, cz);
        let max_x = max3(ax, bx, cx);
        let max_y = max3(ay, by, cy);
        let max_e = max3(u, w_, w);
        let g = |n: i32| _mm256_set1_ps(crate::math::float::gamma(n));
        let dz = mul(g(3), max_z);
        let dx = mul(g(5), add(max_x, max_z));
        let dy = mul(g(5), add(max_y, max_z));
        let de = mul(
            _mm256_set1_ps(2.0),
            add(
                add(mul(mul(g(2), max_x), max_y), mul(dy, max_x)),
                mul(dx, max_y),
            ),
        );
        let err = mul(
            mul(
                _mm256_set1_ps(3.0),
                add(
                    add(mul(mul(g(3), max_e), max_z), mul(de, max_z)),
                    mul(dz, max_e),
                ),
            ),
            abs(inv),
        );
        let good = _mm256_andnot_ps(
            _mm256_cmp_ps::<_CMP_LT_OQ>(t, err),
            _mm256_cmp_ps::<_CMP_GT_OQ>(t, zero),
        );
        mask &= _mm256_movemask_ps(good) as u32;
        Hits8 {
            mask,
            redo,
            t: store(t),
            b1: store(mul(w_, inv)),
            b2: store(mul(w, inv)),
            ts: store(ts),
            det_abs: store(det_abs),
        }
    }
}
