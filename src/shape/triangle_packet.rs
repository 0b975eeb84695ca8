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
    pub fn intersect(&self, s: &RayShear4, t_max: f32) -> Hits4 {
        let [kx, ky, kz] = s.k;
        let project = |vertex: usize| {
            let x = self.v[3 * vertex + kx] - s.o[0];
            let y = self.v[3 * vertex + ky] - s.o[1];
            let z = self.v[3 * vertex + kz] - s.o[2];
            (x - s.sx * z, y - s.sy * z, z)
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
        let (az, bz, cz) = (s.sz * az, s.sz * bz, s.sz * cz);
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

/// `RayShear` with its per-ray constants in SIMD lanes, for `Triangle4`.
#[derive(Clone, Copy, Debug)]
pub struct RayShear4 {
    /// The ray origin, permuted (kx, ky, kz).
    o: [f32x4; 3],
    k: [usize; 3],
    sx: f32x4,
    sy: f32x4,
    sz: f32x4,
}

impl RayShear4 {
    #[inline]
    pub fn new(s: &RayShear) -> Self {
        let k = s.k.map(|k| (k & 3) as usize);
        let o = [s.o.x, s.o.y, s.o.z];
        Self {
            o: k.map(|k| f32x4::splat(o[k])),
            k,
            sx: f32x4::splat(s.sx),
            sy: f32x4::splat(s.sy),
            sz: f32x4::splat(s.sz),
        }
    }
}
