//! Unidirectional path tracing with emitter sampling, BSDF sampling and multiple importance
//! sampling (power heuristic), carrying N wavelengths per path (hero-wavelength transport).
//!
//! Depth follows Mitsuba 3's `path` integrator: a path of k segments has depth k; `max_depth` 1
//! shows only directly visible emitters, 2 adds direct lighting, −1 is unbounded. Russian
//! roulette starts once depth ≥ `rr_depth`: continue with q = min(max(β)·η², 0.95), β /= q.

use crate::bsdf::Bsdf;
use crate::math::sampling::power_heuristic;
use crate::ray::Ray;
use crate::sampler::{PixelSampler, BOUNCE_DIMS, CAMERA_DIMS};
use crate::scene::Scene;
use crate::spectrum::{Spectrum, Wavelengths};
use glam::Vec3;
use serde::{Deserialize, Serialize};

/// Settings of the `path` integrator, with Mitsuba 3's names and defaults.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PathSettings {
    /// Longest path in segments; −1 = unbounded.
    pub max_depth: i32,
    /// Depth from which Russian roulette may end paths.
    pub rr_depth: u32,
    /// Hide emitters seen directly by the camera.
    pub hide_emitters: bool,
    /// Opt-in firefly clamp: a camera sample's radiance is cut to at most this value
    /// (W m^-2 sr^-1 nm^-1) in every lane. Off by default: clamping removes energy, so it biases
    /// ground truth (darker highlights and caustics); prism counts the samples it clamped.
    pub clamp: Option<f32>,
}

impl Default for PathSettings {
    fn default() -> Self {
        Self {
            max_depth: -1,
            rr_depth: 5,
            hide_emitters: false,
            clamp: None,
        }
    }
}

/// How lanes are treated where sampling depends on wavelength (dispersion).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Dispersion {
    /// Keep every lane, weighted by spectral MIS over the lanes' sampling densities (Wilkie et
    /// al. 2014): lanes that could have produced the hero's direction keep contributing.
    #[default]
    SpectralMis,
    /// Drop the secondary lanes at the first dispersive event (pbrt-v4's approach); kept for
    /// comparison.
    TerminateSecondary,
}

/// Radiance arriving along `ray` at the lanes of `wl`, each lane already weighted by the
/// hero-wavelength estimator (the caller divides by N p(λ_j)).
///
/// Spectral MIS bookkeeping: `r[k]` is the ratio of lane k's path density to the hero's. A
/// lane's contribution is scaled by N / Σ r, and emitter-vs-BSDF MIS uses the lanes' average
/// BSDF density weighted by r. Without dispersion r stays 1 and all of this is the identity.
pub fn radiance<const N: usize>(
    scene: &Scene,
    mut ray: Ray,
    wl: &Wavelengths<N>,
    sampler: &mut PixelSampler,
    settings: &PathSettings,
    dispersion: Dispersion,
) -> Spectrum<N> {
    let mut l = Spectrum::<N>::zero();
    if settings.max_depth == 0 {
        return l;
    }
    let max_depth = if settings.max_depth < 0 {
        u32::MAX
    } else {
        settings.max_depth as u32
    };
    let n_emitters = scene.emitters.len();
    let select_pdf = if n_emitters > 0 {
        1.0 / n_emitters as f32
    } else {
        0.0
    };
    let mut beta = Spectrum::<N>::one();
    let mut r = Spectrum::<N>::one();
    let mut lane_w = 1.0f32;
    let mut eta = 1.0f32;
    // The previous vertex's BSDF sampling density, for MIS when the ray lands on an emitter.
    let mut prev_p = ray.o;
    let mut prev_pdf = 0.0f32;
    let mut prev_delta = true; // the camera ray: no competing strategy
    let mut depth = 1u32;
    let mut bsdf = Bsdf::default();
    loop {
        let show = depth > 1 || !settings.hide_emitters;
        let Some(si) = scene.intersect(&ray) else {
            if show {
                for &e in &scene.environment {
                    let em = &scene.emitters[e as usize];
                    let le = em.le_env(ray.d, wl);
                    let w = if prev_delta {
                        1.0
                    } else {
                        power_heuristic(prev_pdf, select_pdf * em.pdf_li_env(ray.d))
                    };
                    l += beta * le * (w * lane_w);
                }
            }
            break;
        };
        if let Some(e) = scene.shape_emitter[si.shape as usize] {
            let em = &scene.emitters[e as usize];
            let le = em.le_surface(&si, -ray.d, wl);
            if show && !le.is_zero() {
                let w = if prev_delta {
                    1.0
                } else {
                    power_heuristic(
                        prev_pdf,
                        select_pdf * em.pdf_li_hit(prev_p, &si, &scene.shapes),
                    )
                };
                l += beta * le * (w * lane_w);
            }
        }
        if depth >= max_depth {
            break;
        }
        sampler.set_dimension(CAMERA_DIMS + (depth - 1).min(1 << 20) * BOUNCE_DIMS);
        let wi = si.frame.to_local(-ray.d);
        let material = &scene.materials[scene.shape_material[si.shape as usize] as usize];
        material.fill_bsdf(&si, wi, wl, &mut bsdf);
        let dispersive = bsdf.dispersive();

        // Emitter sampling.
        let u_select = sampler.next_1d();
        let u_light = sampler.next_2d();
        if n_emitters > 0 && bsdf.has_smooth() {
            let e = ((u_select * n_emitters as f32) as usize).min(n_emitters - 1);
            if let Some(es) = scene.emitters[e].sample_li(&si, u_light, wl, &scene.shapes) {
                let wo = si.frame.to_local(es.wi);
                let f = bsdf.eval(wi, wo);
                if !f.is_zero() && !scene.occluded(&es.shadow) {
                    let light_pdf = select_pdf * es.pdf;
                    let w = if es.delta {
                        1.0
                    } else {
                        let bsdf_pdf = if dispersive {
                            (r * bsdf.pdf_lanes(wi, wo)).sum() / r.sum()
                        } else {
                            bsdf.pdf(wi, wo)
                        };
                        power_heuristic(light_pdf, bsdf_pdf)
                    };
                    l += beta * f * es.radiance * (w / light_pdf * lane_w);
                }
            }
        }

        // BSDF sampling.
        let u_lobe = sampler.next_1d();
        let u_dir = sampler.next_2d();
        let Some(bs) = bsdf.sample(wi, u_lobe, u_dir) else {
            break;
        };
        beta *= bs.weight;
        prev_pdf = bs.pdf;
        if dispersive && N > 1 {
            match dispersion {
                Dispersion::SpectralMis => {
                    prev_pdf = (r * bs.pdf_lanes).sum() / r.sum();
                    r = r * bs.pdf_lanes / bs.pdf;
                }
                Dispersion::TerminateSecondary => {
                    for k in 1..N {
                        beta[k] = 0.0;
                        r[k] = 0.0;
                    }
                }
            }
            lane_w = N as f32 / r.sum();
        }
        eta *= bs.eta;
        if beta.is_zero() {
            break;
        }
        let wo_world: Vec3 = si.frame.to_world(bs.wo);
        prev_p = si.p;
        prev_delta = bs.delta;
        ray = si.spawn(wo_world);

        if depth >= settings.rr_depth {
            let q = (beta.max_value() * lane_w * eta * eta).min(0.95);
            if sampler.next_1d() >= q {
                break;
            }
            beta /= q;
        }
        depth += 1;
    }
    l
}
