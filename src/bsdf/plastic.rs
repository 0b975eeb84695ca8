//! Smooth plastic (Mitsuba's `plastic`): a dielectric coating over a diffuse base. Light is
//! either reflected specularly by the coating (Fresnel F) or enters, scatters diffusely and
//! leaves, with multiple internal reflections folded into the diffuse term:
//!
//! f_diffuse = ρ' (1 − F(θi)) (1 − F(θo)) / (π η²),  ρ' = ρ / (1 − F_dr) (or ρ / (1 − ρ F_dr) when
//! `nonlinear`), with F_dr the hemispherical average of the internal Fresnel reflectance.

use super::describe::plastic;
use super::fresnel;
use super::{BsdfLobe, BsdfParams, BsdfSample, Lobe, Param};
use crate::interaction::SurfaceInteraction;
use crate::math::sampling::{cosine_hemisphere_pdf, square_to_cosine_hemisphere};
use crate::spectrum::{Spectrum, Wavelengths};
use crate::texture::{SpectralTexture, TexPoint};
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

#[derive(Clone, Copy, Debug)]
pub struct Plastic<const N: usize> {
    /// ρ' (internal scattering already folded in).
    pub diffuse: Spectrum<N>,
    pub specular: Spectrum<N>,
    pub eta: f32,
    /// Share of samples sent to the specular lobe before the Fresnel weighting.
    pub specular_weight: f32,
}

/// Probability of sampling the specular reflection, given the coating's F at θi (Mitsuba's rule).
#[inline]
pub(super) fn specular_probability(f_i: f32, weight: f32) -> f32 {
    let s = f_i * weight;
    let d = (1.0 - f_i) * (1.0 - weight);
    if s + d > 0.0 {
        s / (s + d)
    } else {
        0.0
    }
}

impl<const N: usize> BsdfLobe<N> for Plastic<N> {
    #[inline]
    fn eval(&self, wi: Vec3, wo: Vec3) -> Spectrum<N> {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return Spectrum::zero();
        }
        let f_i = fresnel::dielectric(wi.z, self.eta).0;
        let f_o = fresnel::dielectric(wo.z, self.eta).0;
        self.diffuse * ((1.0 - f_i) * (1.0 - f_o) * FRAC_1_PI * wo.z / (self.eta * self.eta))
    }

    #[inline]
    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        let p_spec =
            specular_probability(fresnel::dielectric(wi.z, self.eta).0, self.specular_weight);
        (1.0 - p_spec) * cosine_hemisphere_pdf(wo.z)
    }

    #[inline]
    fn sample(&self, wi: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample<N>> {
        if wi.z <= 0.0 {
            return None;
        }
        let f_i = fresnel::dielectric(wi.z, self.eta).0;
        let p_spec = specular_probability(f_i, self.specular_weight);
        if uc < p_spec {
            return Some(BsdfSample {
                wo: Vec3::new(-wi.x, -wi.y, wi.z),
                pdf: p_spec,
                pdf_lanes: Spectrum::splat(p_spec),
                weight: self.specular * (f_i / p_spec),
                delta: true,
                eta: 1.0,
            });
        }
        let wo = square_to_cosine_hemisphere(u);
        let pdf = self.pdf(wi, wo);
        if pdf <= 0.0 {
            return None;
        }
        Some(BsdfSample::reflection(wo, pdf, self.eval(wi, wo) / pdf))
    }

    #[inline]
    fn glossy(&self, _max_alpha: f32) -> bool {
        false
    }
}

/// ρ' = ρ / (1 − F_dr), or ρ / (1 − ρ F_dr) with `nonlinear`: the diffuse base with the light
/// that bounces between it and the coating's underside folded in.
#[inline]
pub(super) fn fold_internal<const N: usize>(
    rho: Spectrum<N>,
    internal: f32,
    nonlinear: bool,
) -> Spectrum<N> {
    if nonlinear {
        Spectrum::from_fn(|i| rho[i] / (1.0 - rho[i] * internal))
    } else {
        rho / (1.0 - internal)
    }
}

/// A smooth plastic's parameters over the surface.
#[derive(Clone, Debug, PartialEq)]
pub struct PlasticParams {
    pub diffuse: SpectralTexture,
    pub specular: SpectralTexture,
    pub eta: f32,
    /// Hemispherical average of the internal Fresnel reflectance.
    pub internal: f32,
    pub nonlinear: bool,
    pub specular_weight: f32,
}

impl BsdfParams for PlasticParams {
    #[inline]
    fn lobe<'a, const N: usize>(
        &'a self,
        si: &SurfaceInteraction,
        wl: &Wavelengths<N>,
    ) -> Lobe<'a, N> {
        Lobe::Plastic(Plastic {
            diffuse: fold_internal(self.diffuse.eval(si.uv, wl), self.internal, self.nonlinear),
            specular: self.specular.eval(si.uv, wl),
            eta: self.eta,
            specular_weight: self.specular_weight,
        })
    }

    fn focuses_light(&self) -> bool {
        true
    }

    fn diffuse_reflectance(&self, uv: TexPoint, wl: &Wavelengths<1>) -> f32 {
        self.diffuse.eval(uv, wl)[0]
    }

    fn traverse<'a>(&'a self, put: &mut impl FnMut(&'static str, Param<'a>)) -> &'static str {
        plastic(&self.diffuse, &self.specular, self.eta, self.nonlinear, put);
        "plastic"
    }
}
