//! The perspective camera, with Mitsuba 3's conventions: in camera space it looks along +z with
//! +y up and +x to the left, so a Mitsuba `to_world` or look-at ports unchanged.

use crate::math::Transform;
use crate::ray::Ray;
use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize};

/// Which image extent `fov` spans.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum FovAxis {
    /// The image width (Mitsuba's default).
    #[default]
    X,
    /// The image height.
    Y,
    /// The image diagonal.
    Diagonal,
    /// The shorter side.
    Smaller,
    /// The longer side.
    Larger,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    pub to_world: Transform,
    to_local: Transform,
    /// tan(half field of view) along x and y.
    tan_half: Vec2,
    near_clip: f32,
    far_clip: f32,
    width: f32,
    height: f32,
}

impl Camera {
    /// `fov_deg` in (0, 180), `near_clip` > 0, width and height > 0 (the config checks).
    pub fn new(
        to_world: Transform,
        fov_deg: f32,
        axis: FovAxis,
        near_clip: f32,
        far_clip: f32,
        width: u32,
        height: u32,
    ) -> Self {
        let (w, h) = (width as f32, height as f32);
        let aspect = w / h;
        let t = (fov_deg.to_radians() * 0.5).tan();
        let axis = match axis {
            FovAxis::Smaller if aspect > 1.0 => FovAxis::Y,
            FovAxis::Smaller => FovAxis::X,
            FovAxis::Larger if aspect > 1.0 => FovAxis::X,
            FovAxis::Larger => FovAxis::Y,
            a => a,
        };
        let tan_x = match axis {
            FovAxis::X => t,
            FovAxis::Y => t * aspect,
            FovAxis::Diagonal => t * w / (w * w + h * h).sqrt(),
            FovAxis::Smaller | FovAxis::Larger => unreachable!(),
        };
        Self {
            to_world,
            to_local: to_world.inverse(),
            tan_half: Vec2::new(tan_x, tan_x / aspect),
            near_clip,
            far_clip,
            width: w,
            height: h,
        }
    }

    /// The ray through film position `film` (pixels; (0,0) is the top-left corner of the image).
    #[inline]
    pub fn ray(&self, film: Vec2) -> Ray {
        let sx = film.x / self.width;
        let sy = film.y / self.height;
        let d = Vec3::new(
            (1.0 - 2.0 * sx) * self.tan_half.x,
            (1.0 - 2.0 * sy) * self.tan_half.y,
            1.0,
        )
        .normalize();
        // Start on the near plane, as Mitsuba does.
        let local_o = d * (self.near_clip / d.z);
        let world_d = self.to_world.vector(d);
        // Distances scale with the transform; the far plane is at far_clip / d.z along d.
        let scale = world_d.length();
        Ray {
            o: self.to_world.point(local_o),
            d: world_d / scale,
            t_max: (self.far_clip - self.near_clip) / d.z * scale,
        }
    }

    /// Where the camera sees world point `p`, for connecting a light path to it (the inverse
    /// of `ray`): None if `p` is behind the camera, outside the clip range or more than `margin`
    /// pixels outside the film (a pixel filter reaches that far beyond the image).
    #[inline]
    pub fn project(&self, p: Vec3, margin: f32) -> Option<Projection> {
        let q = self.to_local.point(p);
        if !(q.z >= self.near_clip && q.z <= self.far_clip) {
            return None;
        }
        let (x, y) = (q.x / q.z, q.y / q.z);
        let film = Vec2::new(
            (1.0 - x / self.tan_half.x) * 0.5 * self.width,
            (1.0 - y / self.tan_half.y) * 0.5 * self.height,
        );
        let (lo, hi) = (-margin, Vec2::new(self.width, self.height) + margin);
        if !(film.x >= lo && film.x < hi.x && film.y >= lo && film.y < hi.y) {
            return None;
        }
        let origin = self.position();
        let to_camera = origin - p;
        let dist = to_camera.length();
        // Solid angle → film: d(film) = W·H / (A · cos³θ) dω, A = 4 tan_x tan_y the film's area
        // on the plane at distance 1 (the plane-to-direction Jacobian is cos³θ).
        let cos = q.z / q.length();
        Some(Projection {
            film,
            wi: to_camera / dist,
            dist,
            importance: self.width * self.height
                / (4.0 * self.tan_half.x * self.tan_half.y * cos * cos * cos),
        })
    }

    pub fn near_clip(&self) -> f32 {
        self.near_clip
    }

    pub fn far_clip(&self) -> f32 {
        self.far_clip
    }

    /// Camera position in world space.
    pub fn position(&self) -> Vec3 {
        self.to_world.point(Vec3::ZERO)
    }

    /// tan of the half field of view along x and y.
    pub fn tan_half_fov(&self) -> Vec2 {
        self.tan_half
    }
}

/// A world point as the camera sees it (`Camera::project`).
#[derive(Clone, Copy, Debug)]
pub struct Projection {
    /// Film position in pixels, as `Camera::ray` takes it.
    pub film: Vec2,
    /// Unit direction from the point to the camera.
    pub wi: Vec3,
    /// Distance from the point to the camera.
    pub dist: f32,
    /// Film area (pixels²) per unit solid angle at the camera in that direction.
    pub importance: f32,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `project` inverts `ray`, and its importance is the film-to-solid-angle density: the
    /// film's W·H pixels over the solid angle the film sees, at the centre and the corners.
    #[test]
    fn project_inverts_ray() {
        let t = Transform::look_at(Vec3::new(0.3, 1.0, 3.9), Vec3::new(0.1, 0.0, 0.0), Vec3::Y)
            .unwrap();
        let cam = Camera::new(t, 50.0, FovAxis::X, 0.01, 100.0, 320, 180);
        for film in [
            Vec2::new(160.0, 90.0),
            Vec2::new(0.5, 0.5),
            Vec2::new(319.5, 179.25),
            Vec2::new(17.0, 140.0),
        ] {
            let r = cam.ray(film);
            let p = r.o + r.d * 2.5;
            let pr = cam.project(p, 0.0).expect("in view");
            assert!((pr.film - film).length() < 2e-3, "{film} -> {}", pr.film);
            assert!((pr.wi + r.d).length() < 1e-5);
            // Numerical Jacobian: the solid angle of a one-pixel square around `film`.
            let d = |f: Vec2| cam.ray(f).d;
            let h = 0.5;
            let (a, b, c) = (
                d(film),
                d(film + Vec2::new(h, 0.0)),
                d(film + Vec2::new(0.0, h)),
            );
            let omega = (b - a).cross(c - a).length() / (h * h);
            assert!(
                (pr.importance * omega - 1.0).abs() < 2e-3,
                "{} vs {omega}",
                pr.importance
            );
        }
        assert!(
            cam.project(Vec3::new(0.3, 1.0, 6.0), 0.0).is_none(),
            "behind the camera"
        );
        assert!(
            cam.project(Vec3::new(40.0, 0.0, 0.0), 0.0).is_none(),
            "outside the film"
        );
        // Just outside the film's left edge: kept within a margin.
        let r = cam.ray(Vec2::new(-0.5, 90.0));
        assert!(cam.project(r.o + r.d * 2.0, 0.0).is_none());
        assert!(cam.project(r.o + r.d * 2.0, 1.0).is_some());
    }

    #[test]
    fn cornell_camera_orientation() {
        let t = Transform::look_at(Vec3::new(0.0, 0.0, 3.9), Vec3::ZERO, Vec3::Y).unwrap();
        let cam = Camera::new(t, 39.3077, FovAxis::Smaller, 0.001, 100.0, 256, 256);
        let c = cam.ray(Vec2::new(128.0, 128.0));
        assert!((c.d - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-6);
        // The image's right edge looks towards world +x, the top edge towards +y.
        assert!(cam.ray(Vec2::new(256.0, 128.0)).d.x > 0.3);
        assert!(cam.ray(Vec2::new(128.0, 0.0)).d.y > 0.3);
        let half = (cam.ray(Vec2::new(256.0, 128.0)).d.x).asin().to_degrees();
        assert!((half - 39.3077 / 2.0).abs() < 1e-3);
    }

    #[test]
    fn fov_axes() {
        let t = Transform::IDENTITY;
        let wide = Camera::new(t, 60.0, FovAxis::Y, 0.01, 1e4, 200, 100);
        assert!((wide.tan_half_fov().y - 30f32.to_radians().tan()).abs() < 1e-6);
        let smaller = Camera::new(t, 60.0, FovAxis::Smaller, 0.01, 1e4, 200, 100);
        assert_eq!(wide.tan_half_fov(), smaller.tan_half_fov());
        let d = Camera::new(t, 60.0, FovAxis::Diagonal, 0.01, 1e4, 300, 400);
        assert!((d.tan_half_fov().length() - 30f32.to_radians().tan()).abs() < 1e-6);
    }
}
