//! Disks: the unit disk placed by an affine transform (intersection in its object space,
//! surface data, uniform area sampling).

use super::{AreaSample, PrimHit, SurfacePoint};
use crate::math::portable;
use crate::math::{sampling, Frame, Transform};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// The unit disk in the local z = 0 plane (normal +z), placed by `to_world`.
#[derive(Clone, Debug, PartialEq)]
pub struct Disk {
    pub to_world: Transform,
    pub flip: bool,
}

/// Ray/disk: the ray in the disk's object space meets z = 0 inside the unit circle; (b1, b2) are
/// the object-space (x, y) of the hit.
#[inline]
pub(super) fn intersect_disk(
    ray: &crate::ray::Ray,
    to_object: &[glam::Vec4; 3],
    t_max: f32,
) -> Option<PrimHit> {
    let o = ray.o.extend(1.0);
    let d = ray.d.extend(0.0);
    let (oz, dz) = (to_object[2].dot(o), to_object[2].dot(d));
    if dz == 0.0 {
        return None;
    }
    let t = -oz / dz;
    if !(t > 0.0 && t < t_max) {
        return None;
    }
    let x = to_object[0].dot(o) + t * to_object[0].dot(d);
    let y = to_object[1].dot(o) + t * to_object[1].dot(d);
    (x * x + y * y <= 1.0).then_some(PrimHit { t, b1: x, b2: y })
}

impl Disk {
    #[inline]
    pub(super) fn surface_at(&self, local: Vec2) -> SurfacePoint {
        let (p, p_error) = self.to_world.point_with_error(local.extend(0.0));
        let mut n = self.to_world.normal(Vec3::Z).normalize();
        if self.flip {
            n = -n;
        }
        let r = local.length();
        let phi = portable::atan2(local.y, local.x);
        let phi = if phi < 0.0 { phi + 2.0 * PI } else { phi };
        let dpdu = self.to_world.vector(Vec3::new(-local.y, local.x, 0.0));
        SurfacePoint {
            p,
            p_error,
            ng: n,
            frame: Frame::from_normal_tangent(n, dpdu),
            uv: Vec2::new(r, phi / (2.0 * PI)),
        }
    }

    /// Uniform point on the (possibly elliptical) disk: an affine map keeps uniform density.
    pub fn sample_area(&self, u: Vec2, area: f32) -> AreaSample {
        let s = self.surface_at(sampling::square_to_disk_concentric(u));
        AreaSample {
            p: s.p,
            p_error: s.p_error,
            n: s.ng,
            pdf_area: 1.0 / area,
        }
    }
}
