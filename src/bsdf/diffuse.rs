//! Lambertian reflection (Mitsuba's `diffuse`): f = ρ/π on the front side, cosine sampling.

use super::BsdfSample;
use crate::math::sampling::{cosine_hemisphere_pdf, square_to_cosine_hemisphere};
use crate::spectrum::Spectrum;
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

#[derive(Clone, Copy, Debug)]
pub struct Diffuse<const N: usize> {
    pub reflectance: Spectrum<N>,
}

impl<const N: usize> Diffuse<N> {
    #[inline]
    pub fn eval(&self, wi: Vec3, wo: Vec3) -> Spectrum<N> {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return Spectrum::zero();
        }
        self.reflectance * (FRAC_1_PI * wo.z)
    }

    #[inline]
    pub fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        cosine_hemisphere_pdf(wo.z)
    }

    #[inline]
    pub fn sample(&self, wi: Vec3, _uc: f32, u: Vec2) -> Option<BsdfSample<N>> {
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
}
