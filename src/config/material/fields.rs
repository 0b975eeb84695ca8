//! What each material's fields are, for the readers that edit or visit them without matching
//! on the kinds: a dataset's reflectance, roughness and IOR variations, and the rewrite of every
//! file path in an exported frame.

use super::MaterialConfig;
use crate::config::{FloatConfig, IorConfig, SpectrumConfig};

/// A field of a material that holds a spectrum, a scalar parameter or an index.
pub enum Field<'a> {
    Spectrum(&'a mut SpectrumConfig),
    Float(&'a mut FloatConfig),
    Ior(&'a mut IorConfig),
}

impl MaterialConfig {
    /// The kinds `base_reflectance_mut`, `set_roughness` and `set_int_ior` find a field in, for
    /// error hints.
    pub const WITH_BASE_REFLECTANCE: &'static str =
        "Diffuse, Plastic, RoughPlastic, Conductor and RoughConductor (also inside Twosided)";
    pub const WITH_ROUGHNESS: &'static str = "RoughConductor, RoughDielectric and RoughPlastic";
    pub const WITH_INT_IOR: &'static str = "the dielectrics and plastics";

    /// The base reflectance: a diffuse's `reflectance`, a plastic's `diffuse_reflectance`, a
    /// conductor's `specular_reflectance`; inside `Twosided`, its front's. None: it has none.
    pub fn base_reflectance_mut(&mut self) -> Option<&mut SpectrumConfig> {
        use MaterialConfig as M;
        match self {
            M::Diffuse { reflectance } => Some(reflectance),
            M::Plastic {
                diffuse_reflectance,
                ..
            }
            | M::RoughPlastic {
                diffuse_reflectance,
                ..
            } => Some(diffuse_reflectance),
            M::Conductor {
                specular_reflectance,
                ..
            }
            | M::RoughConductor {
                specular_reflectance,
                ..
            } => Some(specular_reflectance),
            M::Twosided { bsdf, .. } => bsdf.base_reflectance_mut(),
            _ => None,
        }
    }

    /// Sets the (isotropic) roughness α; false if the material has none.
    pub fn set_roughness(&mut self, a: f32) -> bool {
        use MaterialConfig as M;
        match self {
            M::RoughConductor {
                alpha,
                alpha_u,
                alpha_v,
                ..
            }
            | M::RoughDielectric {
                alpha,
                alpha_u,
                alpha_v,
                ..
            } => {
                *alpha = Some(FloatConfig::Value(a));
                *alpha_u = None;
                *alpha_v = None;
                true
            }
            M::RoughPlastic { alpha, .. } => {
                *alpha = a;
                true
            }
            M::Twosided { bsdf, .. } => bsdf.set_roughness(a),
            _ => false,
        }
    }

    /// Sets the interior index of refraction; false if the material has none.
    pub fn set_int_ior(&mut self, n: f32) -> bool {
        use MaterialConfig as M;
        match self {
            M::Dielectric { int_ior, .. }
            | M::RoughDielectric { int_ior, .. }
            | M::ThinDielectric { int_ior, .. }
            | M::Plastic { int_ior, .. }
            | M::RoughPlastic { int_ior, .. } => {
                *int_ior = IorConfig::Value(n);
                true
            }
            M::Twosided { bsdf, .. } => bsdf.set_int_ior(n),
            _ => false,
        }
    }

    /// Calls `f` on every spectrum, scalar and index field, nested materials' included.
    pub fn for_each_field(&mut self, f: &mut impl FnMut(Field)) {
        use Field::{Float, Ior, Spectrum};
        use MaterialConfig as M;
        match self {
            M::Diffuse { reflectance } => f(Spectrum(reflectance)),
            M::Twosided { bsdf, back } => {
                bsdf.for_each_field(f);
                back.iter_mut().for_each(|b| b.for_each_field(f));
            }
            M::Blend {
                weight,
                bsdf0,
                bsdf1,
            } => {
                f(Float(weight));
                bsdf0.for_each_field(f);
                bsdf1.for_each_field(f);
            }
            M::Mask { opacity, bsdf } => {
                f(Float(opacity));
                bsdf.for_each_field(f);
            }
            M::Conductor {
                eta,
                k,
                specular_reflectance,
                ..
            } => {
                [eta, k].into_iter().flatten().for_each(|s| f(Spectrum(s)));
                f(Spectrum(specular_reflectance));
            }
            M::RoughConductor {
                alpha,
                alpha_u,
                alpha_v,
                eta,
                k,
                specular_reflectance,
                ..
            } => {
                [alpha, alpha_u, alpha_v]
                    .into_iter()
                    .flatten()
                    .for_each(|a| f(Float(a)));
                [eta, k].into_iter().flatten().for_each(|s| f(Spectrum(s)));
                f(Spectrum(specular_reflectance));
            }
            M::Dielectric {
                int_ior,
                ext_ior,
                specular_reflectance: r,
                specular_transmittance: t,
            }
            | M::ThinDielectric {
                int_ior,
                ext_ior,
                specular_reflectance: r,
                specular_transmittance: t,
            } => {
                [int_ior, ext_ior].into_iter().for_each(|n| f(Ior(n)));
                [r, t].into_iter().for_each(|s| f(Spectrum(s)));
            }
            M::RoughDielectric {
                alpha,
                alpha_u,
                alpha_v,
                int_ior,
                ext_ior,
                specular_reflectance: r,
                specular_transmittance: t,
                ..
            } => {
                [alpha, alpha_u, alpha_v]
                    .into_iter()
                    .flatten()
                    .for_each(|a| f(Float(a)));
                [int_ior, ext_ior].into_iter().for_each(|n| f(Ior(n)));
                [r, t].into_iter().for_each(|s| f(Spectrum(s)));
            }
            M::Plastic {
                diffuse_reflectance: d,
                specular_reflectance: s,
                int_ior,
                ext_ior,
                ..
            }
            | M::RoughPlastic {
                diffuse_reflectance: d,
                specular_reflectance: s,
                int_ior,
                ext_ior,
                ..
            } => {
                [d, s].into_iter().for_each(|s| f(Spectrum(s)));
                [int_ior, ext_ior].into_iter().for_each(|n| f(Ior(n)));
            }
            M::Principled {
                base_color,
                metallic,
                roughness,
                specular_color,
                transmission,
                ..
            } => {
                [base_color, specular_color]
                    .into_iter()
                    .for_each(|s| f(Spectrum(s)));
                [metallic, roughness, transmission]
                    .into_iter()
                    .for_each(|a| f(Float(a)));
            }
        }
    }
}
