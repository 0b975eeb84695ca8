//! Scattering at a path's vertex (`Path::scatter`): emitter sampling and BSDF sampling, MIS
//! between them, and the spectral-MIS bookkeeping of dispersive lobes.

use super::state::Path;
use super::Dispersion;
use crate::bsdf::BsdfLike;
use crate::emitter::{AreaEmitter, Emitter};
use crate::integrator::caustics::Caustics;
use crate::interaction::SurfaceInteraction;
use crate::math::sampling::power_heuristic;
use crate::ray::Ray;
use crate::sampler::PixelSampler;
use crate::scene::Scene;
use crate::spectrum::{Spectrum, Wavelengths};
use glam::{Vec2, Vec3};

/// Where an emitter sample's radiance comes from (see `Path::scatter`).
enum Le<'a, const N: usize> {
    Value(Spectrum<N>),
    /// An area light, and the uv of the sampled point on it.
    Area(&'a AreaEmitter, Vec2),
    Envmap(&'a crate::emitter::EnvMap),
}

impl<const N: usize> Path<N> {
    /// Emitter sampling and BSDF sampling at `si` with `bsdf`, for a path arriving from world
    /// direction `wi_world`: adds the light sampled there and returns the path's next ray
    /// (None if the path ends here). Emitter samples that `skip` takes are left out.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub(in crate::integrator) fn scatter<const DISPERSIVE: bool>(
        &mut self,
        bsdf: &impl BsdfLike<N>,
        si: &SurfaceInteraction,
        wi_world: Vec3,
        scene: &Scene,
        wl: &Wavelengths<N>,
        sampler: &mut PixelSampler,
        skip: Option<&Caustics>,
    ) -> Option<Ray> {
        let wi = si.frame.to_local(wi_world);
        let dispersive = DISPERSIVE && bsdf.dispersive();

        // Emitter sampling.
        let n_emitters = scene.emitters.len();
        // Point first: it takes the group's best-stratified pair (see `sampler`).
        let u_light = sampler.next_2d();
        let u_select = sampler.next_1d();
        if n_emitters > 0 && bsdf.has_smooth() {
            let e = ((u_select * n_emitters as f32) as usize).min(n_emitters - 1);
            let em = &scene.emitters[e];
            // Area lights and environment maps are sampled for a direction first; their
            // radiance is looked up only for a sample that counts (unoccluded, f ≠ 0), an area
            // light's through the path's memo. Other kinds come with theirs.
            let sample = match em {
                Emitter::Area(a) => a
                    .sample_point(si, u_light, &scene.shapes)
                    .map(|s| (s.wi, s.shadow, s.pdf, false, Le::Area(a, s.uv))),
                Emitter::Envmap(m) => m
                    .sample(u_light)
                    .map(|(wi, pdf)| (wi, si.spawn(wi), pdf, false, Le::Envmap(m))),
                _ => em
                    .sample_li_other(si, u_light, wl)
                    .map(|s| (s.wi, s.shadow, s.pdf, s.delta, Le::Value(s.radiance))),
            };
            if let Some((wi_light, shadow, pdf, delta, radiance)) = sample {
                let wo = si.frame.to_local(wi_light);
                let f = bsdf.eval(wi, wo);
                let taken = skip.is_some_and(|c| c.takes(e as u32, wi_light));
                if !taken && !f.is_zero() && !scene.occluded(&shadow) {
                    let le = match radiance {
                        Le::Value(le) => le,
                        Le::Area(a, uv) => self.le_memo.get(e as u32, a, uv, wl),
                        Le::Envmap(m) => m.eval(wi_light, wl),
                    };
                    let light_pdf = self.select_pdf * pdf;
                    let w = if delta {
                        1.0
                    } else {
                        let bsdf_pdf = if dispersive {
                            (self.r * bsdf.pdf_lanes(wi, wo)).sum() / self.r.sum()
                        } else {
                            bsdf.pdf(wi, wo)
                        };
                        power_heuristic(light_pdf, bsdf_pdf)
                    };
                    self.l += self.beta * f * le * (w / light_pdf * self.lane_w);
                }
            }
        }

        // BSDF sampling.
        let u_lobe = sampler.next_1d();
        let u_dir = sampler.next_2d();
        let bs = bsdf.sample(wi, u_lobe, u_dir)?;
        self.beta *= bs.weight;
        self.prev_pdf = bs.pdf;
        if dispersive && N > 1 {
            match self.dispersion {
                Dispersion::SpectralMis => {
                    self.prev_pdf = (self.r * bs.pdf_lanes).sum() / self.r.sum();
                    self.r = self.r * bs.pdf_lanes / bs.pdf;
                }
                Dispersion::TerminateSecondary => {
                    for k in 1..N {
                        self.beta[k] = 0.0;
                        self.r[k] = 0.0;
                    }
                }
            }
            self.lane_w = N as f32 / self.r.sum();
        }
        self.eta *= bs.eta;
        if self.beta.is_zero() {
            return None;
        }
        let wo_world: Vec3 = si.frame.to_world(bs.wo);
        self.prev_p = si.p;
        self.prev_delta = bs.delta;
        Some(si.spawn(wo_world))
    }
}
