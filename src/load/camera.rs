//! `camera:` → a `Camera`: the model, its intrinsics (a field of view or OpenCV's K) and lens
//! distortion, with every check a user's mistake can trip.

use super::check::check;
use crate::camera::{Camera, Distortion, Intrinsics, Orthographic, Pinhole, ThinLens};
use crate::config::{CameraConfig, CameraModel};
use crate::error::InputError;
use crate::math::Transform;
use std::path::Path;

/// `margin`: how far (pixels) the pixel filter reaches beyond the frame; `caustics`: the scene
/// asks for caustic light tracing, which connects light paths to a pinhole only.
pub fn camera(
    c: &CameraConfig,
    to_world: Transform,
    (width, height): (u32, u32),
    margin: f32,
    caustics: bool,
    file: &Path,
) -> Result<Camera, InputError> {
    let intrinsics = match &c.intrinsics {
        Some(k) => {
            check(
                [k.fx, k.fy].iter().all(|v| v.is_finite() && *v > 0.0),
                file,
                "camera.intrinsics",
                format!("fx {} and fy {} must be positive pixels", k.fx, k.fy),
            )?;
            check(
                k.cx.is_finite() && k.cy.is_finite(),
                file,
                "camera.intrinsics",
                "cx and cy must be finite pixels (OpenCV's convention: the centre of a 640-pixel-wide image is cx = 319.5)",
            )?;
            Some(Intrinsics::from_k(k.fx, k.fy, k.cx, k.cy, width, height))
        }
        None => None,
    };
    let perspective =
        || intrinsics.unwrap_or_else(|| Intrinsics::from_fov(c.fov, c.fov_axis, width, height));
    let distortion = match &c.distortion {
        Some(d) => {
            let dist = Distortion {
                k1: d.k1,
                k2: d.k2,
                p1: d.p1,
                p2: d.p2,
                k3: d.k3,
            };
            check(
                [d.k1, d.k2, d.p1, d.p2, d.k3].iter().all(|v| v.is_finite()),
                file,
                "camera.distortion",
                "distortion coefficients must be finite",
            )?;
            check(
                !matches!(c.model, CameraModel::Orthographic { .. }),
                file,
                "camera.distortion",
                "the orthographic camera takes no lens distortion; remove `distortion` or use `model: Pinhole`",
            )?;
            if let Err(why) = dist.check_frame(&perspective(), margin) {
                return Err(InputError::new(file, why)
                    .field("camera.distortion")
                    .hint("a real lens maps the frame one-to-one: use coefficients from a calibration of this image size, smaller |k1|, |k2|, |k3|, or a narrower field of view"));
            }
            // All-zero coefficients are the pinhole itself: render it as one.
            (dist != Distortion::default()).then_some(dist)
        }
        None => None,
    };
    let (near, far) = (c.near_clip, c.far_clip);
    let camera = match c.model {
        CameraModel::Pinhole => {
            let p = Pinhole::with_intrinsics(to_world, perspective(), near, far);
            match distortion {
                Some(d) => Camera::Distorted(p, d),
                None => Camera::Pinhole(p),
            }
        }
        CameraModel::ThinLens {
            aperture_radius,
            focus_distance,
        } => {
            check(
                aperture_radius.is_finite() && aperture_radius > 0.0,
                file,
                "camera.model.aperture_radius",
                format!("aperture_radius {aperture_radius} must be > 0 (scene units); for no depth of field use `model: Pinhole`"),
            )?;
            check(
                focus_distance.is_finite() && focus_distance > 0.0,
                file,
                "camera.model.focus_distance",
                format!("focus_distance {focus_distance} must be > 0: the distance in front of the lens (scene units) that is in focus"),
            )?;
            // A focus far nearer than the aperture is wide (1e-45 with 0.05) sends rays along
            // the lens plane: d.z underflows and the rays are NaN (fuzzer, issue 27).
            check(
                focus_distance >= 1e-4 * aperture_radius && focus_distance <= 1e18,
                file,
                "camera.model.focus_distance",
                format!("focus_distance {focus_distance} must lie in [1e-4 × aperture_radius, 1e18] (aperture_radius {aperture_radius})"),
            )?;
            Camera::ThinLens(ThinLens {
                pinhole: Pinhole::with_intrinsics(to_world, perspective(), near, far),
                distortion,
                aperture_radius,
                focus_distance,
            })
        }
        CameraModel::Orthographic { width: w } => {
            let k = match (intrinsics, w) {
                (Some(k), None) => k,
                (None, Some(w)) => {
                    check(
                        w.is_finite() && w > 0.0,
                        file,
                        "camera.model.width",
                        format!("width {w} must be > 0 camera units"),
                    )?;
                    let px = width as f64 / w as f64;
                    Intrinsics::from_k(
                        px,
                        px,
                        0.5 * width as f64 - 0.5,
                        0.5 * height as f64 - 0.5,
                        width,
                        height,
                    )
                }
                _ => return Err(InputError::new(
                    file,
                    "the orthographic camera needs its extent: `width` or `intrinsics` (not both)",
                )
                .field("camera.model")
                .hint("e.g. `model: Orthographic(width: 2.0)`: the film spans 2 scene units")),
            };
            Camera::Orthographic(Orthographic {
                to_world,
                intrinsics: k,
                near_clip: near,
                far_clip: far,
            })
        }
    };
    if caustics && !matches!(camera, Camera::Pinhole(_)) {
        return Err(InputError::new(
            file,
            format!(
                "caustic light tracing connects light paths to a pinhole camera only, not to a {} camera",
                camera.model()
            ),
        )
        .field("integrator.caustics")
        .hint("remove `caustics` (or pass `--caustics off`), or use `model: Pinhole` without distortion"));
    }
    Ok(camera)
}
