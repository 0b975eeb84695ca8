//! The camera variation's `intrinsics` and `distortion` ranges: OpenCV's K (fx, fy, cx, cy) and
//! distortion coefficients (k1, k2, p1, p2, k3) drawn per frame, each uniformly in its range,
//! written into the frame's `camera.intrinsics`/`camera.distortion` (so the sidecar's K and
//! distortion are the drawn values) and listed in the frame's JSON.
//!
//! Checked whole at load: the radial slope 1 + 3k1r² + 5k2r⁴ + 7k3r⁶ is linear in (k1, k2, k3)
//! at every r, so its minimum over the box of coefficients lies at a corner, and the frame's
//! farthest corner radius is largest at a corner of the K box: every corner of the joint box
//! (K × distortion, up to 2⁹ combinations) goes through the scene load's own one-to-one check
//! (`Distortion::check_frame`), so a range whose draws could fold inside the frame (and give
//! NaN rays) is refused before any frame.

use super::base::Base;
use super::config::{DistortionRange, IntrinsicsRange, Range};
use super::vary::{Rng, Stream};
use crate::camera::{Distortion, Intrinsics};
use crate::config::{CameraConfig, CameraModel, DistortionConfig, IntrinsicsConfig};
use crate::error::InputError;
use serde_json::{json, Value};

/// Draws frame `i`'s K and distortion into `cam`; None (and `cam` untouched) without ranges.
pub fn draw(base: &Base, i: u32, cam: &mut CameraConfig) -> Option<Value> {
    let v = base.config.camera.as_ref()?;
    if v.intrinsics.is_none() && v.distortion.is_none() {
        return None;
    }
    let mut r = Rng::new(base.config.seed, i, Stream::Intrinsics);
    let mut out = serde_json::Map::new();
    if let Some(k) = &v.intrinsics {
        let fx = r.range(k.fx) as f64;
        let fy = k.fy.map_or(fx, |y| r.range(y) as f64);
        let (cx, cy) = (r.range(k.cx) as f64, r.range(k.cy) as f64);
        cam.intrinsics = Some(IntrinsicsConfig { fx, fy, cx, cy });
        out.insert(
            "K".into(),
            json!([[fx, 0.0, cx], [0.0, fy, cy], [0.0, 0.0, 1.0]]),
        );
    }
    if let Some(d) = &v.distortion {
        let c = [d.k1, d.k2, d.p1, d.p2, d.k3].map(|x| r.range(x) as f64);
        cam.distortion = Some(DistortionConfig {
            k1: c[0],
            k2: c[1],
            p1: c[2],
            p2: c[3],
            k3: c[4],
        });
        out.insert("distortion".into(), json!(c));
    }
    Some(Value::Object(out))
}

/// The ranges checked: finite, not inverted, fx and fy positive, no `fov` beside K, no
/// distortion on an orthographic camera or with `keep_in_view` (whose projection is the
/// pinhole's), and every corner of the joint box one-to-one over the frame.
pub fn check(base: &Base) -> Result<(), InputError> {
    let Some(v) = &base.config.camera else {
        return Ok(());
    };
    let err = |field: &str, m: String| base.err(&format!("camera.{field}"), m);
    let mut ranges: Vec<(String, Range)> = Vec::new();
    if let Some(k) = &v.intrinsics {
        ranges.extend([("fx", k.fx), ("cx", k.cx), ("cy", k.cy)].map(|(n, r)| (n.into(), r)));
        ranges.extend(k.fy.map(|r| ("fy".to_string(), r)));
        if v.fov.is_some() {
            return Err(
                err("intrinsics", "K replaces `fov`: give one of them".into())
                    .hint("drop `fov` (fx, fy set the field of view) or drop `intrinsics`"),
            );
        }
    }
    if let Some(d) = &v.distortion {
        let named = [
            ("k1", d.k1),
            ("k2", d.k2),
            ("p1", d.p1),
            ("p2", d.p2),
            ("k3", d.k3),
        ];
        ranges.extend(named.map(|(n, r)| (n.into(), r)));
        if matches!(base.scene.camera.model, CameraModel::Orthographic { .. }) {
            return Err(err(
                "distortion",
                "the orthographic camera takes no lens distortion".into(),
            )
            .hint("drop `distortion`, or give the scene's camera `model: Pinhole`"));
        }
        if !v.keep_in_view.is_empty() {
            return Err(err("distortion", "keep_in_view tests the undistorted pinhole's view, not a distorted one".into())
                .hint("drop `keep_in_view` (or the distortion ranges); a shell radius that keeps the shapes well inside the frame does the same"));
        }
    }
    for (n, (lo, hi)) in &ranges {
        let group = if n.starts_with(['k', 'p']) {
            "distortion"
        } else {
            "intrinsics"
        };
        let field = format!("{group}.{n}");
        if !(lo.is_finite() && hi.is_finite()) || lo > hi {
            return Err(err(
                &field,
                format!("the range ({lo}, {hi}) is not a finite (lo, hi)"),
            )
            .hint("write it as (lo, hi) with lo ≤ hi"));
        }
        if (n == "fx" || n == "fy") && *lo <= 0.0 {
            return Err(
                err(&field, format!("{n} ({lo}, {hi}) must be positive pixels"))
                    .hint("focal lengths in pixels: fx = width / (2 tan(fov_x / 2))"),
            );
        }
    }
    corners(base, v.intrinsics.as_ref(), v.distortion.as_ref())
}

/// Each corner of the joint box through `Distortion::check_frame`.
fn corners(
    base: &Base,
    k: Option<&IntrinsicsRange>,
    d: Option<&DistortionRange>,
) -> Result<(), InputError> {
    let Some(d) = d else { return Ok(()) };
    let f = &base.scene.film;
    let (w, h) = base
        .config
        .outputs
        .resolution
        .unwrap_or((f.width, f.height));
    let margin = crate::filter::Filter::new(&f.filter).radius();
    let fovs: Vec<Intrinsics> = match k {
        Some(k) => {
            let ends = |r: Range| [r.0 as f64, r.1 as f64];
            let mut all = Vec::new();
            for fx in ends(k.fx) {
                for fy in k.fy.map_or([fx, fx], ends) {
                    for cx in ends(k.cx) {
                        for cy in ends(k.cy) {
                            all.push(Intrinsics::from_k(fx, fy, cx, cy, w, h));
                        }
                    }
                }
            }
            all
        }
        None => {
            let c = &base.scene.camera;
            let fov = base.config.camera.as_ref().and_then(|v| v.fov);
            let (a, b) = fov.unwrap_or((c.fov, c.fov));
            [a, b]
                .map(|x| Intrinsics::from_fov(x, c.fov_axis, w, h))
                .to_vec()
        }
    };
    let ranges = [d.k1, d.k2, d.p1, d.p2, d.k3];
    for bits in 0..32u32 {
        let c: Vec<f64> = (0..5)
            .map(|j| {
                let r = ranges[j];
                (if bits >> j & 1 == 0 { r.0 } else { r.1 }) as f64
            })
            .collect();
        let dist = Distortion {
            k1: c[0],
            k2: c[1],
            p1: c[2],
            p2: c[3],
            k3: c[4],
        };
        for k in &fovs {
            if let Err(why) = dist.check_frame(k, margin) {
                return Err(base
                    .err(
                        "camera.distortion",
                        format!(
                            "at the corner (k1, k2, p1, p2, k3) = ({}, {}, {}, {}, {}) of the ranges: {why}",
                            c[0], c[1], c[2], c[3], c[4]
                        ),
                    )
                    .hint("every draw must map the frame one-to-one: narrow the ranges (smaller |k1|, |k2|, |k3|) or the field of view (larger fx, fy)"));
            }
        }
    }
    Ok(())
}
