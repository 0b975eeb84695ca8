//! Unidirectional path tracing with emitter sampling, BSDF sampling and multiple importance
//! sampling (power heuristic), carrying N wavelengths per path (hero-wavelength transport).
//! This file holds the integrator's settings and its loop over a path's vertices; the path's
//! state and the emission it gathers are in `path/state.rs`, the scattering at a vertex in
//! `path/scatter.rs`.
//!
//! Depth follows Mitsuba 3's `path` integrator: a path of k segments has depth k; `max_depth` 1
//! shows only directly visible emitters, 2 adds direct lighting, −1 is unbounded. Russian
//! roulette starts once depth ≥ `rr_depth`: continue with q = min(max(β)·η², 0.95), β /= q.

mod scatter;
mod state;

pub(super) use state::Path;

use super::caustics::{CausticSettings, Caustics};
use crate::bsdf::{Bsdf, BsdfLike};
use crate::ray::Ray;
use crate::sampler::{PixelSampler, BOUNCE_DIMS, CAMERA_DIMS};
use crate::scene::Scene;
use crate::spectrum::{Spectrum, Wavelengths};
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
    /// Opt-in caustic light tracing (`caustics: Some(())` for the defaults): caustics of an
    /// environment map's sun, of directional and of area lights, seen on surfaces the camera
    /// sees, are traced from the light instead of found by chance (`integrator::caustics`).
    /// Unbiased.
    pub caustics: Option<CausticSettings>,
}

impl Default for PathSettings {
    fn default() -> Self {
        Self {
            max_depth: -1,
            rr_depth: 5,
            hide_emitters: false,
            clamp: None,
            caustics: None,
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

/// `radiance` with its dispersion and caustics chosen.
pub type RadianceFn<const N: usize> = fn(
    &Scene,
    Ray,
    &Wavelengths<N>,
    &mut PixelSampler,
    &PathSettings,
    Dispersion,
    Option<&Caustics>,
) -> Spectrum<N>;

/// Radiance arriving along `ray` at the lanes of `wl`, each lane already weighted by the
/// hero-wavelength estimator (the caller divides by N p(λ_j)).
///
/// `DISPERSIVE` is false for a scene without a dispersive material (decided once per render):
/// the spectral-MIS bookkeeping of `Path` then compiles away, and such a scene pays nothing for
/// it. With `caustics` (and `CAUSTICS`, likewise set once per render so that a render without
/// it pays nothing), the paths its light tracer takes are left out here.
#[allow(clippy::too_many_arguments)]
pub fn radiance<const N: usize, const DISPERSIVE: bool, const CAUSTICS: bool>(
    scene: &Scene,
    mut ray: Ray,
    wl: &Wavelengths<N>,
    sampler: &mut PixelSampler,
    settings: &PathSettings,
    dispersion: Dispersion,
    caustics: Option<&Caustics>,
) -> Spectrum<N> {
    if settings.max_depth == 0 {
        return Spectrum::zero();
    }
    // Known to be None in the copy without caustics, so its checks compile away there.
    let caustics = if CAUSTICS { caustics } else { None };
    let max_depth = if settings.max_depth < 0 {
        u32::MAX
    } else {
        settings.max_depth as u32
    };
    let mut path = Path::start(ray.o, scene.emitters.len(), dispersion);
    let mut depth = 1u32;
    let mut bsdf = Bsdf::default();
    // Caustic light tracing's share: the first vertex (not glossy) scattered through a smooth
    // lobe and `chain` later ones through Dirac lobes or at glossy surfaces (None once the
    // path is not of that form; see `caustics`).
    let mut chain: Option<u32> = None;
    loop {
        let show = depth > 1 || !settings.hide_emitters;
        let Some(si) = scene.intersect(&ray) else {
            if show {
                for &e in &scene.environment {
                    if matches!((caustics, chain), (Some(c), Some(1..)) if c.takes(e, ray.d)) {
                        continue;
                    }
                    path.add_environment(&scene.emitters[e as usize], &ray, wl);
                }
            }
            break;
        };
        if let Some(e) = scene.shape_emitter[si.shape as usize]
            .filter(|&e| !matches!((caustics, chain), (Some(c), Some(1..)) if c.takes(e, ray.d)))
        {
            path.add_hit_emission(scene, e, &si, ray.d, wl, show);
        }
        if depth >= max_depth {
            break;
        }
        sampler.set_dimension(CAMERA_DIMS + (depth - 1).min(1 << 20) * BOUNCE_DIMS);
        let material = &scene.materials[scene.shape_material[si.shape as usize] as usize];
        material.fill_bsdf(&si, si.frame.to_local(-ray.d), wl, &mut bsdf);
        // One copy of the scattering code for each kind of BSDF: for a plain diffuse material
        // it is straight-line code without dispatch, which even leaves out the parts of the
        // local directions that a Lambertian lobe never reads (all but cos θ).
        // Caustic light tracing connects the camera to surfaces that are not glossy, and
        // follows the glossy ones (see `caustics`): a glossy vertex continuing its chain
        // leaves its emitter samples of the light tracer's sources to it.
        let glossy = caustics.is_some_and(|c| bsdf.glossy(c.max_roughness()));
        let skip = match chain {
            Some(_) if glossy && depth >= 2 => caustics,
            _ => None,
        };
        let next = match &bsdf {
            Bsdf::Diffuse(d) => {
                path.scatter::<DISPERSIVE>(d, &si, -ray.d, scene, wl, sampler, skip)
            }
            Bsdf::Mixture(m) => {
                path.scatter::<DISPERSIVE>(m, &si, -ray.d, scene, wl, sampler, skip)
            }
        };
        let Some(next) = next else {
            break;
        };
        ray = next;
        if caustics.is_some() {
            chain = match (depth, chain) {
                (1, _) if !path.prev_delta && !glossy => Some(0),
                (2.., Some(k)) if path.prev_delta || glossy => Some(k + 1),
                _ => None,
            };
        }
        if depth >= settings.rr_depth {
            let q = (path.beta.max_value() * path.lane_w * path.eta * path.eta).min(0.95);
            if sampler.next_1d() >= q {
                break;
            }
            path.beta /= q;
        }
        depth += 1;
    }
    path.l
}
