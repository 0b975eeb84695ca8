//! The BSDF at a hit, its samples, and what the integrator asks of it (`BsdfLike`).

use super::{Diffuse, Mixture};
use crate::spectrum::Spectrum;
use glam::{Vec2, Vec3};

/// A sampled outgoing direction.
#[derive(Clone, Copy, Debug)]
pub struct BsdfSample<const N: usize> {
    pub wo: Vec3,
    /// Density of `wo` under the hero wavelength's BSDF (solid angle; for a Dirac lobe, the
    /// discrete probability of choosing it).
    pub pdf: f32,
    /// The same density for each lane's BSDF (equal to `pdf` in every lane unless sampling
    /// depends on wavelength; 0 where that lane could not have produced `wo`).
    pub pdf_lanes: Spectrum<N>,
    /// f · |cos θ_o| / pdf, per lane.
    pub weight: Spectrum<N>,
    /// True for a Dirac lobe: no emitter sampling, no MIS.
    pub delta: bool,
    /// Relative index of refraction crossed, for the hero (1 for reflection).
    pub eta: f32,
}

impl<const N: usize> BsdfSample<N> {
    /// A sample of a smooth reflection lobe whose sampling does not depend on wavelength:
    /// every lane's density is the hero's.
    #[inline]
    pub fn reflection(wo: Vec3, pdf: f32, weight: Spectrum<N>) -> Self {
        Self {
            wo,
            pdf,
            pdf_lanes: Spectrum::splat(pdf),
            weight,
            delta: false,
            eta: 1.0,
        }
    }
}

/// A BSDF at one hit.
#[derive(Clone, Debug)]
pub enum Bsdf<'a, const N: usize> {
    /// A plain `diffuse` material: one front-side lobe of weight 1 (every hit of a diffuse-only
    /// scene). Kept apart so that the integrator can run its per-hit code on it directly,
    /// without the mixture's loops over lobes, dispatch on their kind and calls out of line.
    Diffuse(Diffuse<N>),
    /// Any other material.
    Mixture(Mixture<'a, N>),
}

/// An empty mixture (for `fill_bsdf` to fill).
impl<const N: usize> Default for Bsdf<'_, N> {
    fn default() -> Self {
        Bsdf::Mixture(Mixture::default())
    }
}

/// What the integrator asks of a BSDF at a hit; directions in the local shading frame.
///
/// `Bsdf` answers by dispatching to its variant. The integrator instead matches on the variant
/// once per hit and runs its per-hit code on the variant itself (generic code, one copy per
/// variant), so a plain diffuse material costs no dispatch at all (`integrator::path`).
pub trait BsdfLike<const N: usize> {
    /// f(wi, wo) · |cos θ_o| of the smooth lobes (Dirac lobes contribute nothing here).
    fn eval(&self, wi: Vec3, wo: Vec3) -> Spectrum<N>;
    /// Hero density with which `sample` produces `wo` from its smooth lobes.
    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32;
    /// Per-lane densities with which `sample` produces `wo` from its smooth lobes.
    fn pdf_lanes(&self, wi: Vec3, wo: Vec3) -> Spectrum<N>;
    /// `uc` picks a lobe (by weight), `u` the direction within it.
    fn sample(&self, wi: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample<N>>;
    /// True if some lobe is not a Dirac lobe: emitter sampling can then contribute.
    fn has_smooth(&self) -> bool;
    /// True if sampling depends on wavelength (the integrator then tracks per-lane densities).
    fn dispersive(&self) -> bool;
    /// True if every lobe is a Dirac lobe or a microfacet lobe no rougher than `max_alpha`
    /// (what caustic light tracing follows).
    fn glossy(&self, max_alpha: f32) -> bool;
}

impl<const N: usize> BsdfLike<N> for Diffuse<N> {
    #[inline]
    fn eval(&self, wi: Vec3, wo: Vec3) -> Spectrum<N> {
        super::BsdfLobe::eval(self, wi, wo)
    }

    #[inline]
    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        super::BsdfLobe::pdf(self, wi, wo)
    }

    #[inline]
    fn pdf_lanes(&self, wi: Vec3, wo: Vec3) -> Spectrum<N> {
        super::BsdfLobe::pdf_lanes(self, wi, wo)
    }

    #[inline]
    fn sample(&self, wi: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample<N>> {
        super::BsdfLobe::sample(self, wi, uc, u)
    }

    #[inline]
    fn has_smooth(&self) -> bool {
        true
    }

    #[inline]
    fn dispersive(&self) -> bool {
        false
    }

    #[inline]
    fn glossy(&self, _max_alpha: f32) -> bool {
        false
    }
}

impl<const N: usize> BsdfLike<N> for Bsdf<'_, N> {
    #[inline]
    fn eval(&self, wi: Vec3, wo: Vec3) -> Spectrum<N> {
        match self {
            Bsdf::Diffuse(d) => d.eval(wi, wo),
            Bsdf::Mixture(m) => m.eval(wi, wo),
        }
    }

    #[inline]
    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        match self {
            Bsdf::Diffuse(d) => d.pdf(wi, wo),
            Bsdf::Mixture(m) => m.pdf(wi, wo),
        }
    }

    #[inline]
    fn pdf_lanes(&self, wi: Vec3, wo: Vec3) -> Spectrum<N> {
        match self {
            Bsdf::Diffuse(d) => d.pdf_lanes(wi, wo),
            Bsdf::Mixture(m) => m.pdf_lanes(wi, wo),
        }
    }

    #[inline]
    fn sample(&self, wi: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample<N>> {
        match self {
            Bsdf::Diffuse(d) => d.sample(wi, uc, u),
            Bsdf::Mixture(m) => m.sample(wi, uc, u),
        }
    }

    #[inline]
    fn has_smooth(&self) -> bool {
        match self {
            Bsdf::Diffuse(d) => d.has_smooth(),
            Bsdf::Mixture(m) => m.has_smooth(),
        }
    }

    #[inline]
    fn dispersive(&self) -> bool {
        match self {
            Bsdf::Diffuse(d) => d.dispersive(),
            Bsdf::Mixture(m) => m.dispersive(),
        }
    }

    #[inline]
    fn glossy(&self, max_alpha: f32) -> bool {
        match self {
            Bsdf::Diffuse(d) => d.glossy(max_alpha),
            Bsdf::Mixture(m) => m.glossy(max_alpha),
        }
    }
}
