//! What a material says about itself, so that no other floor matches on its variants: its
//! diffuse reflectance (Mitsuba 3's `eval_diffuse_reflectance`, the `albedo` AOV) and its
//! parameters by Mitsuba 3's names (its `traverse`, read by `prism export`). A new material
//! answers both here, next to its enum; the readers stay as they are.

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
            Material::Diffuse { reflectance } => reflectance.eval(uv, &wl)[0],
            Material::Plastic { diffuse, .. } | Material::RoughPlastic { diffuse, .. } => {
                diffuse.eval(uv, &wl)[0]
            }
            Material::Principled(p) => {
                let keep = (1.0 - p.metallic.eval(uv).clamp(0.0, 1.0))
                    * (1.0 - p.transmission.eval(uv).clamp(0.0, 1.0));
                p.base_color.eval(uv, &wl)[0] * keep
            }
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
            Material::Conductor(_)
            | Material::RoughConductor { .. }
            | Material::Dielectric { .. }
            | Material::RoughDielectric { .. }
            | Material::ThinDielectric { .. } => 0.0,
        }
    }

    /// Mitsuba 3's plugin name of the material (`principled` is glTF's model, which Mitsuba's
    /// `principled` is not: `gltf_principled`), its parameters passed to `put` by name.
    pub fn traverse<'a>(&'a self, put: &mut impl FnMut(&'static str, Param<'a>)) -> &'static str {
        use Param::*;
        match self {
            Material::Diffuse { reflectance } => {
                put("reflectance", Texture(reflectance));
                "diffuse"
            }
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
            Material::Conductor(p) => {
                conductor(p, put);
                "conductor"
            }
            Material::RoughConductor {
                params,
                distribution,
                alpha_u,
                alpha_v,
            } => {
                conductor(params, put);
                rough(*distribution, alpha_u, alpha_v, put);
                "roughconductor"
            }
            Material::Dielectric {
                ior,
                specular_reflectance,
                specular_transmittance,
            } => {
                dielectric(ior, specular_reflectance, specular_transmittance, put);
                "dielectric"
            }
            Material::RoughDielectric {
                ior,
                distribution,
                alpha_u,
                alpha_v,
                specular_reflectance,
                specular_transmittance,
            } => {
                dielectric(ior, specular_reflectance, specular_transmittance, put);
                rough(*distribution, alpha_u, alpha_v, put);
                "roughdielectric"
            }
            Material::ThinDielectric {
                ior,
                specular_reflectance,
                specular_transmittance,
            } => {
                dielectric(ior, specular_reflectance, specular_transmittance, put);
                "thindielectric"
            }
            Material::Plastic {
                diffuse,
                specular,
                eta,
                nonlinear,
                ..
            } => {
                plastic(diffuse, specular, *eta, *nonlinear, put);
                "plastic"
            }
            Material::RoughPlastic {
                diffuse,
                specular,
                eta,
                microfacet,
                nonlinear,
                ..
            } => {
                plastic(diffuse, specular, *eta, *nonlinear, put);
                put("distribution", Distribution(microfacet.kind));
                put("alpha", Number(microfacet.alpha_u));
                "roughplastic"
            }
            Material::Principled(p) => {
                put("base_color", Texture(&p.base_color));
                put("metallic", Float(&p.metallic));
                put("roughness", Float(&p.roughness));
                put("f0_ior", Number(p.f0_ior));
                put("specular", Float(&p.specular));
                put("specular_color", Spectrum(&p.specular_color));
                put("specular_color_max", Number(p.specular_color_max));
                put("transmission", Float(&p.transmission));
                "gltf_principled"
            }
        }
    }
}

fn conductor<'a>(p: &'a ConductorParams, put: &mut impl FnMut(&'static str, Param<'a>)) {
    put("eta", Param::Spectrum(&p.eta));
    put("k", Param::Spectrum(&p.k));
    put(
        "specular_reflectance",
        Param::Texture(&p.specular_reflectance),
    );
}

fn dielectric<'a>(
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
fn plastic<'a>(
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

fn rough<'a>(
    d: Distribution,
    u: &'a FloatTexture,
    v: &'a FloatTexture,
    put: &mut impl FnMut(&'static str, Param<'a>),
) {
    put("distribution", Param::Distribution(d));
    put("alpha_u", Param::Float(u));
    put("alpha_v", Param::Float(v));
}
