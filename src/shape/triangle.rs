//! Watertight ray/triangle intersection (Woop, Benthin & Wald, JCGT 2013): rays that hit a shared
//! edge or vertex hit at least one of the triangles, so meshes have no cracks for light to leak.

use crate::math::float::gamma;
use crate::ray::Ray;
use glam::Vec3;
use wide::{f32x4, CmpEq, CmpGe, CmpGt, CmpLe, CmpLt, CmpNe};

/// Per-ray constants of the watertight test: the axis permutation that makes the ray's largest
/// direction component z, and the shear that aligns the ray with z.
#[derive(Clone, Copy, Debug)]
pub struct RayShear {
    o: Vec3,
    /// Axis indices (kx, ky, kz); always < 3, and masked with `& 3` on use so that indexing a
    /// 4-element array needs no bounds check.
    k: [u32; 3],
    sx: f32,
    sy: f32,
    sz: f32,
}

impl RayShear {
    #[inline]
    pub fn new(ray: &Ray) -> Self {
        let a = ray.d.abs();
        let kz = if a.x > a.y {
            if a.x > a.z {
                0
            } else {
                2
            }
        } else if a.y > a.z {
            1
        } else {
            2
        };
        let mut kx = (kz + 1) % 3;
        let mut ky = (kx + 1) % 3;
        if ray.d[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        let sz = 1.0 / ray.d[kz];
        Self {
            o: ray.o,
            k: [kx as u32, ky as u32, kz as u32],
            sx: ray.d[kx] * sz,
            sy: ray.d[ky] * sz,
            sz,
        }
    }

    /// A vertex relative to the ray origin, permuted and sheared: (x, y) in the ray's frame,
    /// and the unsheared z (sheared later, only for triangles the ray passes through).
    #[inline(always)]
    fn project(&self, v: Vec3) -> (f32, f32, f32) {
        let d = v - self.o;
        let p = [d.x, d.y, d.z, 0.0];
        let (x, y, z) = (
            p[(self.k[0] & 3) as usize],
            p[(self.k[1] & 3) as usize],
            p[(self.k[2] & 3) as usize],
        );
        (x - self.sx * z, y - self.sy * z, z)
    }
}

/// A hit: distance and barycentrics (b1, b2) of vertices 1 and 2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriHit {
    pub t: f32,
    pub b1: f32,
    pub b2: f32,
}

#[inline]
pub fn intersect(s: &RayShear, t_max: f32, v: &[Vec3; 3]) -> Option<TriHit> {
    let (ax, ay, az) = s.project(v[0]);
    let (bx, by, bz) = s.project(v[1]);
    let (cx, cy, cz) = s.project(v[2]);
    let mut u = cx * by - cy * bx;
    let mut w_ = ax * cy - ay * cx;
    let mut w = bx * ay - by * ax;
    // Exactly zero edge functions are ambiguous in f32: redo them in f64 (rare).
    if u == 0.0 || w_ == 0.0 || w == 0.0 {
        u = (cx as f64 * by as f64 - cy as f64 * bx as f64) as f32;
        w_ = (ax as f64 * cy as f64 - ay as f64 * cx as f64) as f32;
        w = (bx as f64 * ay as f64 - by as f64 * ax as f64) as f32;
    }
    if (u < 0.0 || w_ < 0.0 || w < 0.0) && (u > 0.0 || w_ > 0.0 || w > 0.0) {
        return None;
    }
    let det = u + w_ + w;
    if det == 0.0 {
        return None;
    }
    let (az, bz, cz) = (s.sz * az, s.sz * bz, s.sz * cz);
    let t_scaled = u * az + w_ * bz + w * cz;
    // t must lie in (0, t_max); compare before dividing, with det's sign folded in.
    let ts = t_scaled * det.signum();
    if ts <= 0.0 || ts >= t_max * det.abs() {
        return None;
    }
    let inv = 1.0 / det;
    let t = t_scaled * inv;
    if t.is_nan() || t <= 0.0 {
        return None;
    }
    // A t this close to 0 may be rounding error rather than a hit: a ray leaving a large,
    // slightly non-planar or rotated surface would otherwise re-hit it (shadow acne). Reject t
    // unless it exceeds a conservative bound on its own error, propagated through the shear,
    // the edge functions and the scaled depths (the error analysis of Pharr, Jakob & Humphreys,
    // PBR 4th ed., §6.8.6). Only runs for hits, and only costs arithmetic.
    if t < near_hit_error(ax, ay, bx, by, cx, cy, [az, bz, cz], [u, w_, w], inv) {
        return None;
    }
    Some(TriHit {
        t,
        b1: w_ * inv,
        b2: w * inv,
    })
}

/// Arithmetic shared by the scalar and the 4-lane triangle tests, so both round identically.
trait Lane: Copy + std::ops::Add<Output = Self> + std::ops::Mul<Output = Self> {
    fn splat(x: f32) -> Self;
    fn abs(self) -> Self;
    fn max(self, o: Self) -> Self;
}

impl Lane for f32 {
    #[inline(always)]
    fn splat(x: f32) -> Self {
        x
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f32::abs(self)
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        f32::max(self, o)
    }
}

impl Lane for f32x4 {
    #[inline(always)]
    fn splat(x: f32) -> Self {
        f32x4::splat(x)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f32x4::abs(self)
    }
    // Operands are never NaN where the result is used (NaN lanes fail earlier tests).
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        self.fast_max(o)
    }
}

/// Upper bound on the rounding error of a hit's t (see `intersect`).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn near_hit_error<T: Lane>(
    ax: T,
    ay: T,
    bx: T,
    by: T,
    cx: T,
    cy: T,
    z: [T; 3],
    e: [T; 3],
    inv_det: T,
) -> T {
    let max_z = z[0].abs().max(z[1].abs()).max(z[2].abs());
    let max_x = ax.abs().max(bx.abs()).max(cx.abs());
    let max_y = ay.abs().max(by.abs()).max(cy.abs());
    let max_e = e[0].abs().max(e[1].abs()).max(e[2].abs());
    let g = |n: i32| T::splat(gamma(n));
    let dz = g(3) * max_z;
    let dx = g(5) * (max_x + max_z);
    let dy = g(5) * (max_y + max_z);
    let de = T::splat(2.0) * (g(2) * max_x * max_y + dy * max_x + dx * max_y);
    T::splat(3.0) * (g(3) * max_e * max_z + de * max_z + dz * max_e) * inv_det.abs()
}

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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hits_inside_misses_outside() {
        let tri = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ];
        let r = Ray::new(Vec3::new(0.25, 0.25, 1.0), -Vec3::Z);
        let h = intersect(&RayShear::new(&r), f32::INFINITY, &tri).unwrap();
        assert!((h.t - 1.0).abs() < 1e-6);
        assert!((h.b1 - 0.25).abs() < 1e-6 && (h.b2 - 0.25).abs() < 1e-6);
        let miss = Ray::new(Vec3::new(0.75, 0.75, 1.0), -Vec3::Z);
        assert!(intersect(&RayShear::new(&miss), f32::INFINITY, &tri).is_none());
        assert!(
            intersect(&RayShear::new(&r), 0.5, &tri).is_none(),
            "beyond t_max"
        );
        let behind = Ray::new(Vec3::new(0.25, 0.25, 1.0), Vec3::Z);
        assert!(intersect(&RayShear::new(&behind), f32::INFINITY, &tri).is_none());
    }

    /// Rays leaving a point of a large, rotated triangle (interpolated from its vertices, so off
    /// its plane by rounding) must not re-hit it: their t would be pure rounding error.
    #[test]
    fn no_self_hits_leaving_a_rotated_triangle() {
        let rot = glam::Quat::from_axis_angle(Vec3::new(1.0, 0.3, -0.2).normalize(), 1.3);
        let tri = [
            rot * Vec3::new(-4.0, -4.0, 0.0),
            rot * Vec3::new(4.0, -4.0, 0.0),
            rot * Vec3::new(4.0, 4.0, 0.0),
        ];
        let n = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalize();
        let mut state = 7u32;
        let mut next = || {
            state = state.wrapping_mul(747796405).wrapping_add(2891336453);
            (state >> 8) as f32 / (1u32 << 24) as f32
        };
        let mut self_hits = 0;
        for _ in 0..20000 {
            let (b1, b2) = (next() * 0.5, next() * 0.5);
            let p = tri[0] * (1.0 - b1 - b2) + tri[1] * b1 + tri[2] * b2;
            let z = 0.1 + 0.9 * next();
            let phi = std::f32::consts::TAU * next();
            let frame = crate::math::frame::Frame::from_normal(n);
            let r = (1.0 - z * z).sqrt();
            for side in [1.0f32, -1.0] {
                let d = frame.to_world(Vec3::new(r * phi.cos(), r * phi.sin(), z * side));
                let ray = Ray::new(p, d);
                if intersect(&RayShear::new(&ray), f32::INFINITY, &tri).is_some() {
                    self_hits += 1;
                }
            }
        }
        assert_eq!(self_hits, 0, "rays re-hit the triangle they leave");
    }

    /// Every lane of the packet test agrees bit for bit with the scalar test, or is handed back
    /// for it (`redo`, an edge function exactly zero). Rays aim at edges and vertices (where
    /// rounding decides) as well as inside; some lanes are degenerate, some unused.
    #[test]
    fn packet_test_matches_scalar_test() {
        let mut state = 11u32;
        let mut next = || {
            state = state.wrapping_mul(747796405).wrapping_add(2891336453);
            (state >> 8) as f32 / (1u32 << 24) as f32
        };
        let (mut hits, mut redone) = (0, 0);
        for _ in 0..20000 {
            let mut tris = Vec::new();
            for id in 0..4 {
                let mut v = [0; 3].map(|_| Vec3::new(next(), next(), next()) * 4.0 - 2.0);
                if id == 3 && next() < 0.3 {
                    v[2] = v[1]; // degenerate
                }
                tris.push((v, id));
            }
            let n = 1 + (next() * 4.0) as usize;
            let packet = Triangle4::new(&tris[..n]);
            let target = tris[(next() * n as f32) as usize % n].0;
            let (b1, b2) = match (next() * 3.0) as u32 {
                0 => (0.0, next()), // on an edge
                1 => (1.0, 0.0),    // at a vertex
                _ => (next() * 0.6, next() * 0.4),
            };
            let aim = target[0] * (1.0 - b1 - b2) + target[1] * b1 + target[2] * b2;
            // Origins sometimes on the target itself (rays leaving a surface).
            let o = if next() < 0.1 {
                aim
            } else {
                Vec3::new(next(), next(), next()) * 8.0 - 4.0
            };
            let d = if next() < 0.1 {
                Vec3::new(next(), next(), next()) - 0.5
            } else {
                aim - o
            };
            if d.length_squared() == 0.0 {
                continue;
            }
            let ray = Ray::new(o, d.normalize());
            let shear = RayShear::new(&ray);
            let t_max = if next() < 0.2 {
                next() * 4.0
            } else {
                f32::INFINITY
            };
            let h = packet.intersect(&RayShear4::new(&shear), t_max);
            assert_eq!((h.mask | h.redo) >> n, 0, "an unused lane was hit");
            assert_eq!(h.mask & h.redo, 0);
            for (lane, (v, _)) in tris[..n].iter().enumerate() {
                let bit = 1 << lane;
                if h.redo & bit != 0 {
                    redone += 1;
                    continue;
                }
                let scalar = intersect(&shear, t_max, v);
                let packet = (h.mask & bit != 0).then(|| TriHit {
                    t: h.t[lane],
                    b1: h.b1[lane],
                    b2: h.b2[lane],
                });
                assert_eq!(packet, scalar, "lane {lane} of {v:?}, ray {ray:?}");
                hits += scalar.is_some() as u32;
            }
        }
        assert!(hits > 5000, "too few hits ({hits}) to test anything");
        assert!(
            redone > 100,
            "edge and vertex cases not exercised ({redone})"
        );
    }

    #[test]
    fn shared_edge_is_watertight() {
        // Two triangles sharing the diagonal of the unit square; rays along the diagonal must
        // hit one of them.
        let t1 = [
            Vec3::ZERO,
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
        ];
        let t2 = [
            Vec3::ZERO,
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ];
        for i in 0..1000 {
            let x = i as f32 / 1000.0 * 0.98 + 0.01;
            let r = Ray::new(
                Vec3::new(x, x, 3.0),
                Vec3::new(0.001, -0.002, -1.0).normalize(),
            );
            let s = RayShear::new(&r);
            let r2 = Ray::new(r.o - r.d * 0.0, r.d);
            let hit =
                intersect(&s, r2.t_max, &t1).is_some() || intersect(&s, r2.t_max, &t2).is_some();
            assert!(hit, "ray {i} leaked through the shared edge");
        }
    }
}
