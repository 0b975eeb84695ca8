//! Materials in the scene file (Mitsuba 3's BSDF names and parameters); `load::materials` turns
//! them into `bsdf::Material`s. Each material answers for its fields in `fields` (`Field`), so
//! a dataset variation or a path rewrite never matches on the material kinds.

mod fields;

pub use fields::Field;

use super::shape::one;
use super::{FloatConfig, IorConfig, SpectrumConfig};
use crate::bsdf::microfacet::Distribution;
use serde::{Deserialize, Serialize};

/// A material (Mitsuba 3's BSDF names and parameters).
///
/// ```ron
/// Diffuse(reflectance: Rgb(0.8, 0.2, 0.2))
/// Twosided(bsdf: Diffuse(reflectance: Bitmap(path: "leaf.png")))
/// Blend(weight: 0.3, bsdf0: Diffuse(), bsdf1: Diffuse(reflectance: Constant(0.9)))
/// Mask(opacity: Bitmap(path: "alpha.png"), bsdf: Diffuse())
/// Conductor(material: "Au")
/// RoughConductor(material: "Al", distribution: Ggx, alpha_u: 0.05, alpha_v: 0.3)
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum MaterialConfig {
    /// Lambertian, one-sided (Mitsuba's `diffuse`). `reflectance` default `Constant(0.5)`.
    Diffuse {
        #[serde(default = "half_grey")]
        reflectance: SpectrumConfig,
    },
    /// `bsdf` on both sides (or `bsdf` in front and `back` behind), Mitsuba's `twosided`.
    Twosided {
        bsdf: Box<MaterialConfig>,
        #[serde(default)]
        back: Option<Box<MaterialConfig>>,
    },
    /// (1 − weight)·bsdf0 + weight·bsdf1 (Mitsuba's `blendbsdf`); `weight` default 0.5.
    Blend {
        #[serde(default = "half")]
        weight: FloatConfig,
        bsdf0: Box<MaterialConfig>,
        bsdf1: Box<MaterialConfig>,
    },
    /// `opacity`·bsdf; the rest of the light passes straight through (Mitsuba's `mask`);
    /// `opacity` default 0.5.
    Mask {
        #[serde(default = "half")]
        opacity: FloatConfig,
        bsdf: Box<MaterialConfig>,
    },
    // Conductors.
    /// A smooth metal (Mitsuba's `conductor`): `material` names a metal (`"Au"`, `"Cu"`, …;
    /// default `"none"`, a perfect mirror), or `eta` and `k` give its index of refraction
    /// (defaults 0 and 1, the same mirror), not both; `specular_reflectance` default 1.
    Conductor {
        #[serde(default)]
        material: Option<String>,
        #[serde(default)]
        eta: Option<SpectrumConfig>,
        #[serde(default)]
        k: Option<SpectrumConfig>,
        #[serde(default = "full_reflectance")]
        specular_reflectance: SpectrumConfig,
    },
    /// A rough metal (Mitsuba's `roughconductor`): `distribution` `Beckmann` (default) or `Ggx`;
    /// `alpha` (default 0.1) or both `alpha_u` and `alpha_v`, each in (0, 1], a number or a
    /// texture; `material`, `eta`, `k`, `specular_reflectance` as for `Conductor`.
    RoughConductor {
        #[serde(default)]
        distribution: Distribution,
        #[serde(default)]
        alpha: Option<FloatConfig>,
        #[serde(default)]
        alpha_u: Option<FloatConfig>,
        #[serde(default)]
        alpha_v: Option<FloatConfig>,
        #[serde(default)]
        material: Option<String>,
        #[serde(default)]
        eta: Option<SpectrumConfig>,
        #[serde(default)]
        k: Option<SpectrumConfig>,
        #[serde(default = "full_reflectance")]
        specular_reflectance: SpectrumConfig,
    },
    // Dielectrics.
    /// A smooth interface between two dielectrics (Mitsuba's `dielectric`): glass, water.
    /// `int_ior` default `"bk7"` (1.5046), `ext_ior` default `"air"` (1.000277), the exterior
    /// being the side the normal points to; `specular_reflectance` and `specular_transmittance`
    /// (default `Constant(1)`) scale the two lobes and should stay 1 for physical realism.
    ///
    /// ```ron
    /// Dielectric(int_ior: Glass("SF11"), ext_ior: Named("air"))
    /// ```
    Dielectric {
        #[serde(default = "bk7")]
        int_ior: IorConfig,
        #[serde(default = "air")]
        ext_ior: IorConfig,
        #[serde(default = "unit")]
        specular_reflectance: SpectrumConfig,
        #[serde(default = "unit")]
        specular_transmittance: SpectrumConfig,
    },
    /// A rough dielectric interface (Mitsuba's `roughdielectric`, Walter et al. 2007):
    /// `distribution` `Beckmann` (default) or `Ggx`; `alpha` (default 0.1) or both `alpha_u` and
    /// `alpha_v` (anisotropic); IORs and specular factors as `Dielectric`.
    ///
    /// ```ron
    /// RoughDielectric(distribution: Ggx, alpha: 0.05, int_ior: Glass("BK7"))
    /// ```
    RoughDielectric {
        #[serde(default)]
        distribution: Distribution,
        #[serde(default)]
        alpha: Option<FloatConfig>,
        #[serde(default)]
        alpha_u: Option<FloatConfig>,
        #[serde(default)]
        alpha_v: Option<FloatConfig>,
        #[serde(default = "bk7")]
        int_ior: IorConfig,
        #[serde(default = "air")]
        ext_ior: IorConfig,
        #[serde(default = "unit")]
        specular_reflectance: SpectrumConfig,
        #[serde(default = "unit")]
        specular_transmittance: SpectrumConfig,
    },
    /// An infinitely thin dielectric slab, e.g. a window pane modelled as one sheet
    /// (Mitsuba's `thindielectric`): specular reflection, undeflected transmission. Parameters
    /// as `Dielectric`.
    ///
    /// ```ron
    /// ThinDielectric(int_ior: Named("bk7"))
    /// ```
    ThinDielectric {
        #[serde(default = "bk7")]
        int_ior: IorConfig,
        #[serde(default = "air")]
        ext_ior: IorConfig,
        #[serde(default = "unit")]
        specular_reflectance: SpectrumConfig,
        #[serde(default = "unit")]
        specular_transmittance: SpectrumConfig,
    },
    // Plastics.
    /// A smooth dielectric coating over a diffuse base (Mitsuba's `plastic`).
    /// Defaults: diffuse_reflectance 0.5, specular_reflectance 1, int_ior `"polypropylene"`
    /// (1.49), ext_ior `"air"` (1.000277), nonlinear false. The indices are written as a
    /// dielectric's (a number or a name) but must not vary with wavelength, as in Mitsuba.
    Plastic {
        #[serde(default = "half_grey")]
        diffuse_reflectance: SpectrumConfig,
        #[serde(default = "one_spectrum")]
        specular_reflectance: SpectrumConfig,
        #[serde(default = "polypropylene")]
        int_ior: IorConfig,
        #[serde(default = "air")]
        ext_ior: IorConfig,
        #[serde(default)]
        nonlinear: bool,
    },
    /// A rough coating over a diffuse base (Mitsuba's `roughplastic`): isotropic `Beckmann`
    /// (default) or `Ggx` with roughness `alpha` (default 0.1); other defaults as `Plastic`.
    RoughPlastic {
        #[serde(default)]
        distribution: crate::bsdf::microfacet::Distribution,
        #[serde(default = "point_one")]
        alpha: f32,
        #[serde(default = "half_grey")]
        diffuse_reflectance: SpectrumConfig,
        #[serde(default = "one_spectrum")]
        specular_reflectance: SpectrumConfig,
        #[serde(default = "polypropylene")]
        int_ior: IorConfig,
        #[serde(default = "air")]
        ext_ior: IorConfig,
        #[serde(default)]
        nonlinear: bool,
    },
    /// The glTF 2.0 metallic-roughness BRDF (the specification's Appendix B, with
    /// KHR_materials_ior, _specular and thin-walled _transmission); what glTF materials become.
    /// Defaults are glTF's: base_color 1, metallic 1, roughness 1 (α = roughness², GGX),
    /// ior 1.5, specular 1, specular_color 1, transmission 0.
    ///
    /// ```ron
    /// Principled(base_color: Rgb(0.8, 0.1, 0.1), metallic: 0, roughness: 0.4)
    /// ```
    Principled {
        #[serde(default = "one_spectrum")]
        base_color: SpectrumConfig,
        #[serde(default = "one_float")]
        metallic: FloatConfig,
        #[serde(default = "one_float")]
        roughness: FloatConfig,
        #[serde(default = "gltf_ior")]
        ior: f32,
        #[serde(default = "one")]
        specular: f32,
        #[serde(default = "one_spectrum")]
        specular_color: SpectrumConfig,
        #[serde(default = "zero_float")]
        transmission: FloatConfig,
    },
}

fn one_float() -> FloatConfig {
    FloatConfig::Value(1.0)
}

fn zero_float() -> FloatConfig {
    FloatConfig::Value(0.0)
}

fn gltf_ior() -> f32 {
    1.5
}

fn one_spectrum() -> SpectrumConfig {
    SpectrumConfig::Constant(1.0)
}

fn polypropylene() -> IorConfig {
    IorConfig::named("polypropylene")
}

fn point_one() -> f32 {
    0.1
}

// Dielectrics.
fn bk7() -> IorConfig {
    IorConfig::named("bk7")
}

fn air() -> IorConfig {
    IorConfig::named("air")
}

fn unit() -> SpectrumConfig {
    SpectrumConfig::Constant(1.0)
}

fn half_grey() -> SpectrumConfig {
    SpectrumConfig::Constant(0.5)
}

fn full_reflectance() -> SpectrumConfig {
    SpectrumConfig::Constant(1.0)
}

fn half() -> FloatConfig {
    FloatConfig::Value(0.5)
}
