//! One leaf BSDF at a hit and the dispatch to its kind.

use super::{
    BsdfSample, Conductor, Dielectric, Diffuse, Mixture, Plastic, Principled, RoughConductor,
    RoughDielectric, RoughPlastic, ThinDielectric,
};
use crate::spectrum::Spectrum;
use glam::{Vec2, Vec3};

/// One leaf BSDF at a hit, at the path's wavelengths.
#[derive(Clone, Copy, Debug)]
pub enum Lobe<'a, const N: usize> {
    Diffuse(Diffuse<N>),
    // Conductors.
    /// Mirror reflection, Fresnel-weighted per wavelength.
    Conductor(Conductor<N>),
    /// Microfacet reflection, Fresnel-weighted per wavelength.
    RoughConductor(RoughConductor<N>),
    // Dielectrics.
    Dielectric(Dielectric<N>),
    RoughDielectric(RoughDielectric<N>),
    ThinDielectric(ThinDielectric<N>),
    // Plastics.
    Plastic(Plastic<N>),
    RoughPlastic(RoughPlastic<'a, N>),
    Principled(Principled<N>),
    /// Passes light straight through, unchanged (the transparent part of a `mask`).
    Null,
}

impl<'a, const N: usize> Lobe<'a, N> {
    pub(super) fn push(self, weight: f32, flip: bool, out: &mut Mixture<'a, N>) {
        if weight > 0.0 && !out.lobes.is_full() {
            out.lobes.push((self, weight, flip));
        }
    }

    /// f(wi, wo) · |cos θ_o| per lane (0 for Dirac lobes).
    #[inline]
    pub(super) fn eval(&self, wi: Vec3, wo: Vec3) -> Spectrum<N> {
        match self {
            Lobe::Diffuse(b) => b.eval(wi, wo),
            // Conductors.
            Lobe::Conductor(_) => Spectrum::zero(),
            Lobe::RoughConductor(b) => b.eval(wi, wo),
            // Dielectrics.
            Lobe::RoughDielectric(b) => b.eval(wi, wo),
            Lobe::Dielectric(_) | Lobe::ThinDielectric(_) => Spectrum::zero(),
            // Plastics.
            Lobe::Plastic(b) => b.eval(wi, wo),
            Lobe::RoughPlastic(b) => b.eval(wi, wo),
            Lobe::Principled(b) => b.eval(wi, wo),
            Lobe::Null => Spectrum::zero(),
        }
    }

    /// Hero density of sampling `wo` (0 for Dirac lobes).
    #[inline]
    pub(super) fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        match self {
            Lobe::Diffuse(b) => b.pdf(wi, wo),
            // Conductors.
            Lobe::Conductor(_) => 0.0,
            Lobe::RoughConductor(b) => b.pdf(wi, wo),
            // Dielectrics.
            Lobe::RoughDielectric(b) => b.pdf(wi, wo),
            Lobe::Dielectric(_) | Lobe::ThinDielectric(_) => 0.0,
            // Plastics.
            Lobe::Plastic(b) => b.pdf(wi, wo),
            Lobe::RoughPlastic(b) => b.pdf(wi, wo),
            Lobe::Principled(b) => b.pdf(wi, wo),
            Lobe::Null => 0.0,
        }
    }

    /// Per-lane densities of sampling `wo`.
    #[inline]
    pub(super) fn pdf_lanes(&self, wi: Vec3, wo: Vec3) -> Spectrum<N> {
        match self {
            Lobe::Diffuse(_) | Lobe::Null => Spectrum::splat(self.pdf(wi, wo)),
            // Conductors.
            Lobe::Conductor(_) | Lobe::RoughConductor(_) => Spectrum::splat(self.pdf(wi, wo)),
            // Dielectrics.
            Lobe::RoughDielectric(b) => b.pdf_lanes(wi, wo),
            Lobe::Dielectric(_) | Lobe::ThinDielectric(_) => Spectrum::zero(),
            // Plastics.
            Lobe::Plastic(_) | Lobe::RoughPlastic(_) | Lobe::Principled(_) => {
                Spectrum::splat(self.pdf(wi, wo))
            }
        }
    }

    #[inline]
    pub(super) fn sample(&self, wi: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample<N>> {
        match self {
            Lobe::Diffuse(b) => b.sample(wi, uc, u),
            // Conductors.
            Lobe::Conductor(b) => b.sample(wi, uc, u),
            Lobe::RoughConductor(b) => b.sample(wi, uc, u),
            // Dielectrics.
            Lobe::Dielectric(b) => b.sample(wi, uc, u),
            Lobe::RoughDielectric(b) => b.sample(wi, uc, u),
            Lobe::ThinDielectric(b) => b.sample(wi, uc, u),
            // Plastics.
            Lobe::Plastic(b) => b.sample(wi, uc, u),
            Lobe::RoughPlastic(b) => b.sample(wi, uc, u),
            Lobe::Principled(b) => b.sample(wi, uc, u),
            Lobe::Null => Some(BsdfSample {
                wo: -wi,
                pdf: 1.0,
                pdf_lanes: Spectrum::one(),
                weight: Spectrum::one(),
                delta: true,
                eta: 1.0,
            }),
        }
    }

    /// True if the lobe has a non-Dirac part (emitter sampling can reach it).
    #[inline]
    pub(super) fn has_smooth(&self) -> bool {
        match self {
            Lobe::Diffuse(_) => true,
            // Conductors.
            Lobe::Conductor(_) => false,
            Lobe::RoughConductor(_) => true,
            // Dielectrics.
            Lobe::RoughDielectric(_) => true,
            Lobe::Dielectric(_) | Lobe::ThinDielectric(_) => false,
            // Plastics.
            Lobe::Plastic(_) | Lobe::RoughPlastic(_) | Lobe::Principled(_) => true,
            Lobe::Null => false,
        }
    }

    /// True if the lobe is a Dirac lobe or a microfacet lobe no rougher than `max_alpha`.
    #[inline]
    pub(super) fn glossy(&self, max_alpha: f32) -> bool {
        match self {
            Lobe::Conductor(_) | Lobe::Dielectric(_) | Lobe::ThinDielectric(_) | Lobe::Null => true,
            Lobe::RoughConductor(b) => b.distr.alpha_u.max(b.distr.alpha_v) <= max_alpha,
            Lobe::RoughDielectric(b) => b.dist.alpha_u.max(b.dist.alpha_v) <= max_alpha,
            // Only a pure metal is glossy throughout (a dielectric has a diffuse base).
            Lobe::Principled(b) => b.metallic >= 1.0 && b.distr.alpha_u <= max_alpha,
            Lobe::Diffuse(_) | Lobe::Plastic(_) | Lobe::RoughPlastic(_) => false,
        }
    }

    /// True if the lobe's sampling depends on wavelength.
    #[inline]
    pub(super) fn dispersive(&self) -> bool {
        match self {
            Lobe::Diffuse(_) | Lobe::Null => false,
            // Conductors.
            Lobe::Conductor(_) | Lobe::RoughConductor(_) => false,
            // Dielectrics.
            Lobe::Dielectric(b) => b.dispersive,
            Lobe::RoughDielectric(b) => b.dispersive,
            Lobe::ThinDielectric(b) => b.dispersive,
            // Plastics.
            Lobe::Plastic(_) | Lobe::RoughPlastic(_) | Lobe::Principled(_) => false,
        }
    }
}
