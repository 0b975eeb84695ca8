//! The pinhole camera and the film-to-plane map (`Intrinsics`) every model shares.

use crate::math::portable;
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

/// The map from film positions (pixels) to the camera's plane z = 1 (for the orthographic
/// camera: to camera-space x, y), and back. In camera space +x is left and +y up, on the film
/// +x is right and +y down: plane = ((1 − 2(f.x − o.x)/W)·tan_x, (1 − 2(f.y − o.y)/H)·tan_y),
/// o the principal point's offset from the film centre (zero for a field of view). With
/// OpenCV's intrinsics that is x_cv = −plane.x = (f.x − 0.5 − cx)/fx, cx in OpenCV's pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Intrinsics {
    /// tan(half field of view) along x and y (orthographic: the half extent in camera units).
    pub tan_half: Vec2,
    /// Principal point minus film centre, in pixels (prism's = OpenCV's: a shift).
    pub offset: Vec2,
    pub width: f32,
    pub height: f32,
}

impl Intrinsics {
    /// From a field of view in (0, 180) degrees along `axis`.
    pub fn from_fov(fov_deg: f32, axis: FovAxis, width: u32, height: u32) -> Self {
        let (w, h) = (width as f32, height as f32);
        let aspect = w / h;
        let t = portable::tan(fov_deg.to_radians() * 0.5);
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
            tan_half: Vec2::new(tan_x, tan_x / aspect),
            offset: Vec2::ZERO,
            width: w,
            height: h,
        }
    }

    /// From OpenCV's K: focal lengths and principal point in pixels, pixel centres at integers
    /// (OpenCV's convention, so a calibration's K is used as it is; prism's centres are at
    /// i + 0.5, hence the half-pixel shift). Orthographic: fx, fy in pixels per camera unit.
    pub fn from_k(fx: f64, fy: f64, cx: f64, cy: f64, width: u32, height: u32) -> Self {
        let (w, h) = (width as f64, height as f64);
        Self {
            tan_half: Vec2::new((w / (2.0 * fx)) as f32, (h / (2.0 * fy)) as f32),
            offset: Vec2::new((cx + 0.5 - 0.5 * w) as f32, (cy + 0.5 - 0.5 * h) as f32),
            width: width as f32,
            height: height as f32,
        }
    }

    /// OpenCV's (fx, fy, cx, cy): pixels, pixel centres at integers (cx = prism's − 0.5).
    pub fn k_opencv(&self) -> [f64; 4] {
        let (w, h) = (self.width as f64, self.height as f64);
        [
            w / (2.0 * self.tan_half.x as f64),
            h / (2.0 * self.tan_half.y as f64),
            0.5 * w + self.offset.x as f64 - 0.5,
            0.5 * h + self.offset.y as f64 - 0.5,
        ]
    }

    /// The point on the plane z = 1 (camera frame) that film position `film` sees.
    #[inline]
    pub fn plane(&self, film: Vec2) -> Vec2 {
        let sx = (film.x - self.offset.x) / self.width;
        let sy = (film.y - self.offset.y) / self.height;
        Vec2::new(
            (1.0 - 2.0 * sx) * self.tan_half.x,
            (1.0 - 2.0 * sy) * self.tan_half.y,
        )
    }

    /// The film position of plane point `q` (the inverse of `plane`).
    #[inline]
    pub fn film(&self, q: Vec2) -> Vec2 {
        Vec2::new(
            (1.0 - q.x / self.tan_half.x) * 0.5 * self.width + self.offset.x,
            (1.0 - q.y / self.tan_half.y) * 0.5 * self.height + self.offset.y,
        )
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Pinhole {
    pub to_world: Transform,
    to_local: Transform,
    pub intrinsics: Intrinsics,
    near_clip: f32,
    far_clip: f32,
}

impl Pinhole {
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
        Self::with_intrinsics(
            to_world,
            Intrinsics::from_fov(fov_deg, axis, width, height),
            near_clip,
            far_clip,
        )
    }

    pub fn with_intrinsics(
        to_world: Transform,
        intrinsics: Intrinsics,
        near_clip: f32,
        far_clip: f32,
    ) -> Self {
        Self {
            to_world,
            to_local: to_world.inverse(),
            intrinsics,
            near_clip,
            far_clip,
        }
    }

    /// The ray through film position `film` (pixels; (0,0) is the top-left corner of the image).
    #[inline]
    pub fn ray(&self, film: Vec2) -> Ray {
        self.ray_through(self.intrinsics.plane(film))
    }

    /// The ray through point `q` of the plane z = 1 (camera frame).
    #[inline]
    pub fn ray_through(&self, q: Vec2) -> Ray {
        let d = Vec3::new(q.x, q.y, 1.0).normalize();
        // Start on the near plane, as Mitsuba does.
        let local_o = d * (self.near_clip / d.z);
        let world_d = self.to_world.vector(d);
        // Distances scale with the transform; the far plane is at far_clip / d.z along d.
        let scale = world_d.length();
        Ray {
            o: self.to_world.point(local_o),
            d: world_d / scale,
            t_max: (self.far_clip - self.near_clip) / d.z * scale,
            time: 0.0,
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
        let film = self.intrinsics.film(Vec2::new(q.x / q.z, q.y / q.z));
        let k = &self.intrinsics;
        let (lo, hi) = (-margin, Vec2::new(k.width, k.height) + margin);
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
            importance: k.width * k.height / (4.0 * k.tan_half.x * k.tan_half.y * cos * cos * cos),
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
        self.intrinsics.tan_half
    }
}

/// A world point as the camera sees it (`Pinhole::project`).
#[derive(Clone, Copy, Debug)]
pub struct Projection {
    /// Film position in pixels, as `Pinhole::ray` takes it.
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
        let cam = Pinhole::new(t, 50.0, FovAxis::X, 0.01, 100.0, 320, 180);
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
        let cam = Pinhole::new(t, 39.3077, FovAxis::Smaller, 0.001, 100.0, 256, 256);
        let c = cam.ray(Vec2::new(128.0, 128.0));
        assert!((c.d - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-6);
        // The image's right edge looks towards world +x, the top edge towards +y.
        assert!(cam.ray(Vec2::new(256.0, 128.0)).d.x > 0.3);
        assert!(cam.ray(Vec2::new(128.0, 0.0)).d.y > 0.3);
        let half = portable::asin(cam.ray(Vec2::new(256.0, 128.0)).d.x).to_degrees();
        assert!((half - 39.3077 / 2.0).abs() < 1e-3);
    }

    #[test]
    fn fov_axes() {
        let t = Transform::IDENTITY;
        let wide = Pinhole::new(t, 60.0, FovAxis::Y, 0.01, 1e4, 200, 100);
        assert!((wide.tan_half_fov().y - portable::tan(30f32.to_radians())).abs() < 1e-6);
        let smaller = Pinhole::new(t, 60.0, FovAxis::Smaller, 0.01, 1e4, 200, 100);
        assert_eq!(wide.tan_half_fov(), smaller.tan_half_fov());
        let d = Pinhole::new(t, 60.0, FovAxis::Diagonal, 0.01, 1e4, 300, 400);
        assert!((d.tan_half_fov().length() - portable::tan(30f32.to_radians())).abs() < 1e-6);
    }
}
