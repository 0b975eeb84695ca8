//! Cameras, with Mitsuba 3's frame: in camera space they look along +z with +y up and +x to the
//! left, so a Mitsuba `to_world` or look-at ports unchanged. One enum, matched once per camera
//! ray: the pinhole (prism's original camera, unchanged bit for bit), the pinhole seen through
//! OpenCV's lens distortion, the thin lens (depth of field) and the orthographic camera.
//!
//! Intrinsics: every perspective model maps a film position (pixels, (0,0) the top-left corner,
//! pixel centres at i + 0.5) to a point on the plane z = 1 through `Intrinsics`; a distorted
//! camera reads that point as OpenCV's *distorted* normalised coordinate and undistorts it
//! (`Distortion::undistort`, Newton's method on the forward model), so the image is what a real
//! camera with that calibration records.

mod distortion;
mod ortho;
mod pinhole;
mod thin_lens;

pub use distortion::Distortion;
pub use ortho::Orthographic;
pub use pinhole::{FovAxis, Intrinsics, Pinhole, Projection};
pub use thin_lens::{ThinLens, LENS_DIM};

use crate::math::portable;
use crate::math::Transform;
use crate::ray::Ray;
use crate::sampler::PixelSampler;
use glam::{DMat3, DMat4, DVec3, Vec2, Vec3};

#[derive(Clone, Debug, PartialEq)]
pub enum Camera {
    Pinhole(Pinhole),
    /// A pinhole behind an OpenCV distortion (k1, k2, p1, p2, k3).
    Distorted(Pinhole, Distortion),
    ThinLens(ThinLens),
    Orthographic(Orthographic),
}

impl Camera {
    /// A pinhole camera (see `Pinhole::new`).
    pub fn new(
        to_world: Transform,
        fov_deg: f32,
        axis: FovAxis,
        near_clip: f32,
        far_clip: f32,
        width: u32,
        height: u32,
    ) -> Self {
        Camera::Pinhole(Pinhole::new(
            to_world, fov_deg, axis, near_clip, far_clip, width, height,
        ))
    }

    /// The ray through film position `film` (pixels; (0,0) is the top-left corner of the image).
    /// Only the thin lens draws from `sampler` (two numbers at `LENS_DIM`), so the other
    /// models use exactly the sample dimensions they always did.
    #[inline]
    pub fn ray(&self, film: Vec2, sampler: &mut PixelSampler) -> Ray {
        match self {
            Camera::Pinhole(p) => p.ray(film),
            Camera::Distorted(p, d) => p.ray_through(d.undistort_plane(p.intrinsics.plane(film))),
            Camera::ThinLens(t) => {
                sampler.set_dimension(LENS_DIM);
                t.ray(film, sampler.next_2d())
            }
            Camera::Orthographic(o) => o.ray(film),
        }
    }

    /// The ray through the pixel-centred film position `film` and the centre of the lens (for
    /// the first-hit layers, which sample no lens).
    pub fn center_ray(&self, film: Vec2) -> Ray {
        match self {
            Camera::Pinhole(p) => p.ray(film),
            Camera::Distorted(p, d) => p.ray_through(d.undistort_plane(p.intrinsics.plane(film))),
            Camera::ThinLens(t) => t.ray(film, Vec2::splat(0.5)),
            Camera::Orthographic(o) => o.ray(film),
        }
    }

    /// Where the camera sees world point `p`, for the caustic light tracer (see
    /// `Pinhole::project`). Only the pinhole connects light paths to the camera; the scene
    /// loader refuses caustics with the other models, so they never get here.
    #[inline]
    pub fn project(&self, p: Vec3, margin: f32) -> Option<Projection> {
        match self {
            Camera::Pinhole(c) => c.project(p, margin),
            _ => None,
        }
    }

    /// The model's name, as the sidecar and error messages write it.
    pub fn model(&self) -> &'static str {
        match self {
            Camera::Pinhole(_) => "pinhole",
            Camera::Distorted(..) => "pinhole+distortion",
            Camera::ThinLens(_) => "thin_lens",
            Camera::Orthographic(_) => "orthographic",
        }
    }

    /// The same camera at another pose (a moving camera at another time: `integrator::flow`).
    pub fn with_to_world(&self, to_world: Transform) -> Camera {
        let pin = |p: &Pinhole| {
            Pinhole::with_intrinsics(to_world, p.intrinsics, p.near_clip(), p.far_clip())
        };
        match self {
            Camera::Pinhole(p) => Camera::Pinhole(pin(p)),
            Camera::Distorted(p, d) => Camera::Distorted(pin(p), *d),
            Camera::ThinLens(t) => Camera::ThinLens(ThinLens {
                pinhole: pin(&t.pinhole),
                ..t.clone()
            }),
            Camera::Orthographic(o) => Camera::Orthographic(Orthographic {
                to_world,
                ..o.clone()
            }),
        }
    }

    pub fn to_world(&self) -> &Transform {
        match self {
            Camera::Pinhole(p) | Camera::Distorted(p, _) => &p.to_world,
            Camera::ThinLens(t) => &t.pinhole.to_world,
            Camera::Orthographic(o) => &o.to_world,
        }
    }

    /// The film-to-plane map (for the orthographic camera: to camera-space x, y in world units).
    pub fn intrinsics(&self) -> &Intrinsics {
        match self {
            Camera::Pinhole(p) | Camera::Distorted(p, _) => &p.intrinsics,
            Camera::ThinLens(t) => &t.pinhole.intrinsics,
            Camera::Orthographic(o) => &o.intrinsics,
        }
    }

    pub fn distortion(&self) -> Option<&Distortion> {
        match self {
            Camera::Distorted(_, d) => Some(d),
            Camera::ThinLens(t) => t.distortion.as_ref(),
            _ => None,
        }
    }

    pub fn near_clip(&self) -> f32 {
        match self {
            Camera::Pinhole(p) | Camera::Distorted(p, _) => p.near_clip(),
            Camera::ThinLens(t) => t.pinhole.near_clip(),
            Camera::Orthographic(o) => o.near_clip,
        }
    }

    pub fn far_clip(&self) -> f32 {
        match self {
            Camera::Pinhole(p) | Camera::Distorted(p, _) => p.far_clip(),
            Camera::ThinLens(t) => t.pinhole.far_clip(),
            Camera::Orthographic(o) => o.far_clip,
        }
    }

    /// Camera position in world space (the lens centre; the orthographic camera's film centre).
    pub fn position(&self) -> Vec3 {
        self.to_world().point(Vec3::ZERO)
    }

    /// tan of the half field of view along x and y (for the orthographic camera: the film's
    /// half extent in camera units).
    pub fn tan_half_fov(&self) -> Vec2 {
        self.intrinsics().tan_half
    }

    /// World → OpenCV's camera frame (x right, y down, z forward): x_cam = R·x_world + t, in
    /// world units. A uniform scale in `to_world` (which changes no ray direction) is divided
    /// out of its columns; the loader refuses any other linear part (`pose_error`).
    pub fn world_to_opencv(&self) -> (DMat3, DVec3) {
        let m = self.to_world().m.as_dmat4();
        let axis = |v: glam::DVec4| v.truncate().normalize();
        // prism's camera frame is Mitsuba's: +x left, +y up, +z forward.
        let c2w = DMat3::from_cols(-axis(m.x_axis), -axis(m.y_axis), axis(m.z_axis));
        let r = c2w.transpose();
        (r, -(r * m.w_axis.truncate()))
    }

    /// OpenCV's Rodrigues vector of `world_to_opencv`'s R (axis × angle, angle in [0, π]),
    /// through R's quaternion, which stays exact near π where the skew-part formula
    /// angle / (2 sin angle) · (R − Rᵀ) loses the axis (a camera turned 180° gave [0, 0, 0]).
    pub fn rvec_opencv(&self) -> DVec3 {
        let q = glam::DQuat::from_mat3(&self.world_to_opencv().0).normalize();
        // q and −q are the same rotation: w ≥ 0 keeps the angle in [0, π].
        let (v, w) = if q.w < 0.0 {
            (-q.xyz(), -q.w)
        } else {
            (q.xyz(), q.w)
        };
        let s = v.length();
        if s == 0.0 {
            return DVec3::ZERO;
        }
        v * (2.0 * portable::atan2(s, w) / s)
    }

    /// Camera → world in OpenGL's (and Blender's) camera frame: x right, y up, looking along −z.
    pub fn camera_to_world_opengl(&self) -> DMat4 {
        let m = self.to_world().m.as_dmat4();
        let axis = |v: glam::DVec4| v.truncate().normalize().extend(0.0);
        DMat4::from_cols(-axis(m.x_axis), axis(m.y_axis), -axis(m.z_axis), m.w_axis)
    }
}

/// Why a camera `to_world` is not a rotation times a uniform positive scale (None when it is).
/// A shear, a non-uniform scale or a mirror changes the rays in ways no R, t and K describe,
/// so the sidecar could not state the camera exactly. The tolerance, 1e-4 relative, is far
/// above f32 rounding of composed rotations and look-ats (~1e-6) and far below any
/// deliberate scale or shear.
pub fn pose_error(to_world: &Transform) -> Option<String> {
    let m = glam::DMat3::from_mat4(to_world.m.as_dmat4());
    let cols = [m.x_axis, m.y_axis, m.z_axis];
    let len = cols.map(|c| c.length());
    let s = (len[0] + len[1] + len[2]) / 3.0;
    let tol = 1e-4;
    if !(s.is_finite() && s > 0.0) {
        return Some("its linear part is degenerate (a zero scale)".into());
    }
    if len.iter().any(|l| (l - s).abs() > tol * s) {
        return Some(format!(
            "it scales the camera's axes unequally (column lengths {:.6}, {:.6}, {:.6})",
            len[0], len[1], len[2]
        ));
    }
    let dots = [
        cols[0].dot(cols[1]),
        cols[0].dot(cols[2]),
        cols[1].dot(cols[2]),
    ];
    if dots.iter().any(|d| d.abs() > tol * s * s) {
        return Some("it shears the camera (its axes are not perpendicular)".into());
    }
    if m.determinant() < 0.0 {
        return Some("it mirrors the camera (a negative scale)".into());
    }
    None
}
