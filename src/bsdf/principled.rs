//! The glTF 2.0 metallic-roughness BRDF, as the specification's Appendix B defines it, with the
//! `ior`, `specular` and `transmission` extensions:
//!
//! ```text
//! material       = mix(dielectric_brdf, metal_brdf, metallic)
//! metal_brdf     = specular_brdf(α) · (f0 + (1 − f0)(1 − |V·H|)⁵),   f0 = baseColor
//! dielectric     = (1 − w·max(Fr)) · mix(diffuse, baseColor·specular_btdf(α), transmission)
//!                  + w · Fr · specular_brdf(α)
//! Fr             = f0_d + (1 − f0_d)(1 − |V·H|)⁵,   f0_d = min(((ior − 1)/(ior + 1))² · specularColor, 1)
//! specular_brdf  = D(H) · G(L, V) / (4 |N·L| |N·V|)     (GGX, α = roughness², separable Smith)
//! diffuse        = baseColor / π
//! ```
//!
//! with w = `specular` (KHR_materials_specular's factor; 1 without the extension). max(Fr) is
//! the largest RGB component of Fr; Fr grows with f0_d, so it is Fr at the largest component
//! of f0_d, which is kept apart (`f0_max`) while Fr itself is evaluated per wavelength. The
//! transmission lobe is KHR_materials_transmission's thin-walled one (no volume): the specular
//! lobe mirrored to the other side of the surface. The material is the same from both sides (a
//! glTF surface has no inside without KHR_materials_volume), so a direction pair below the
//! surface is mirrored above it first.
//!
//! Sampling picks the metal/specular lobe with probability metallic + (1 − metallic)·w·Fr(cos θi)
//! (scalar, from `f0_max`), else the diffuse or the transmission lobe in the ratio
//! (1 − transmission) : transmission; the specular lobes sample the GGX visible normals.

use super::microfacet::Distribution;
use super::microfacet::Microfacet;
use super::{BsdfLobe, BsdfParams, BsdfSample, Lobe, Param};
use crate::interaction::SurfaceInteraction;
use crate::math::sampling::{cosine_hemisphere_pdf, square_to_cosine_hemisphere};
use crate::spectrum::{Curve, Spectrum, Wavelengths};
use crate::texture::{FloatTexture, SpectralTexture, TexPoint};
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

/// A principled material's parameters over the surface (`Material::Principled`).
#[derive(Clone, Debug, PartialEq)]
pub struct PrincipledParams {
    pub base_color: SpectralTexture,
    /// In [0, 1] (texture values are clamped).
    pub metallic: FloatTexture,
    /// Perceptual roughness in [0, 1]; α = roughness².
    pub roughness: FloatTexture,
    /// ((ior − 1)/(ior + 1))².
    pub f0_ior: f32,
    /// KHR_materials_specular's colour (a reflectance-like factor of f0) and its largest RGB
    /// component (the largest value over the wavelength range for a non-RGB spectrum).
    pub specular_color: Curve,
    pub specular_color_max: f32,
    /// KHR_materials_specular's weight (1 without the extension; clamped to [0, 1]).
    pub specular: FloatTexture,
    pub transmission: FloatTexture,
    /// KHR_materials_specular's specularColorTexture, which multiplies `specular_color`; None
    /// without one.
    pub specular_color_texture: Option<Box<SpecularColorTexture>>,
}

/// A specular-colour texture: its (uplifted) texels, and per texel the largest RGB component
/// of texel × factor, which replaces `specular_color_max` where the texture is.
#[derive(Clone, Debug, PartialEq)]
pub struct SpecularColorTexture {
    pub color: SpectralTexture,
    pub max: FloatTexture,
}

impl PrincipledParams {
    /// The BSDF at texture coordinates `uv` (or a hit, for vertex colours) and the path's
    /// wavelengths.
    #[inline]
    pub fn at<const N: usize>(
        &self,
        at: impl Into<TexPoint>,
        wl: &Wavelengths<N>,
    ) -> Principled<N> {
        let uv: TexPoint = at.into();
        let r = self.roughness.eval(uv).clamp(0.0, 1.0);
        let alpha = r * r;
        let mut sc = self.specular_color.eval(wl);
        let mut sc_max = self.specular_color_max;
        if let Some(t) = &self.specular_color_texture {
            sc *= t.color.eval(uv, wl);
            sc_max = t.max.eval(uv);
        }
        Principled {
            base_color: self.base_color.eval(uv, wl),
            metallic: self.metallic.eval(uv).clamp(0.0, 1.0),
            distr: Microfacet::new(Distribution::Ggx, alpha, alpha),
            f0: Spectrum::from_fn(|k| (self.f0_ior * sc[k]).min(1.0)),
            f0_max: (self.f0_ior * sc_max).min(1.0),
            specular: self.specular.eval(uv).clamp(0.0, 1.0),
            transmission: self.transmission.eval(uv).clamp(0.0, 1.0),
        }
    }
}

/// The principled BSDF at one hit, at the path's wavelengths.
#[derive(Clone, Copy, Debug)]
pub struct Principled<const N: usize> {
    pub base_color: Spectrum<N>,
    pub metallic: f32,
    /// GGX with α = roughness².
    pub distr: Microfacet,
    /// The dielectric's normal-incidence reflectance per lane, min(f0(ior) · specularColor, 1).
    pub f0: Spectrum<N>,
    /// Its largest RGB component (for the spec's max(Fr) weighting of the base layer).
    pub f0_max: f32,
    /// KHR_materials_specular's `specular` weight w.
    pub specular: f32,
    /// KHR_materials_transmission's factor.
    pub transmission: f32,
}

/// Schlick's (1 − c)⁵.
#[inline]
fn schlick_weight(c: f32) -> f32 {
    let m = (1.0 - c).clamp(0.0, 1.0);
    let m2 = m * m;
    m2 * m2 * m
}

/// Both directions above the surface (the material is the same from both sides), and whether
/// `wo` crossed to the other side (transmission) before mirroring.
#[inline]
fn upper(wi: Vec3, wo: Vec3) -> (Vec3, Vec3, bool) {
    let (wi, wo) = if wi.z < 0.0 { (-wi, -wo) } else { (wi, wo) };
    if wo.z < 0.0 {
        (wi, Vec3::new(wo.x, wo.y, -wo.z), true)
    } else {
        (wi, wo, false)
    }
}

impl<const N: usize> Principled<N> {
    /// Probability of sampling the specular (metal and dielectric) lobe from cos θi.
    #[inline]
    fn p_specular(&self, cos_i: f32) -> f32 {
        let fr = self.f0_max + (1.0 - self.f0_max) * schlick_weight(cos_i);
        let p = self.metallic + (1.0 - self.metallic) * self.specular * fr;
        p.clamp(0.0, 1.0)
    }

    /// D G / (4 cos θi) (the specular BRDF times cos θo), with `wo` above the surface.
    #[inline]
    fn specular_lobe(&self, wi: Vec3, wo: Vec3, h: Vec3) -> f32 {
        let d = self.distr.d(h);
        if d == 0.0 {
            return 0.0;
        }
        d * self.distr.g(wi, wo, h) / (4.0 * wi.z)
    }
}

impl<const N: usize> BsdfLobe<N> for Principled<N> {
    /// f(wi, wo) · |cos θo| per lane.
    #[inline]
    fn eval(&self, wi: Vec3, wo: Vec3) -> Spectrum<N> {
        if wi.z == 0.0 || wo.z == 0.0 {
            return Spectrum::zero();
        }
        let (wi, wo, through) = upper(wi, wo);
        let h = (wi + wo).normalize();
        let vh = wi.dot(h).abs();
        let sw = schlick_weight(vh);
        let spec = self.specular_lobe(wi, wo, h);
        let fr_max = self.f0_max + (1.0 - self.f0_max) * sw;
        let base_weight = (1.0 - self.specular * fr_max) * (1.0 - self.metallic);
        if through {
            // Thin-walled transmission: baseColor · specular_btdf, under the dielectric layer.
            return self.base_color * (base_weight * self.transmission * spec);
        }
        let diffuse = base_weight * (1.0 - self.transmission) * FRAC_1_PI * wo.z;
        Spectrum::from_fn(|k| {
            let b = self.base_color[k];
            let metal = b + (1.0 - b) * sw;
            let fr = self.f0[k] + (1.0 - self.f0[k]) * sw;
            b * diffuse
                + spec * (self.metallic * metal + (1.0 - self.metallic) * self.specular * fr)
        })
    }

    /// Density of `sample` (solid angle).
    #[inline]
    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        if wi.z == 0.0 || wo.z == 0.0 {
            return 0.0;
        }
        let (wi, wo, through) = upper(wi, wo);
        let p_spec = self.p_specular(wi.z);
        let rest = 1.0 - p_spec;
        let h = (wi + wo).normalize();
        let cos_h = wo.dot(h);
        let p_glossy = if cos_h > 0.0 {
            self.distr.pdf_visible(wi, h) / (4.0 * cos_h)
        } else {
            0.0
        };
        if through {
            rest * self.transmission * p_glossy
        } else {
            p_spec * p_glossy + rest * (1.0 - self.transmission) * cosine_hemisphere_pdf(wo.z)
        }
    }

    #[inline]
    fn sample(&self, wi_in: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample<N>> {
        if wi_in.z == 0.0 {
            return None;
        }
        let below = wi_in.z < 0.0;
        let wi = if below { -wi_in } else { wi_in };
        let p_spec = self.p_specular(wi.z);
        let rest = 1.0 - p_spec;
        let p_trans = rest * self.transmission;
        let mut wo = if uc < p_spec || uc < p_spec + p_trans {
            let m = self.distr.sample_visible(wi, u);
            let wo = 2.0 * wi.dot(m) * m - wi;
            if wo.z <= 0.0 {
                return None;
            }
            if uc < p_spec {
                wo
            } else {
                Vec3::new(wo.x, wo.y, -wo.z)
            }
        } else {
            square_to_cosine_hemisphere(u)
        };
        if below {
            wo = -wo;
        }
        let pdf = self.pdf(wi_in, wo);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        let f = self.eval(wi_in, wo);
        Some(BsdfSample::reflection(wo, pdf, f / pdf))
    }

    /// Only a pure metal is glossy throughout (a dielectric has a diffuse base).
    #[inline]
    fn glossy(&self, max_alpha: f32) -> bool {
        self.metallic >= 1.0 && self.distr.alpha_u <= max_alpha
    }
}

impl BsdfParams for PrincipledParams {
    #[inline]
    fn lobe<'a, const N: usize>(
        &'a self,
        si: &SurfaceInteraction,
        wl: &Wavelengths<N>,
    ) -> Lobe<'a, N> {
        Lobe::Principled(self.at(si, wl))
    }

    fn focuses_light(&self) -> bool {
        true
    }

    fn diffuse_reflectance(&self, uv: TexPoint, wl: &Wavelengths<1>) -> f32 {
        let keep = (1.0 - self.metallic.eval(uv).clamp(0.0, 1.0))
            * (1.0 - self.transmission.eval(uv).clamp(0.0, 1.0));
        self.base_color.eval(uv, wl)[0] * keep
    }

    fn traverse<'a>(&'a self, put: &mut impl FnMut(&'static str, Param<'a>)) -> &'static str {
        put("base_color", Param::Texture(&self.base_color));
        put("metallic", Param::Float(&self.metallic));
        put("roughness", Param::Float(&self.roughness));
        put("f0_ior", Param::Number(self.f0_ior));
        put("specular", Param::Float(&self.specular));
        put("specular_color", Param::Spectrum(&self.specular_color));
        put("specular_color_max", Param::Number(self.specular_color_max));
        put("transmission", Param::Float(&self.transmission));
        "gltf_principled"
    }
}
