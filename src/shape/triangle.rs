//! Watertight ray/triangle intersection (Woop, Benthin & Wald, JCGT 2013): rays that hit a shared
//! edge or vertex hit at least one of the triangles, so meshes have no cracks for light to leak.

use crate::math::float::gamma;
use crate::ray::Ray;
use glam::Vec3;

/// Per-ray constants of the watertight test: the axis permutation that makes the ray's largest
/// direction component z, and the shear that aligns the ray with z.
#[derive(Clone, Copy, Debug)]
pub struct RayShear {
    o: Vec3,
    /// Axis indices (kx, ky, kz); always < 3, and masked with `& 3` on use so that indexing a
    /// 4-element array needs no bounds check.
    k: [u8; 3],
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
            k: [kx as u8, ky as u8, kz as u8],
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

/// Upper bound on the rounding error of a hit's t (see `intersect`).
#[allow(clippy::too_many_arguments)]
#[inline]
fn near_hit_error(
    ax: f32,
    ay: f32,
    bx: f32,
    by: f32,
    cx: f32,
    cy: f32,
    z: [f32; 3],
    e: [f32; 3],
    inv_det: f32,
) -> f32 {
    let max_z = z[0].abs().max(z[1].abs()).max(z[2].abs());
    let max_x = ax.abs().max(bx.abs()).max(cx.abs());
    let max_y = ay.abs().max(by.abs()).max(cy.abs());
    let max_e = e[0].abs().max(e[1].abs()).max(e[2].abs());
    let dz = gamma(3) * max_z;
    let dx = gamma(5) * (max_x + max_z);
    let dy = gamma(5) * (max_y + max_z);
    let de = 2.0 * (gamma(2) * max_x * max_y + dy * max_x + dx * max_y);
    3.0 * (gamma(3) * max_e * max_z + de * max_z + dz * max_e) * inv_det.abs()
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
