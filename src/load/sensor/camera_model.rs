//! `sensor.camera`: the camera's curves, white balance, colour-correction fit and exposure as a
//! `CameraModel`.

use super::At;
use crate::config::sensor::{CameraConfig, CameraCurves, WhiteBalance};
use crate::error::InputError;
use crate::load::{spectrum_ctx, Role};
use crate::sensor::camera::{self, CameraModel, CAMERAS};
use crate::sensor::Observer;
use crate::spectrum::{data, Curve};

pub(super) fn camera_model(
    cam: &CameraConfig,
    at: &At,
    range: (f32, f32),
    observer: Observer,
    warnings: &mut Vec<String>,
) -> Result<([Curve; 3], CameraModel), InputError> {
    let (curves, name) = match &cam.curves {
        CameraCurves::Named(n) => (
            camera::named(n).ok_or_else(|| {
                at.err("camera.curves", format!("unknown camera `{n}`"))
                    .hint(format!("the named cameras are: {}", CAMERAS.join(", ")))
            })?,
            n.clone(),
        ),
        CameraCurves::Curves { r, g, b } => {
            let mut out = Vec::new();
            for (c, s) in [("r", r), ("g", g), ("b", b)] {
                let f = at.field(&format!("camera.curves.{c}"));
                out.push(s.resolve(Role::Response, &spectrum_ctx(at.file, &f, range), warnings)?);
            }
            let [r, g, b]: [Curve; 3] = out.try_into().expect("three curves");
            ([r, g, b], "user curves".to_string())
        }
    };
    let d65 = data::named_illuminant("D65").expect("D65 is embedded");
    let wb_illum = match &cam.white_balance {
        WhiteBalance::Off => None,
        WhiteBalance::Illuminant(n) => Some(data::named_illuminant(n).ok_or_else(|| {
            at.err("camera.white_balance", format!("unknown illuminant `{n}`"))
                .hint(format!(
                    "the named illuminants are: {}",
                    data::illuminant_names().join(", ")
                ))
        })?),
        WhiteBalance::Temperature(k) => {
            if !(k.is_finite() && *k >= 1000.0 && *k <= 40000.0) {
                return Err(at.err(
                    "camera.white_balance",
                    format!("colour temperature {k} K is outside 1000–40000 K"),
                ));
            }
            Some(Curve::blackbody(*k))
        }
    };
    let m = match &wb_illum {
        Some(w) => camera::white_balance(&curves, w),
        None => glam::DVec3::ONE,
    };
    if !m.is_finite() || m.min_element() <= 0.0 {
        return Err(at.err(
            "camera.white_balance",
            "a camera channel does not respond to the white-balance illuminant",
        ));
    }
    let fit = camera::fit_matrix(
        &curves,
        m,
        wb_illum.as_ref().unwrap_or(&d65),
        &d65,
        observer.cmf(),
    );
    // Identical, zero or dependent curves leave the least-squares fit singular: its matrix is
    // NaN or enormous, and every corrected channel would be NaN (found only after rendering).
    let worst = fit
        .to_cols_array()
        .iter()
        .fold(0.0f64, |w, v| w.max(v.abs()));
    if !fit.is_finite() || worst > 1e6 {
        return Err(at
            .err(
                "camera.curves",
                format!("the three curves cannot be fitted to XYZ (the colour matrix is not finite or has an entry of {worst:e}): they are zero, equal or one is a mix of the others"),
            )
            .hint("give three different channel responses (r, g, b) that respond within the spectral range"));
    }
    let exposure = match cam.exposure {
        None => 1.0,
        Some(e) => {
            for (v, f) in [
                (e.iso, "iso"),
                (e.shutter, "shutter"),
                (e.f_number, "f_number"),
            ] {
                if !(v.is_finite() && v > 0.0) {
                    return Err(at
                        .err(
                            &format!("camera.exposure.{f}"),
                            format!("{f} is {v}; it must be a positive number"),
                        )
                        .hint("e.g. exposure: (iso: 100, shutter: 0.01, f_number: 8)"));
                }
            }
            let k = camera::exposure_scale(e.iso as f64, e.shutter as f64, e.f_number as f64);
            // Each input may be finite and the product still leave f32 (f_number 1e-21 gave
            // Inf and NaN channels): the factor itself must lie in a range that keeps any
            // plausible radiance finite and nonzero.
            if !(camera::EXPOSURE_RANGE.0..=camera::EXPOSURE_RANGE.1).contains(&k) {
                return Err(at
                    .err(
                        "camera.exposure",
                        format!(
                            "the exposure factor (iso/100) · shutter · π / (4 · f_number²) is {k:e}; it must lie in [{:e}, {:e}]",
                            camera::EXPOSURE_RANGE.0, camera::EXPOSURE_RANGE.1
                        ),
                    )
                    .hint("check iso, shutter and f_number, e.g. exposure: (iso: 100, shutter: 0.01, f_number: 8)"));
            }
            k
        }
    };
    let model = CameraModel {
        name,
        white_balance: m.as_vec3(),
        exposure: exposure as f32,
        to_xyz: fit.as_mat3(),
        corrected: cam.corrected,
    };
    Ok((curves, model))
}
