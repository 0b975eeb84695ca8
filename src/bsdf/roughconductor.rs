//! A rough conductor (Mitsuba's `roughconductor`): the microfacet model of Walter et al. 2007,
//! f = F(wi·m) D(m) G(wi, wo, m) / (4 cos θ_i cos θ_o) with m the half vector, sampled by the
//! distribution of visible normals. Single scattering: light that would bounce between
//! microfacets more than once is lost, so the albedo falls below 1 as the roughness grows.
//! One-sided, like Mitsuba's.

use super::conductor::Conductor;
use super::describe::{conductor, rough};
use super::microfacet::Distribution;
use super::microfacet::Microfacet;
use super::{BsdfLobe, BsdfParams, BsdfSample, ConductorParams, Lobe, Param};
use crate::interaction::SurfaceInteraction;
use crate::spectrum::{Spectrum, Wavelengths};
use crate::texture::FloatTexture;
use glam::{Vec2, Vec3};

/// A rough conductor at the path's wavelengths.
#[derive(Clone, Copy, Debug)]
pub struct RoughConductor<const N: usize> {
    /// The optical constants every microfacet reflects with.
    pub surface: Conductor<N>,
    /// The microfacet normal distribution at this hit.
    pub distr: Microfacet,
}

impl<const N: usize> BsdfLobe<N> for RoughConductor<N> {
    /// f · cos θ_o = F D G / (4 cos θ_i).
    #[inline]
    fn eval(&self, wi: Vec3, wo: Vec3) -> Spectrum<N> {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return Spectrum::zero();
        }
        let m = (wi + wo).normalize();
        let d = self.distr.d(m);
        if d == 0.0 {
            return Spectrum::zero();
        }
        let g = self.distr.g(wi, wo, m);
        self.surface.reflectance(wi.dot(m)) * (d * g / (4.0 * wi.z))
    }

    /// Density of `sample`: the visible normals' density times the Jacobian 1 / (4 wo·m) of
    /// reflecting about m.
    #[inline]
    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        let m = (wi + wo).normalize();
        self.distr.pdf_visible(wi, m) / (4.0 * wo.dot(m))
    }

    #[inline]
    fn sample(&self, wi: Vec3, _uc: f32, u: Vec2) -> Option<BsdfSample<N>> {
        if wi.z <= 0.0 {
            return None;
        }
        let m = self.distr.sample_visible(wi, u);
        let cos_m = wi.dot(m);
        let wo = 2.0 * cos_m * m - wi;
        if wo.z <= 0.0 || cos_m <= 0.0 {
            return None;
        }
        let pdf = self.distr.pdf_visible(wi, m) / (4.0 * cos_m);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        // f cos θ_o / pdf: D and G1(wi) cancel against the visible normals' density.
        let weight = self.surface.reflectance(cos_m) * self.distr.g1(wo, m);
        Some(BsdfSample::reflection(wo, pdf, weight))
    }

    #[inline]
    fn glossy(&self, max_alpha: f32) -> bool {
        self.distr.alpha_u.max(self.distr.alpha_v) <= max_alpha
    }
}

/// A rough conductor's parameters over the surface; the roughnesses along the tangent and
/// bitangent may vary.
#[derive(Clone, Debug, PartialEq)]
pub struct RoughConductorParams {
    pub params: ConductorParams,
    pub distribution: Distribution,
    pub alpha_u: FloatTexture,
    pub alpha_v: FloatTexture,
}

impl BsdfParams for RoughConductorParams {
    #[inline]
    fn lobe<'a, const N: usize>(
        &'a self,
        si: &SurfaceInteraction,
        wl: &Wavelengths<N>,
    ) -> Lobe<'a, N> {
        Lobe::RoughConductor(RoughConductor {
            surface: self.params.at(si.uv, wl),
            // Texture values outside [0, 1] are clamped, as for blend weights and opacities.
            distr: Microfacet::new(
                self.distribution,
                self.alpha_u.eval(si.uv).clamp(0.0, 1.0),
                self.alpha_v.eval(si.uv).clamp(0.0, 1.0),
            ),
        })
    }

    fn focuses_light(&self) -> bool {
        true
    }

    fn traverse<'a>(&'a self, put: &mut impl FnMut(&'static str, Param<'a>)) -> &'static str {
        conductor(&self.params, put);
        rough(self.distribution, &self.alpha_u, &self.alpha_v, put);
        "roughconductor"
    }
}
