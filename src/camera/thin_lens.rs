//! The thin lens (depth of field): rays leave a disk of radius `aperture_radius` in the plane
//! z = 0 and converge on the plane z = `focus_distance` at the point the pinhole ray through the
//! same film position meets it, so that plane is in focus and a point at depth z is blurred
//! into a disk of diameter 2·aperture·|z − focus|/z on the focus plane (seen from the lens:
//! the circle of confusion, tested in `tests/camera_models.rs`). Mitsuba 3's `thinlens` model.

use super::{Distortion, Pinhole};
use crate::math::sampling::square_to_disk_concentric;
use crate::ray::Ray;
use glam::{Vec2, Vec3};

/// The sampler dimension of the lens sample: a group of its own far above every bounce's
/// (bounces use dimensions below 4 + 8·2²⁰), so the film, wavelength and bounce dimensions are
/// the pinhole's.
pub const LENS_DIM: u32 = 1 << 30;

#[derive(Clone, Debug, PartialEq)]
pub struct ThinLens {
    /// Frame, intrinsics and clip planes (the ray through the lens centre is the pinhole's).
    pub pinhole: Pinhole,
    pub distortion: Option<Distortion>,
    pub aperture_radius: f32,
    pub focus_distance: f32,
}

impl ThinLens {
    /// The ray through film position `film` and lens sample `u` ∈ [0,1)² (u = (0.5, 0.5) is
    /// the lens centre).
    #[inline]
    pub fn ray(&self, film: Vec2, u: Vec2) -> Ray {
        let mut q = self.pinhole.intrinsics.plane(film);
        if let Some(d) = &self.distortion {
            q = d.undistort_plane(q);
        }
        let focus = Vec3::new(q.x, q.y, 1.0) * self.focus_distance;
        let lens = square_to_disk_concentric(u) * self.aperture_radius;
        let o = Vec3::new(lens.x, lens.y, 0.0);
        let d = (focus - o).normalize();
        let p = &self.pinhole;
        let (near, far) = (p.near_clip(), p.far_clip());
        let local_o = o + d * (near / d.z);
        let world_d = p.to_world.vector(d);
        let scale = world_d.length();
        Ray {
            o: p.to_world.point(local_o),
            d: world_d / scale,
            t_max: (far - near) / d.z * scale,
            time: 0.0,
        }
    }
}
