//! What a material says about itself, so that no other floor matches on its variants: its
//! diffuse reflectance (Mitsuba 3's `eval_diffuse_reflectance`, the `albedo` AOV) and its
//! parameters by Mitsuba 3's names (its `traverse`, read by `prism export`). A leaf answers
//! both in its own file (`BsdfParams`); the inner nodes here, with the helpers several BSDFs
//! share. The readers stay as they are.

use super::microfacet::Distribution;
use super::{ConductorParams, Material};
use crate::spectrum::{Curve, RelativeIor, Wavelengths};
use crate::texture::{FloatTexture, SpectralTexture, TexPoint};

/// One parameter of a material, typed so that a reader can write it out.
pub enum Param<'a> {
    Texture(&'a SpectralTexture),
    Float(&'a FloatTexture),
    Spectrum(&'a Curve),
    Number(f32),
    Bool(bool),
    Distribution(Distribution),
    /// A dielectric's interior and exterior indices (`int_ior`, `ext_ior`, `dispersive`).
    Ior(&'a RelativeIor),
    /// A nested material (`twosided`, `blend`, `mask`).
    Bsdf(&'a Material),
}

impl Material {
    /// ρ(λ) of the diffuse part at texture coordinates `uv`; `front`: the camera meets the
    /// shading normal's side. Definition (scenes/README.md, "AOVs"): `diffuse` its reflectance;
    /// plastics the base's (before the coating); `principled` base colour × (1 − metallic) ×
    /// (1 − transmission); `twosided` the side met; `blend` (1 − w)·a + w·b; `mask`
    /// opacity·inner; conductors and dielectrics 0.
    pub fn diffuse_reflectance(&self, uv: TexPoint, front: bool, lambda: f32) -> f32 {
        let wl = Wavelengths::<1> {
            lambda: [lambda],
            pdf: [1.0],
        };
        match self {
            Material::Twosided { front: f, back: b } => {
                (if front { f } else { b }).diffuse_reflectance(uv, front, lambda)
            }
            Material::Blend { a, b, weight } => {
                let w = weight.eval(uv);
                (1.0 - w) * a.diffuse_reflectance(uv, front, lambda)
                    + w * b.diffuse_reflectance(uv, front, lambda)
            }
            Material::Mask { inner, opacity } => {
                opacity.eval(uv) * inner.diffuse_reflectance(uv, front, lambda)
            }
            leaf => leaf.leaf_diffuse_reflectance(uv, &wl),
        }
    }

    /// Mitsuba 3's plugin name of the material (`principled` is glTF's model, which Mitsuba's
    /// `principled` is not: `gltf_principled`), its parameters passed to `put` by name.
    pub fn traverse<'a>(&'a self, put: &mut impl FnMut(&'static str, Param<'a>)) -> &'static str {
        use Param::*;
        match self {
            Material::Twosided { front, back } => {
                put("front", Bsdf(front));
                put("back", Bsdf(back));
                "twosided"
            }
            Material::Blend { a, b, weight } => {
                put("weight", Float(weight));
                put("bsdf0", Bsdf(a));
                put("bsdf1", Bsdf(b));
                "blend"
            }
            Material::Mask { inner, opacity } => {
                put("opacity", Float(opacity));
                put("bsdf", Bsdf(inner));
                "mask"
            }
            leaf => leaf.leaf_traverse(put),
        }
    }
}

/// A conductor's optical constants and factor (`conductor`, `roughconductor`).
pub(super) fn conductor<'a>(p: &'a ConductorParams, put: &mut impl FnMut(&'static str, Param<'a>)) {
    put("eta", Param::Spectrum(&p.eta));
    put("k", Param::Spectrum(&p.k));
    put(
        "specular_reflectance",
        Param::Texture(&p.specular_reflectance),
    );
}

/// A dielectric interface's factors and indices (the three dielectrics).
pub(super) fn dielectric<'a>(
    ior: &'a RelativeIor,
    reflectance: &'a SpectralTexture,
    transmittance: &'a SpectralTexture,
    put: &mut impl FnMut(&'static str, Param<'a>),
) {
    put("specular_reflectance", Param::Texture(reflectance));
    put("specular_transmittance", Param::Texture(transmittance));
    put("ior", Param::Ior(ior));
}

/// A plastic's coating: Mitsuba takes its indices as numbers, the exterior one being air's.
pub(super) fn plastic<'a>(
    diffuse: &'a SpectralTexture,
    specular: &'a SpectralTexture,
    eta: f32,
    nonlinear: bool,
    put: &mut impl FnMut(&'static str, Param<'a>),
) {
    put("diffuse_reflectance", Param::Texture(diffuse));
    put("specular_reflectance", Param::Texture(specular));
    put("int_ior", Param::Number(eta));
    put("ext_ior", Param::Number(1.0));
    put("nonlinear", Param::Bool(nonlinear));
}

/// A microfacet distribution with roughnesses along the tangent and bitangent.
pub(super) fn rough<'a>(
    d: Distribution,
    u: &'a FloatTexture,
    v: &'a FloatTexture,
    put: &mut impl FnMut(&'static str, Param<'a>),
) {
    put("distribution", Param::Distribution(d));
    put("alpha_u", Param::Float(u));
    put("alpha_v", Param::Float(v));
}
