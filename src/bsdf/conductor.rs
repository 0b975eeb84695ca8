//! A smooth conductor (Mitsuba's `conductor`): mirror reflection scaled by the Fresnel
//! reflectance of the complex index η + iκ, per wavelength. One-sided, like Mitsuba's.

use super::describe::conductor;
use super::{fresnel, BsdfLobe, BsdfParams, BsdfSample, Lobe, Param};
use crate::interaction::SurfaceInteraction;
use crate::spectrum::{Curve, Spectrum, Wavelengths};
use crate::texture::SpectralTexture;
use glam::{Vec2, Vec3};

/// A conductor's optical constants at the path's wavelengths.
#[derive(Clone, Copy, Debug)]
pub struct Conductor<const N: usize> {
    /// Real part of the index of refraction, relative to the outside medium.
    pub eta: Spectrum<N>,
    /// Imaginary part (extinction coefficient).
    pub k: Spectrum<N>,
    /// Factor on the reflection (Mitsuba's `specular_reflectance`; 1 for a physical metal).
    pub specular: Spectrum<N>,
}

impl<const N: usize> Conductor<N> {
    /// Fresnel reflectance times `specular` for light meeting a (micro)surface at cos θ = `cos`.
    #[inline]
    pub fn reflectance(&self, cos: f32) -> Spectrum<N> {
        Spectrum::from_fn(|i| fresnel::conductor(cos, self.eta[i], self.k[i])) * self.specular
    }
}

impl<const N: usize> BsdfLobe<N> for Conductor<N> {
    /// The mirror direction, with weight F(cos θ_i): the only direction this lobe scatters to.
    #[inline]
    fn sample(&self, wi: Vec3, _uc: f32, _u: Vec2) -> Option<BsdfSample<N>> {
        if wi.z <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wo: Vec3::new(-wi.x, -wi.y, wi.z),
            pdf: 1.0,
            pdf_lanes: Spectrum::one(),
            weight: self.reflectance(wi.z),
            delta: true,
            eta: 1.0,
        })
    }

    #[inline]
    fn eval(&self, _wi: Vec3, _wo: Vec3) -> Spectrum<N> {
        Spectrum::zero()
    }

    #[inline]
    fn pdf(&self, _wi: Vec3, _wo: Vec3) -> f32 {
        0.0
    }

    #[inline]
    fn has_smooth(&self) -> bool {
        false
    }

    #[inline]
    fn glossy(&self, _max_alpha: f32) -> bool {
        true
    }
}

/// A conductor's parameters as the scene gives them, before a hit fixes the wavelengths and uv.
#[derive(Clone, Debug, PartialEq)]
pub struct ConductorParams {
    /// Real part of the index of refraction.
    pub eta: Curve,
    /// Imaginary part.
    pub k: Curve,
    /// Factor on the reflection; may vary over the surface.
    pub specular_reflectance: SpectralTexture,
}

impl ConductorParams {
    /// The conductor at a hit's uv and the path's wavelengths.
    #[inline]
    pub fn at<const N: usize>(&self, uv: Vec2, wl: &Wavelengths<N>) -> Conductor<N> {
        Conductor {
            eta: self.eta.eval(wl),
            k: self.k.eval(wl),
            specular: self.specular_reflectance.eval(uv, wl),
        }
    }
}

impl BsdfParams for ConductorParams {
    #[inline]
    fn lobe<'a, const N: usize>(
        &'a self,
        si: &SurfaceInteraction,
        wl: &Wavelengths<N>,
    ) -> Lobe<'a, N> {
        Lobe::Conductor(self.at(si.uv, wl))
    }

    fn focuses_light(&self) -> bool {
        true
    }

    fn traverse<'a>(&'a self, put: &mut impl FnMut(&'static str, Param<'a>)) -> &'static str {
        conductor(self, put);
        "conductor"
    }
}
