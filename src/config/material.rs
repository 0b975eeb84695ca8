//! Materials in the scene file (Mitsuba 3's BSDF names and parameters); `load::materials` turns
//! them into `bsdf::Material`s. Each material answers for its fields in `fields` (`Field`), so
//! a dataset variation or a path rewrite never matches on the material kinds.

mod fields;

pub use fields::{Field, Roughness};

use super::shape::one;
use super::{FloatConfig, IorConfig, SpectrumConfig};
use crate::bsdf::for_each_bsdf;
use crate::bsdf::microfacet::Distribution;
use serde::{Deserialize, Serialize};

// The BSDF list's names for the scene file's kinds (bsdf/mod.rs writes each BSDF's schema).
type Spectrum = SpectrumConfig;
type Float = FloatConfig;
type Ior = IorConfig;

/// Generates `MaterialConfig` from the BSDF list: each BSDF's variant with the doc, fields and
/// serde attributes the list gives it, and the tree's inner nodes written out here. The list's
/// first BSDF (`Diffuse`) stays ahead of the inner nodes, where it always was: an unknown
/// material's error ("expected one of …") names the variants in this order.
macro_rules! material_config {
    (
        $(#[$doc0:meta])* $V0:ident($L0:ty, $P0:ty) {$($f0:tt)*} [$($r0:tt)*],
        $($(#[$doc:meta])* $V:ident($L:ty, $P:ty) {$($f:tt)*} [$($r:tt)*]),* $(,)?
    ) => {
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
            $(#[$doc0])*
            $V0 { $($f0)* },
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
            $(
                $(#[$doc])*
                $V { $($f)* },
            )*
        }
    };
}

for_each_bsdf!(material_config);

// The default values the list's serde attributes name.
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
