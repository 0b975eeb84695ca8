//! A ray's hit on a surface: where, which way the surface faces, and its shading frame.

use crate::math::Frame;
use crate::ray::{self, Ray};
use glam::{Vec2, Vec3};

#[derive(Clone, Copy, Debug)]
pub struct SurfaceInteraction {
    pub p: Vec3,
    /// Conservative bound on the rounding error of `p` (per component).
    pub p_error: Vec3,
    /// Unit geometric normal on the surface's front side.
    pub ng: Vec3,
    /// Shading frame (z = shading normal).
    pub frame: Frame,
    pub uv: Vec2,
    /// Distance along the ray that found it.
    pub t: f32,
    pub shape: u32,
    pub prim: u32,
    /// The time of the ray that found it (`Ray::time`).
    pub time: f32,
    /// Barycentrics (b1, b2) of the hit in triangle `prim`, in the order the shape intersects
    /// it (per-vertex data, `TexPoint`); meaningless for spheres and disks.
    pub bary: Vec2,
}

/// Texture lookups at a hit read its uv and, for per-vertex colours, its triangle.
impl From<&SurfaceInteraction> for crate::texture::TexPoint {
    #[inline(always)]
    fn from(si: &SurfaceInteraction) -> Self {
        crate::texture::TexPoint {
            uv: si.uv,
            prim: si.prim,
            bary: si.bary,
        }
    }
}

impl SurfaceInteraction {
    /// A ray leaving this point in unit direction `d`.
    #[inline]
    pub fn spawn(&self, d: Vec3) -> Ray {
        Ray {
            time: self.time,
            ..ray::spawn(self.p, self.p_error, self.ng, d)
        }
    }

    /// `spawn`, written into `out` (see `Path::scatter`).
    #[inline]
    pub fn spawn_into(&self, d: Vec3, out: &mut Ray) {
        let r = self.spawn(d);
        (out.o, out.d, out.t_max, out.time) = (r.o, r.d, r.t_max, r.time);
    }

    /// A shadow ray to `target` (on a surface with normal `target_n`, or a free point).
    /// Always inline: out of line it was 5.7% of a Cornell render's instructions in the packet
    /// kernel, compiled for baseline SSE2 instead of the kernel's AVX2.
    #[inline(always)]
    pub fn spawn_to(&self, target: Vec3, target_error: Vec3, target_n: Option<Vec3>) -> Ray {
        Ray {
            time: self.time,
            ..ray::spawn_to(
                self.p,
                self.p_error,
                self.ng,
                target,
                target_error,
                target_n,
            )
        }
    }
}
