//! The sensor's spectral channels for `prism export` (the `"sensor"` key of scene.json), so
//! another renderer can record the same channels (Mitsuba 3's `specfilm`: one sensor response
//! function per channel; tools/prism_tools/mitsuba_scene.py).
//!
//! Each entry is `{"name", "srf", "gain"}`: the EXR channel `name` holds
//! `gain · ∫ L(λ) srf(λ) dλ` over the spectral range, where `srf` is tabulated
//! (`{"type": "irregular", "wavelengths", "values"}`, linear between samples, 0 outside) and
//! clipped to the spectral range (prism samples no wavelength outside it). Entries: the even
//! bands (a box each, gain 1 / width), the box bands and filters (gain 1 / ∫ shape), then a
//! camera's R, G, B as `camera.R/G/B` (gain k · m_c / ∫ ḡ: exposure and white balance, see
//! camera.rs). XYZ and the RGB spaces are not listed: they are the observer's, which the
//! exporter's `outputs` already describes.

use super::{Response, Sensor, Shape};
use serde_json::{json, Value};

/// The channel list (module docs) for the spectral range [lo, hi].
pub fn channels(sensor: &Sensor, lo: f32, hi: f32) -> Value {
    let mut out = Vec::new();
    if let Some(b) = sensor.bands() {
        let w = b.width();
        for k in 0..b.count {
            let (a, z) = (b.lo + k as f32 * w, b.lo + (k + 1) as f32 * w);
            let srf = irregular(&[a, z], &[1.0, 1.0]);
            out.push(json!({"name": sensor.band_name(k), "srf": srf, "gain": 1.0 / w}));
        }
    }
    let names = &sensor.layers.responses;
    let camera = sensor.layers.camera.as_ref();
    for (k, r) in sensor.responses().iter().enumerate() {
        // The raw model's photon-count slots feed `raw.Y`, computed after the render: no
        // film channel of their own, nothing for a spectral film to reproduce.
        if matches!(r.shape, Shape::Photons(_)) {
            continue;
        }
        let (name, gain) = match names.get(k) {
            Some(n) => (sensor.response_name(n), r.scale),
            None => {
                // The camera's three curves follow the named responses.
                let c = k - names.len();
                let cam = camera.expect("responses past the named ones are the camera's");
                let name = format!("camera.{}", ["R", "G", "B"][c]);
                (name, r.scale * cam.white_balance[c] * cam.exposure)
            }
        };
        out.push(json!({"name": name, "srf": srf(r, lo, hi), "gain": gain}));
    }
    Value::Array(out)
}

fn irregular(nm: &[f32], values: &[f32]) -> Value {
    json!({"type": "irregular", "wavelengths": nm, "values": values})
}

/// The response's shape on [lo, hi]: its own samples inside the range, plus the range's ends
/// where the shape reaches past them (so the tabulation stays exact where prism renders).
fn srf(r: &Response, lo: f32, hi: f32) -> Value {
    match &r.shape {
        Shape::Box { lo: a, hi: z } => irregular(&[a.max(lo), z.min(hi)], &[1.0, 1.0]),
        Shape::Curve(c) | Shape::Photons(c) => {
            let weight = |l: f32| match r.shape {
                Shape::Photons(_) => l,
                _ => 1.0,
            };
            let Some((knots, _)) = c.tabulate(lo, hi) else {
                let v = c.eval_one(lo);
                if matches!(r.shape, Shape::Photons(_)) {
                    return irregular(&[lo, hi], &[v * lo, v * hi]);
                }
                return irregular(&[lo, hi], &[v, v]);
            };
            let (first, last) = (knots[0], knots[knots.len() - 1]);
            let mut nm = Vec::with_capacity(knots.len() + 2);
            if first < lo {
                nm.push(lo);
            }
            nm.extend(knots.iter().copied().filter(|&l| l >= lo && l <= hi));
            if last > hi {
                nm.push(hi);
            }
            nm.dedup();
            let values: Vec<f32> = nm.iter().map(|&l| c.eval_one(l) * weight(l)).collect();
            irregular(&nm, &values)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::Curve;

    /// A curve sampled at 300..1100 nm is cut to a 360–1000 nm render, exactly at the ends; a
    /// box band keeps its edges.
    #[test]
    fn responses_are_clipped_to_the_range() {
        let c = Curve::from_samples(&[300.0, 700.0, 1100.0], &[0.0, 1.0, 0.0]);
        let r = Response {
            shape: Shape::Curve(c),
            scale: 1.0,
        };
        let v = srf(&r, 360.0, 1000.0);
        let nm: Vec<f64> = serde_json::from_value(v["wavelengths"].clone()).unwrap();
        let vals: Vec<f64> = serde_json::from_value(v["values"].clone()).unwrap();
        assert_eq!(nm, vec![360.0, 700.0, 1000.0]);
        assert!((vals[0] - 0.15).abs() < 1e-6 && vals[1] == 1.0 && (vals[2] - 0.25).abs() < 1e-6);
        let b = Response {
            shape: Shape::Box {
                lo: 840.0,
                hi: 860.0,
            },
            scale: 0.05,
        };
        assert_eq!(srf(&b, 360.0, 1000.0)["wavelengths"], json!([840.0, 860.0]));
    }
}
