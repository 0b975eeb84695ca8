//! The camera's model, intrinsics and lens distortion (fields of `camera:`).

use serde::{Deserialize, Serialize};

/// `model: ThinLens(aperture_radius: 0.05, focus_distance: 3.0)`
///
/// `Pinhole` (default), `ThinLens` (depth of field; Mitsuba's `thinlens`) or
/// `Orthographic(width: 2.0)` (parallel rays; the film spans `width` camera units, or give
/// `intrinsics` in pixels per unit).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum CameraModel {
    #[default]
    Pinhole,
    /// `aperture_radius` (> 0, scene units) and `focus_distance` (> 0: the plane z = focus
    /// distance in front of the lens is sharp).
    ThinLens {
        aperture_radius: f32,
        focus_distance: f32,
    },
    /// `width`: the film's width in camera units (needed unless `intrinsics` are given).
    Orthographic {
        #[serde(default)]
        width: Option<f32>,
    },
}

/// `intrinsics: (fx: 500, fy: 500, cx: 319.5, cy: 239.5)`
///
/// OpenCV's K in pixels, in OpenCV's pixel convention (pixel centres at integers: the image
/// centre of a 640-pixel-wide film is cx = 319.5), so a calibration's K is used as it is;
/// replaces `fov`. For the orthographic camera fx, fy are pixels per camera unit.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IntrinsicsConfig {
    pub fx: f64,
    pub fy: f64,
    pub cx: f64,
    pub cy: f64,
}

/// `distortion: (k1: -0.2, k2: 0.05, p1: 0.001, p2: 0, k3: 0)`
///
/// OpenCV's distortion coefficients (its order; each default 0), rendered exactly: the image
/// is what a camera with this calibration records. Coefficients whose map folds inside the
/// frame are refused.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct DistortionConfig {
    pub k1: f64,
    pub k2: f64,
    pub p1: f64,
    pub p2: f64,
    pub k3: f64,
}
