//! A path being traced (`Path`): its throughput, the radiance it has gathered, the previous
//! vertex for MIS, and the emission it adds where a ray leaves the scene or lands on an area
//! light, with the memo of a light's radiance (`LeMemo`).

use super::Dispersion;
use crate::emitter::{AreaEmitter, AreaRadiance, Emitter};
use crate::interaction::SurfaceInteraction;
use crate::math::sampling::power_heuristic;
use crate::ray::Ray;
use crate::scene::Scene;
use crate::spectrum::{Spectrum, Wavelengths};
use glam::{Vec2, Vec3};

/// A path being traced: what it has gathered, and what its next vertex needs.
///
/// Spectral MIS bookkeeping: `r[k]` is the ratio of lane k's path density to the hero's. A
/// lane's contribution is scaled by `lane_w` = N / Σ r, and emitter-vs-BSDF MIS uses the lanes'
/// average BSDF density weighted by r. Without dispersion r stays 1 and all of this is the
/// identity.
pub(in crate::integrator) struct Path<const N: usize> {
    /// Radiance gathered so far.
    pub(in crate::integrator) l: Spectrum<N>,
    /// Throughput.
    pub(in crate::integrator) beta: Spectrum<N>,
    pub(super) r: Spectrum<N>,
    pub(in crate::integrator) lane_w: f32,
    /// Product of the relative indices of refraction crossed (for Russian roulette).
    pub(in crate::integrator) eta: f32,
    // The previous vertex and its BSDF sampling density, for MIS when the ray lands on an
    // emitter.
    pub(in crate::integrator) prev_p: Vec3,
    pub(in crate::integrator) prev_pdf: f32,
    pub(in crate::integrator) prev_delta: bool,
    /// Probability of choosing each emitter for emitter sampling (uniform).
    pub(in crate::integrator) select_pdf: f32,
    pub(super) dispersion: Dispersion,
    pub(in crate::integrator) le_memo: LeMemo<N>,
}

/// An area light's radiance at the path's lanes, kept for the uniform light the path last
/// sampled or hit. It is the same all over the light, and the lanes stay fixed along the path,
/// so a path in a one-light scene (the Cornell box) evaluates it once instead of at every
/// bounce (the RGB uplift times D65 there was 6% of the render). A textured light is never
/// memoised (its radiance depends on the point): it is looked up at each point's uv, on the
/// memo's miss branch, so the uniform case's hit path is what it was.
pub(in crate::integrator) struct LeMemo<const N: usize> {
    emitter: u32,
    le: Spectrum<N>,
}

impl<const N: usize> LeMemo<N> {
    const NONE: u32 = u32::MAX;

    /// The radiance of area emitter `a` (emitter index `e`) at the point of uv `uv` on it.
    #[inline(always)]
    pub(in crate::integrator) fn get(
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
    pub(in crate::integrator) fn add_environment(
        &mut self,
        em: &Emitter,
        ray: &Ray,
        wl: &Wavelengths<N>,
    ) {
        let (d, time) = (ray.d, ray.time);
        let le = em.le_env_at(d, time, wl);
        let w = if self.prev_delta {
            1.0
        } else {
            power_heuristic(self.prev_pdf, self.select_pdf * em.pdf_li_env_at(d, time))
        };
        self.l += self.beta * le * (w * self.lane_w);
    }

    /// Adds the radiance of emitter `e` at hit `si`, seen along `d` (area lights emit from
    /// their front side only; `show`: emitters seen from the camera count), MIS-weighted
    /// against the BSDF sampling that found it.
    #[inline(always)]
    pub(in crate::integrator) fn add_hit_emission(
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
    pub(in crate::integrator) fn start(o: Vec3, n_emitters: usize, dispersion: Dispersion) -> Self {
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
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shape::{Shape, Sphere};
    use crate::spectrum::{Curve, WavelengthSampler, WavelengthSampling};

    /// The memo is keyed by emitter: two lights of different spectra, asked for in turn, each
    /// get their own radiance, evaluated at the path's lanes.
    #[test]
    fn le_memo_keeps_each_light_apart() {
        let sphere = Shape::Sphere(Sphere {
            center: Vec3::ZERO,
            radius: 1.0,
            flip: false,
        });
        let red = AreaEmitter::new(0, &sphere, Curve::rgb_illuminant([4.0, 0.1, 0.1]));
        let blue = AreaEmitter::new(1, &sphere, Curve::rgb_illuminant([0.1, 0.1, 4.0]));
        let wl: Wavelengths<8> =
            WavelengthSampler::new(WavelengthSampling::Visible, 360.0, 830.0).sample(0.3);
        let want = |a: &AreaEmitter| a.radiance.eval(Vec2::ZERO, &wl);
        let mut memo = LeMemo {
            emitter: LeMemo::<8>::NONE,
            le: Spectrum::zero(),
        };
        for (e, em) in [
            (0, &red),
            (0, &red),
            (1, &blue),
            (0, &red),
            (1, &blue),
            (1, &blue),
        ] {
            assert_eq!(memo.get(e, em, Vec2::ZERO, &wl), want(em), "emitter {e}");
        }
        assert_ne!(want(&red), want(&blue));
    }
}
