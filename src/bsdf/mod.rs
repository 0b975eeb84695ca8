//! Materials and BSDFs.
//!
//! A `Material` is what the scene holds (spectra, later textures). At a hit it becomes a
//! `Bsdf<N>`: the BSDF with its parameters evaluated at the path's N wavelengths, on the stack.
//! Directions are in the local shading frame (z = normal) and point away from the surface:
//! `wi` towards the previous vertex (the camera side), `wo` towards the next (the light side).
//! BSDFs are one-sided, as in Mitsuba 3: light arriving from below the surface is black.

mod diffuse;

use crate::interaction::SurfaceInteraction;
use crate::spectrum::{Curve, Spectrum, Wavelengths};
pub use diffuse::Diffuse;
use glam::{Vec2, Vec3};

/// A material of the scene.
#[derive(Clone, Debug, PartialEq)]
pub enum Material {
    Diffuse { reflectance: Curve },
}

/// A BSDF at one hit, at the path's wavelengths.
#[derive(Clone, Copy, Debug)]
pub enum Bsdf<const N: usize> {
    Diffuse(Diffuse<N>),
}

/// A sampled outgoing direction.
#[derive(Clone, Copy, Debug)]
pub struct BsdfSample<const N: usize> {
    pub wo: Vec3,
    /// Solid-angle density of `wo` (for a delta lobe: the discrete probability of the lobe).
    pub pdf: f32,
    /// f · |cos θ_o| / pdf.
    pub weight: Spectrum<N>,
    /// True for a specular (Dirac) lobe: no emitter sampling, no MIS.
    pub delta: bool,
    /// Relative index of refraction crossed (1 for reflection).
    pub eta: f32,
}

impl Material {
    #[inline]
    pub fn bsdf<const N: usize>(&self, _si: &SurfaceInteraction, wl: &Wavelengths<N>) -> Bsdf<N> {
        match self {
            Material::Diffuse { reflectance } => Bsdf::Diffuse(Diffuse {
                reflectance: reflectance.eval(wl),
            }),
        }
    }
}

impl<const N: usize> Bsdf<N> {
    /// f(wi, wo) · |cos θ_o|.
    #[inline]
    pub fn eval(&self, wi: Vec3, wo: Vec3) -> Spectrum<N> {
        match self {
            Bsdf::Diffuse(b) => b.eval(wi, wo),
        }
    }

    /// Solid-angle density with which `sample` picks `wo` (hero wavelength).
    #[inline]
    pub fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        match self {
            Bsdf::Diffuse(b) => b.pdf(wi, wo),
        }
    }

    /// `uc` picks a lobe, `u` the direction within it.
    #[inline]
    pub fn sample(&self, wi: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample<N>> {
        match self {
            Bsdf::Diffuse(b) => b.sample(wi, uc, u),
        }
    }

    /// True if some lobe is not a delta: emitter sampling can then contribute.
    #[inline]
    pub fn has_smooth(&self) -> bool {
        match self {
            Bsdf::Diffuse(_) => true,
        }
    }
}
