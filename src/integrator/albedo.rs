//! The `albedo` AOV: the diffuse reflectance spectrum of the material at each pixel-centre hit
//! (the analogue of Mitsuba 3's `albedo` AOV, which reports `eval_diffuse_reflectance`), with
//! textures evaluated at the hit's uv. Each material defines its own
//! (`Material::diffuse_reflectance`, scenes/README.md "AOVs"); background: 0.
//!
//! `albedo.R/G/B`: linear sRGB of the reflectance seen under D65, sRGB's white
//! (XYZ = ∫ρ·D65·cmf dλ / ∫D65·ȳ dλ, CIE 1931 observer, then XYZ → sRGB), so a constant ρ gives
//! R = G = B = ρ and an `Rgb(r, g, b)` reflectance gives back ≈ (r, g, b). Per band (spectral sensors): ρ averaged over the band's [lo, hi), named as
//! the film's band channels (`albedo.S0.<λ>nm`).

use super::aov::Hit;
use crate::film::Channel;
use crate::scene::Scene;
use crate::spectrum::color;
use glam::Vec3;
use rayon::prelude::*;

/// Weights w_c(λ_i) on the CMF's 1 nm grid (trapezoid rule) with Σ_i w_c(λ_i)·ρ(λ_i) the
/// colour c of ρ under D65, normalised so that ρ = 1 gives Y = 1.
fn xyz_weights() -> Vec<(f32, [f64; 3])> {
    let cmf = color::cie1931();
    let d65 = crate::spectrum::data::named_illuminant("D65").expect("D65 is embedded");
    let (lo, hi) = cmf.range();
    let n = (hi - lo).round() as usize;
    let mut w: Vec<(f32, [f64; 3])> = (0..=n)
        .map(|i| {
            let l = lo + i as f32;
            let t = if i == 0 || i == n { 0.5 } else { 1.0 };
            let e = d65.eval_one(l) as f64 * t;
            (l, cmf.eval(l).map(|c| c as f64 * e))
        })
        .collect();
    let y: f64 = w.iter().map(|(_, c)| c[1]).sum();
    for (_, c) in &mut w {
        *c = c.map(|v| v / y);
    }
    w
}

/// ρ averaged over [lo, hi) (midpoint rule, cells of at most 0.5 nm).
fn band_mean(lo: f32, hi: f32, f: impl Fn(f32) -> f32) -> f32 {
    let n = (((hi - lo) * 2.0).ceil() as usize).max(1);
    let h = (hi - lo) as f64 / n as f64;
    ((0..n)
        .map(|i| f((lo as f64 + (i as f64 + 0.5) * h) as f32) as f64)
        .sum::<f64>()
        / n as f64) as f32
}

/// `albedo.R/G/B` (with `rgb`) and, with `bands`, one `albedo.<band>` per band, from the
/// pixel-centre hits. R/G/B does not depend on the sensor: an extra sensor's layer is its
/// bands alone (`pipeline::add_layers`).
pub fn layers(
    scene: &Scene,
    hits: &[Option<Hit>],
    sensor: &crate::sensor::Sensor,
    rgb: bool,
) -> Vec<Channel> {
    let bands = sensor.bands();
    let weights = xyz_weights();
    let nb = bands.map_or(0, |b| b.count as usize);
    let per_pixel: Vec<Vec<f32>> = hits
        .par_iter()
        .with_min_len(64)
        .map(|h| {
            let mut v = vec![0.0f32; 3 + nb];
            let Some(h) = h else { return v };
            let m = &scene.materials[scene.shape_material[h.shape as usize] as usize];
            let f = |l: f32| m.diffuse_reflectance(h.tex, h.front, l);
            if rgb {
                let mut xyz = [0.0f64; 3];
                for (l, w) in &weights {
                    let r = f(*l) as f64;
                    (0..3).for_each(|c| xyz[c] += w[c] * r);
                }
                let c = color::xyz_to_srgb(Vec3::new(xyz[0] as f32, xyz[1] as f32, xyz[2] as f32));
                v[..3].copy_from_slice(&c.to_array());
            }
            if let Some(b) = bands {
                for k in 0..b.count {
                    let l0 = b.lo + k as f32 * b.width();
                    v[3 + k as usize] = band_mean(l0, l0 + b.width(), f);
                }
            }
            v
        })
        .collect();
    let mut names: Vec<String> = ["R", "G", "B"].map(|c| format!("albedo.{c}")).to_vec();
    if let Some(b) = bands {
        names.extend((0..b.count).map(|k| format!("albedo.{}", sensor.band_name(k))));
    }
    names
        .into_iter()
        .enumerate()
        .skip(if rgb { 0 } else { 3 })
        .map(|(c, name)| Channel {
            name,
            data: per_pixel.iter().map(|v| v[c]).collect(),
        })
        .collect()
}
