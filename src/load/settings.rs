//! The render settings of a scene, checked before anything loads: the spectral range, the
//! camera and film, the sampler and the integrator (`load::build` calls them in this order, so
//! the first mistake in a file is the one reported).

use super::check::check;
use super::geometry;
use super::MAX_NM;
use crate::camera::Camera;
use crate::config::{self, SceneConfig};
use crate::error::InputError;
use crate::filter::{Filter, FilterConfig};
use crate::integrator::SUPPORTED_LANES;
use std::path::Path;

/// `spectral.wavelengths` and `spectral.range`, checked; the range in nm.
pub(super) fn spectral_range(cfg: &SceneConfig, file: &Path) -> Result<(f32, f32), InputError> {
    let sp = &cfg.spectral;
    check(
        SUPPORTED_LANES.contains(&sp.wavelengths),
        file,
        "spectral.wavelengths",
        format!(
            "{} wavelengths per path is not supported; use one of {SUPPORTED_LANES:?}",
            sp.wavelengths
        ),
    )?;
    let (lo, hi) = sp.range;
    // The upper bound keeps every table over the range (sensor curves, sampling pdfs, 0.05 nm
    // integration cells) bounded: a range to 1e9 nm made them run for hours.
    check(
        lo.is_finite() && hi.is_finite() && lo > 0.0 && lo < hi && hi <= MAX_NM,
        file,
        "spectral.range",
        format!("the range ({lo}, {hi}) nm must be positive, increasing and end by {MAX_NM} nm"),
    )
    .map_err(|e| {
        e.hint("e.g. range: (360, 830) for the visible, (360, 1000) with near infrared")
    })?;
    Ok((lo, hi))
}

/// The camera and film, checked; the camera.
pub(super) fn camera(cfg: &SceneConfig, file: &Path) -> Result<Camera, InputError> {
    // Camera and film.
    let c = &cfg.camera;
    check(
        c.fov.is_finite() && c.fov > 0.0 && c.fov < 180.0,
        file,
        "camera.fov",
        format!("fov {} must lie in (0, 180) degrees", c.fov),
    )?;
    // Parallel rays may start on the camera's plane (glTF's orthographic znear may be 0);
    // perspective rays start on the near plane, which must lie in front of the pinhole.
    let ortho = matches!(c.model, config::CameraModel::Orthographic { .. });
    check(
        c.near_clip.is_finite() && (c.near_clip > 0.0 || ortho && c.near_clip == 0.0),
        file,
        "camera.near_clip",
        format!(
            "near_clip {} must be > 0{}",
            c.near_clip,
            if ortho { " (or 0, orthographic)" } else { "" }
        ),
    )?;
    check(
        c.far_clip > c.near_clip,
        file,
        "camera.far_clip",
        format!(
            "far_clip {} must exceed near_clip {}",
            c.far_clip, c.near_clip
        ),
    )?;
    let f = &cfg.film;
    check(
        f.width > 0 && f.height > 0,
        file,
        "film",
        format!(
            "the film size {}×{} must be at least 1×1",
            f.width, f.height
        ),
    )?;
    check(
        f.width <= 1 << 15 && f.height <= 1 << 15,
        file,
        "film",
        "the film is larger than 32768 pixels on a side",
    )?;
    match f.filter {
        FilterConfig::Box { radius } => check(
            radius.is_finite() && radius > 0.0 && radius <= 8.0,
            file,
            "film.filter.radius",
            format!("box radius {radius} must lie in (0, 8] pixels"),
        )?,
        FilterConfig::Gaussian { stddev } => check(
            stddev.is_finite() && stddev > 0.0 && stddev <= 2.0,
            file,
            "film.filter.stddev",
            format!("gaussian stddev {stddev} must lie in (0, 2] pixels"),
        )?,
    }
    let cam_t = geometry::transform(&c.to_world, file, "camera.to_world")?;
    super::extent::check_point(
        cam_t.m.w_axis.truncate(),
        file,
        "camera.to_world",
        "the camera",
    )?;
    if let Some(why) = crate::camera::pose_error(&cam_t) {
        return Err(InputError::new(
            file,
            format!("the camera's to_world is not a rotation, translation and uniform scale: {why}"),
        )
        .field("camera.to_world")
        .hint("remove the Scale or Matrix entry that scales the axes unequally, shears or mirrors; a camera's image is set by fov or intrinsics, not by scaling its transform"));
    }
    super::camera::camera(
        c,
        cam_t,
        (f.width, f.height),
        Filter::new(&f.filter).radius(),
        cfg.integrator.caustics.is_some(),
        file,
    )
}

/// The sampler and the integrator's settings, checked.
pub(super) fn check_integrator(cfg: &SceneConfig, file: &Path) -> Result<(), InputError> {
    // Sampler and integrator.
    let s = &cfg.sampler;
    if let Some((sub, message)) = s.spp.problem(s.kind) {
        return Err(InputError::new(file, message)
            .field(format!("sampler.spp{sub}"))
            .hint("spp is a whole number ≥ 1, or Adaptive(rel_error: 0.01, min: 16, max: 4096) with min ≤ max (scenes/README.md)"));
    }
    check(
        cfg.integrator.max_depth >= -1,
        file,
        "integrator.max_depth",
        "max_depth must be −1 (unbounded) or ≥ 0",
    )?;
    if let Some(c) = cfg.integrator.clamp {
        check(
            c.is_finite() && c > 0.0,
            file,
            "integrator.clamp",
            "clamp must be a positive radiance (or left out: no clamping)",
        )?;
    }

    if let Some(c) = &cfg.integrator.caustics {
        check(
            c.light_paths.is_finite() && c.light_paths > 0.0,
            file,
            "integrator.caustics.light_paths",
            "light_paths must be a positive number of light paths per camera sample (default 0.1)",
        )?;
        check(
            c.bright_ratio.is_finite() && c.bright_ratio > 0.0,
            file,
            "integrator.caustics.bright_ratio",
            "bright_ratio must be a positive multiple of the environment map's mean (default 50)",
        )?;
        check(
            (0.0..=1.0).contains(&c.max_roughness),
            file,
            "integrator.caustics.max_roughness",
            "max_roughness must be a microfacet roughness α in [0, 1] (default 0.3; 0: Dirac lobes only)",
        )?;
    }
    Ok(())
}
