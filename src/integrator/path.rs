//! Unidirectional path tracing with emitter sampling, BSDF sampling and multiple importance
//! sampling (power heuristic), carrying N wavelengths per path (hero-wavelength transport).
//!
//! Depth follows Mitsuba 3's `path` integrator: a path of k segments has depth k; `max_depth` 1
//! shows only directly visible emitters, 2 adds direct lighting, −1 is unbounded. Russian
//! roulette starts once depth ≥ `rr_depth`: continue with q = min(max(β)·η², 0.95), β /= q.
//!
//! The settings are in `path/settings.rs`; the loop, the path's state and its scattering stay
//! in this one file, so that the hot code compiles as one unit as it did (a split of it cost
//! instructions in callgrind).

mod settings;
#[cfg(test)]
mod tests;

pub use settings::{Dispersion, PathSettings};

use super::caustics::Caustics;
use crate::bsdf::{Bsdf, BsdfLike};
use crate::emitter::{AreaEmitter, AreaRadiance, Emitter};
use crate::interaction::SurfaceInteraction;
use crate::math::sampling::power_heuristic;
use crate::ray::Ray;
use crate::sampler::{PixelSampler, BOUNCE_DIMS, CAMERA_DIMS};
use crate::scene::Scene;
use crate::spectrum::{Spectrum, Wavelengths};
use glam::{Vec2, Vec3};

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
        let goes_on = match &bsdf {
            Bsdf::Diffuse(d) => {
                path.scatter::<DISPERSIVE>(d, &si, &mut ray, scene, wl, sampler, skip)
            }
            Bsdf::Mixture(m) => {
                path.scatter::<DISPERSIVE>(m, &si, &mut ray, scene, wl, sampler, skip)
            }
        };
        if !goes_on {
            break;
        }
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

/// A path being traced: what it has gathered, and what its next vertex needs.
///
/// Spectral MIS bookkeeping: `r[k]` is the ratio of lane k's path density to the hero's. A
/// lane's contribution is scaled by `lane_w` = N / Σ r, and emitter-vs-BSDF MIS uses the lanes'
/// average BSDF density weighted by r. Without dispersion r stays 1 and all of this is the
/// identity.
pub(super) struct Path<const N: usize> {
    /// Radiance gathered so far.
    pub(super) l: Spectrum<N>,
    /// Throughput.
    pub(super) beta: Spectrum<N>,
    r: Spectrum<N>,
    pub(super) lane_w: f32,
    /// Product of the relative indices of refraction crossed (for Russian roulette).
    pub(super) eta: f32,
    // The previous vertex and its BSDF sampling density, for MIS when the ray lands on an
    // emitter.
    pub(super) prev_p: Vec3,
    pub(super) prev_pdf: f32,
    pub(super) prev_delta: bool,
    /// Probability of choosing each emitter for emitter sampling (uniform).
    pub(super) select_pdf: f32,
    dispersion: Dispersion,
    pub(super) le_memo: LeMemo<N>,
}

/// Where an emitter sample's radiance comes from (see `Path::scatter`).
enum Le<'a, const N: usize> {
    Value(Spectrum<N>),
    /// An area light, and the uv of the sampled point on it.
    Area(&'a AreaEmitter, Vec2),
    Envmap(&'a crate::emitter::EnvMap),
}

/// An area light's radiance at the path's lanes, kept for the uniform light the path last
/// sampled or hit. It is the same all over the light, and the lanes stay fixed along the path,
/// so a path in a one-light scene (the Cornell box) evaluates it once instead of at every
/// bounce (the RGB uplift times D65 there was 6% of the render). A textured light is never
/// memoised (its radiance depends on the point): it is looked up at each point's uv, on the
/// memo's miss branch, so the uniform case's hit path is what it was.
pub(super) struct LeMemo<const N: usize> {
    emitter: u32,
    le: Spectrum<N>,
}

impl<const N: usize> LeMemo<N> {
    const NONE: u32 = u32::MAX;

    /// The radiance of area emitter `a` (emitter index `e`) at the point of uv `uv` on it.
    #[inline(always)]
    pub(super) fn get(
        &mut self,
        e: u32,
        a: &AreaEmitter,
        uv: Vec2,
        wl: &Wavelengths<N>,
    ) -> Spectrum<N> {
        if self.emitter != e {
            match &a.radiance {
                AreaRadiance::Uniform(c) => {
                    self.le = c.eval(wl);
                    self.emitter = e;
                }
                AreaRadiance::Textured(t) => return t.eval(uv, wl),
            }
        }
        self.le
    }
}

impl<const N: usize> LeMemo<N> {
    /// `get` out of line and cold, for a light on a moving shape: the inlined code for still
    /// lights stays as it was (callgrind, docs/performance.md "Paths in lanes").
    #[cold]
    #[inline(never)]
    fn get_moving(
        &mut self,
        e: u32,
        a: &AreaEmitter,
        uv: Vec2,
        wl: &Wavelengths<N>,
    ) -> Spectrum<N> {
        self.get(e, a, uv, wl)
    }
}

impl<const N: usize> Path<N> {
    /// Adds environment emitter `em`'s radiance along `d` (a ray that left the scene),
    /// MIS-weighted against the BSDF sampling that chose `d`.
    #[inline(always)]
    pub(super) fn add_environment(&mut self, em: &Emitter, ray: &Ray, wl: &Wavelengths<N>) {
        let (d, time) = (ray.d, ray.time);
        let (le, w) = if self.prev_delta {
            (em.le_env_at(d, time, wl), 1.0)
        } else {
            let (le, pdf) = em.le_and_pdf_env_at(d, time, wl);
            (le, power_heuristic(self.prev_pdf, self.select_pdf * pdf))
        };
        self.l += self.beta * le * (w * self.lane_w);
    }

    /// Adds the radiance of emitter `e` at hit `si`, seen along `d` (area lights emit from
    /// their front side only; `show`: emitters seen from the camera count), MIS-weighted
    /// against the BSDF sampling that found it.
    #[inline(always)]
    pub(super) fn add_hit_emission(
        &mut self,
        scene: &Scene,
        e: u32,
        si: &SurfaceInteraction,
        d: Vec3,
        wl: &Wavelengths<N>,
        show: bool,
    ) {
        let em = &scene.emitters[e as usize];
        let le = match em {
            Emitter::Area(a) if show && si.ng.dot(-d) > 0.0 => self.le_memo.get(e, a, si.uv, wl),
            Emitter::MovingArea(m) if show && si.ng.dot(-d) > 0.0 => {
                self.le_memo.get_moving(e, &m.area, si.uv, wl)
            }
            _ => Spectrum::zero(),
        };
        if !le.is_zero() {
            let w = if self.prev_delta {
                1.0
            } else {
                power_heuristic(
                    self.prev_pdf,
                    self.select_pdf * em.pdf_li_hit(self.prev_p, si, &scene.shapes),
                )
            };
            self.l += self.beta * le * (w * self.lane_w);
        }
    }

    /// A path whose camera ray leaves `o`, in a scene of `n_emitters` emitters.
    #[inline(always)]
    pub(super) fn start(o: Vec3, n_emitters: usize, dispersion: Dispersion) -> Self {
        Path {
            l: Spectrum::zero(),
            beta: Spectrum::one(),
            r: Spectrum::one(),
            lane_w: 1.0,
            eta: 1.0,
            prev_p: o,
            prev_pdf: 0.0,
            prev_delta: true, // the camera ray: no competing strategy
            select_pdf: if n_emitters > 0 {
                1.0 / n_emitters as f32
            } else {
                0.0
            },
            dispersion,
            le_memo: LeMemo {
                emitter: LeMemo::<N>::NONE,
                le: Spectrum::zero(),
            },
        }
    }

    /// Emitter sampling and BSDF sampling at `si` with `bsdf`, for a path arriving along `ray`:
    /// adds the light sampled there and, if the path goes on (true), makes `ray` its next ray.
    /// Emitter samples that `skip` takes are left out. (The next ray is written in place: made
    /// in a temporary and copied, its 32 bytes were read back in one load before the narrower
    /// stores that wrote them had landed, a store-forwarding stall that perf put at 5.8% of the
    /// packet kernel's Cornell samples.)
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub(super) fn scatter<const DISPERSIVE: bool>(
        &mut self,
        bsdf: &impl BsdfLike<N>,
        si: &SurfaceInteraction,
        ray: &mut Ray,
        scene: &Scene,
        wl: &Wavelengths<N>,
        sampler: &mut PixelSampler,
        skip: Option<&Caustics>,
    ) -> bool {
        let wi = si.frame.to_local(-ray.d);
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
        let Some(bs) = bsdf.sample(wi, u_lobe, u_dir) else {
            return false;
        };
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
            return false;
        }
        let wo_world: Vec3 = si.frame.to_world(bs.wo);
        self.prev_p = si.p;
        self.prev_delta = bs.delta;
        si.spawn_into(wo_world, ray);
        true
    }
}
