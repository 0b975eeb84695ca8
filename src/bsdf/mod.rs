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

mod conductor;
mod describe;
pub mod dielectric;
mod diffuse;
pub mod fresnel;
mod hit;
mod lobe;
mod material;
pub mod microfacet;
mod mixture;
mod plastic;
pub mod principled;
mod roughconductor;
pub mod roughdielectric;
pub mod roughplastic;
pub mod thindielectric;

pub use conductor::{Conductor, ConductorParams};
pub use describe::Param;
pub use dielectric::Dielectric;
pub use diffuse::Diffuse;
pub use hit::{Bsdf, BsdfLike, BsdfSample};
pub use lobe::Lobe;
pub use material::Material;
pub use mixture::Mixture;
pub use plastic::Plastic;
pub use principled::{Principled, PrincipledParams, SpecularColorTexture};
pub use roughconductor::RoughConductor;
pub use roughdielectric::RoughDielectric;
pub use roughplastic::RoughPlastic;
pub use thindielectric::ThinDielectric;

/// Most leaf lobes one material may combine (blends and masks of blends…).
pub const MAX_LOBES: usize = 4;
