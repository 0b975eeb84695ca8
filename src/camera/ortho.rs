//! The orthographic camera: parallel rays along +z from the film, which spans
//! 2·tan_half.x × 2·tan_half.y camera units (`Intrinsics` with the plane read as camera-space
//! x, y; for OpenCV-style intrinsics fx, fy are pixels per camera unit).

use super::Intrinsics;
use crate::math::Transform;
use crate::ray::Ray;
use glam::{Vec2, Vec3};

#[derive(Clone, Debug, PartialEq)]
pub struct Orthographic {
    pub to_world: Transform,
    pub intrinsics: Intrinsics,
    pub near_clip: f32,
    pub far_clip: f32,
}

impl Orthographic {
    #[inline]
    pub fn ray(&self, film: Vec2) -> Ray {
        let q = self.intrinsics.plane(film);
        let world_d = self.to_world.vector(Vec3::Z);
        let scale = world_d.length();
        Ray {
            o: self.to_world.point(Vec3::new(q.x, q.y, self.near_clip)),
            d: world_d / scale,
            t_max: (self.far_clip - self.near_clip) * scale,
            time: 0.0,
        }
    }
}
