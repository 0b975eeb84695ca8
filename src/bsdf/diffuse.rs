//! Lambertian reflection (Mitsuba's `diffuse`): f = ρ/π on the front side, cosine sampling.

use super::{BsdfLobe, BsdfParams, BsdfSample, Lobe, Param};
use crate::interaction::SurfaceInteraction;
use crate::math::sampling::{cosine_hemisphere_pdf, square_to_cosine_hemisphere};
use crate::spectrum::{Spectrum, Wavelengths};
use crate::texture::{SpectralTexture, TexPoint};
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

#[derive(Clone, Copy, Debug)]
pub struct Diffuse<const N: usize> {
    pub reflectance: Spectrum<N>,
}

impl<const N: usize> BsdfLobe<N> for Diffuse<N> {
    #[inline]
    fn eval(&self, wi: Vec3, wo: Vec3) -> Spectrum<N> {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return Spectrum::zero();
        }
        self.reflectance * (FRAC_1_PI * wo.z)
    }

    #[inline]
    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        cosine_hemisphere_pdf(wo.z)
    }

    #[inline]
    fn sample(&self, wi: Vec3, _uc: f32, u: Vec2) -> Option<BsdfSample<N>> {
        if wi.z <= 0.0 {
            return None;
        }
        let wo = square_to_cosine_hemisphere(u);
        let pdf = cosine_hemisphere_pdf(wo.z);
        if pdf <= 0.0 {
            return None;
        }
        Some(BsdfSample::reflection(wo, pdf, self.reflectance))
    }

    #[inline]
    fn glossy(&self, _max_alpha: f32) -> bool {
        false
    }
}

/// A diffuse material's parameters over the surface.
#[derive(Clone, Debug, PartialEq)]
pub struct DiffuseParams {
    pub reflectance: SpectralTexture,
}

impl DiffuseParams {
    /// The lobe at a hit (also built directly, as `Bsdf::Diffuse`, for a plain diffuse material).
    #[inline]
    pub fn at<const N: usize>(&self, si: &SurfaceInteraction, wl: &Wavelengths<N>) -> Diffuse<N> {
        Diffuse {
            reflectance: self.reflectance.eval(si.uv, wl),
        }
    }
}

impl BsdfParams for DiffuseParams {
    #[inline]
    fn lobe<'a, const N: usize>(
        &'a self,
        si: &SurfaceInteraction,
        wl: &Wavelengths<N>,
    ) -> Lobe<'a, N> {
        Lobe::Diffuse(self.at(si, wl))
    }

    fn focuses_light(&self) -> bool {
        false
    }

    fn diffuse_reflectance(&self, uv: TexPoint, wl: &Wavelengths<1>) -> f32 {
        self.reflectance.eval(uv, wl)[0]
    }

    fn traverse<'a>(&'a self, put: &mut impl FnMut(&'static str, Param<'a>)) -> &'static str {
        put("reflectance", Param::Texture(&self.reflectance));
        "diffuse"
    }
}
