//! Materials and BSDFs.
//!
//! A `Material` is what the scene holds: a tree of BSDFs (Mitsuba's names: `diffuse`,
//! `conductor`, `dielectric`, …, combined by `twosided`, `blend` and `mask`) whose parameters
//! are spectra or textures. At a hit it becomes a `Bsdf<N>`: a mixture of at most `MAX_LOBES`
//! leaf lobes with their parameters evaluated at the path's N wavelengths and the hit's uv,
//! built on the stack (no allocation, static dispatch). A plain `diffuse` material, the
//! commonest by far, becomes a lone diffuse lobe instead, which the integrator handles without
//! any of the mixture's machinery: a diffuse-only scene pays nothing for the other materials
//! (docs/performance.md).
//!
//! Directions are in the local shading frame (z = normal) and point away from the surface:
//! `wi` towards the previous vertex (the camera side), `wo` towards the next (the light side).
//! Leaf BSDFs are one-sided where Mitsuba's are (light from below a diffuse surface is black);
//! `twosided` mirrors directions (z → −z) for the back side.
//!
//! Wavelength-dependent sampling (dispersion): a sample reports the density with which each
//! lane's BSDF would have produced the same direction (`pdf_lanes`); the integrator weights the
//! lanes by spectral MIS with them (Wilkie et al. 2014).

/// The BSDFs, one line each: `Variant(its lobe at a hit, its parameters in the scene)`. `Lobe`
/// (lobe.rs) and `Material` (material.rs) are generated from this list, so a new BSDF is its
/// own file (the two types, implementing `BsdfLobe` and `BsdfParams`), its `mod` and `pub use`
/// lines and its line here; `config` and `load` add its schema and its loader.
macro_rules! for_each_bsdf {
    ($then:ident) => {
        $then! {
            Diffuse(Diffuse<N>, DiffuseParams),
            // Conductors.
            Conductor(Conductor<N>, ConductorParams),
            RoughConductor(RoughConductor<N>, RoughConductorParams),
            // Dielectrics.
            Dielectric(Dielectric<N>, DielectricParams),
            RoughDielectric(RoughDielectric<N>, RoughDielectricParams),
            ThinDielectric(ThinDielectric<N>, ThinDielectricParams),
            // Plastics.
            Plastic(Plastic<N>, PlasticParams),
            RoughPlastic(RoughPlastic<'a, N>, RoughPlasticParams),
            Principled(Principled<N>, Box<PrincipledParams>),
        }
    };
}

mod describe;
mod hit;
mod lobe;
mod material;
mod mixture;

pub mod conductor;
pub mod dielectric;
pub mod diffuse;
pub mod fresnel;
pub mod microfacet;
pub mod plastic;
pub mod principled;
pub mod roughconductor;
pub mod roughdielectric;
pub mod roughplastic;
pub mod thindielectric;

pub use conductor::{Conductor, ConductorParams};
pub use describe::Param;
pub use dielectric::{Dielectric, DielectricParams};
pub use diffuse::{Diffuse, DiffuseParams};
pub use hit::{Bsdf, BsdfLike, BsdfSample};
pub use lobe::{BsdfLobe, Lobe};
pub use material::{BsdfParams, Material};
pub use mixture::Mixture;
pub use plastic::{Plastic, PlasticParams};
pub use principled::{Principled, PrincipledParams, SpecularColorTexture};
pub use roughconductor::{RoughConductor, RoughConductorParams};
pub use roughdielectric::{RoughDielectric, RoughDielectricParams};
pub use roughplastic::{RoughPlastic, RoughPlasticParams};
pub use thindielectric::{ThinDielectric, ThinDielectricParams};

/// Most leaf lobes one material may combine (blends and masks of blends…).
pub const MAX_LOBES: usize = 4;
