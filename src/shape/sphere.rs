//! Spheres: intersection (in f64, with the stable root pair), surface data, and sampling for
//! area lights (uniform in area, or uniform in the solid angle the sphere subtends).

use super::{AreaSample, PrimHit, SurfacePoint};
use crate::math::float::gamma;
use crate::math::turns::{acos_half_turns, azimuth_turns, sin_cos_turns};
use crate::math::{sampling, Frame};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

#[derive(Clone, Debug, PartialEq)]
pub struct Sphere {
    pub center: Vec3,
    pub radius: f32,
    /// Normals point inward (the front side is the inside).
    pub flip: bool,
}

/// Ray/sphere intersection in f64 with the numerically stable root pair (the discriminant is
/// formed from the perpendicular distance, which does not cancel for distant spheres).
#[inline]
pub(super) fn intersect_sphere(
    ray: &crate::ray::Ray,
    center: Vec3,
    radius: f32,
    t_max: f32,
) -> Option<PrimHit> {
    let o = ray.o.as_dvec3() - center.as_dvec3();
    let d = ray.d.as_dvec3();
    let r = radius as f64;
    let b = o.dot(d);
    let perp = o - b * d;
    let disc = r * r - perp.length_squared();
    if disc < 0.0 {
        return None;
    }
    let c = o.length_squared() - r * r;
    let q = -b - disc.sqrt().copysign(b);
    let (mut t0, mut t1) = if q != 0.0 { (c / q, q) } else { (0.0, 0.0) };
    if t0 > t1 {
        std::mem::swap(&mut t0, &mut t1);
    }
    let t_max = t_max as f64;
    let t = if t0 > 0.0 && t0 < t_max {
        t0
    } else if t1 > 0.0 && t1 < t_max {
        t1
    } else {
        return None;
    };
    Some(PrimHit {
        t: t as f32,
        b1: 0.0,
        b2: 0.0,
    })
}

impl Sphere {
    #[inline]
    pub(super) fn surface_at(&self, hit: Vec3) -> SurfacePoint {
        // Reproject onto the sphere: the error then depends only on |p|, not on the ray length.
        let dir = (hit - self.center).normalize();
        let p = self.center + dir * self.radius;
        let p_error = gamma(5) * (self.center.abs() + (dir * self.radius).abs());
        let n = if self.flip { -dir } else { dir };
        let dpdu = Vec3::new(-dir.y, dir.x, 0.0);
        SurfacePoint {
            p,
            p_error,
            ng: n,
            frame: Frame::from_normal_tangent(n, dpdu),
            uv: Vec2::new(azimuth_turns(dir.y, dir.x), acos_half_turns(dir.z)),
        }
    }

    /// Uniform point on the whole sphere.
    pub fn sample_area(&self, u: Vec2) -> AreaSample {
        let dir = sampling::square_to_uniform_sphere(u);
        let s = self.surface_at(self.center + dir * self.radius);
        AreaSample {
            p: s.p,
            p_error: s.p_error,
            n: s.ng,
            pdf_area: 1.0 / (4.0 * PI * self.radius * self.radius),
        }
    }

    /// 1 − cos θ_max of the cone the sphere subtends from `p` (None if `p` is inside), computed
    /// without cancellation so a tiny distant sphere keeps an accurate, non-zero cone.
    pub fn cone_one_minus_cos(&self, p: Vec3) -> Option<f32> {
        let dc2 = (self.center - p).length_squared();
        let r2 = self.radius * self.radius;
        if dc2 <= r2 * (1.0 + 1e-4) {
            return None;
        }
        let sin2 = r2 / dc2;
        let cos = (1.0 - sin2).max(0.0).sqrt();
        Some(sin2 / (1.0 + cos))
    }

    /// A point on the part of the sphere visible from `p`, uniform in solid angle (the cone
    /// method), or uniform in area when `p` is inside. Returns the sample and its solid-angle pdf.
    pub fn sample_from(&self, p: Vec3, u: Vec2) -> (AreaSample, f32) {
        let Some(omc) = self.cone_one_minus_cos(p) else {
            let s = self.sample_area(u);
            let to = s.p - p;
            let d2 = to.length_squared();
            let cos = s.n.dot(-to / d2.sqrt()).abs();
            let pdf = if cos > 0.0 {
                s.pdf_area * d2 / cos
            } else {
                0.0
            };
            return (s, pdf);
        };
        let to_c = self.center - p;
        let dc = to_c.length();
        let frame = Frame::from_normal(to_c / dc);
        // θ from the cone axis: 1 − cos θ = u·omc and sin²θ = (1 − cos θ)(1 + cos θ), never
        // formed by subtracting from 1 (for a tiny light that would leave a few distinct angles).
        let one_minus_cos_t = u.x * omc;
        let cos_t = 1.0 - one_minus_cos_t;
        let sin2_t = one_minus_cos_t * (2.0 - one_minus_cos_t);
        // Angle α at the centre between −axis and the surface point the direction hits first:
        // cos α = sin²θ / sin θmax + cos θ · √(1 − sin²θ / sin²θmax), free of cancellation.
        let r = self.radius;
        let sin_max = r / dc;
        let ratio = (sin2_t / (sin_max * sin_max)).min(1.0);
        let cos_a = (sin2_t / sin_max + cos_t * (1.0 - ratio).sqrt()).clamp(-1.0, 1.0);
        let sin_a = (1.0 - cos_a * cos_a).max(0.0).sqrt();
        let (sp, cp) = sin_cos_turns(u.y);
        let local = Vec3::new(sin_a * cp, sin_a * sp, cos_a);
        let dir = -frame.to_world(local);
        let s = self.surface_at(self.center + dir * r);
        let pdf = 1.0 / (2.0 * PI * omc);
        (
            AreaSample {
                p: s.p,
                p_error: s.p_error,
                n: s.ng,
                pdf_area: 0.0,
            },
            pdf,
        )
    }

    /// Solid-angle pdf of `sample_from(p, ·)` choosing the surface point `q` with normal `n`.
    pub fn pdf_from(&self, p: Vec3, q: Vec3, n: Vec3) -> f32 {
        match self.cone_one_minus_cos(p) {
            Some(omc) => 1.0 / (2.0 * PI * omc),
            None => {
                let to = q - p;
                let d2 = to.length_squared();
                let cos = n.dot(to / d2.sqrt()).abs();
                if cos > 0.0 {
                    d2 / (cos * 4.0 * PI * self.radius * self.radius)
                } else {
                    0.0
                }
            }
        }
    }
}
