//! Edits of a scene config for one frame: which field of a material or emitter a variation
//! writes. (The dataset layer edits the config and builds the frame from it, so whatever a
//! scene can say — channels, AOVs, sensors — comes along unchanged.)

use crate::config::{
    EmitterConfig, FloatConfig, IorConfig, MaterialConfig, SpectrumConfig, TransformOp,
};

/// The base reflectance of a material: a diffuse's `reflectance`, a plastic's
/// `diffuse_reflectance`, a conductor's `specular_reflectance`; inside `Twosided`, its front.
pub fn reflectance_slot(m: &mut MaterialConfig) -> Option<&mut SpectrumConfig> {
    match m {
        MaterialConfig::Diffuse { reflectance } => Some(reflectance),
        MaterialConfig::Plastic {
            diffuse_reflectance,
            ..
        }
        | MaterialConfig::RoughPlastic {
            diffuse_reflectance,
            ..
        } => Some(diffuse_reflectance),
        MaterialConfig::Conductor {
            specular_reflectance,
            ..
        }
        | MaterialConfig::RoughConductor {
            specular_reflectance,
            ..
        } => Some(specular_reflectance),
        MaterialConfig::Twosided { bsdf, .. } => reflectance_slot(bsdf),
        _ => None,
    }
}

/// Sets the (isotropic) roughness α; false if the material has none.
pub fn set_roughness(m: &mut MaterialConfig, a: f32) -> bool {
    match m {
        MaterialConfig::RoughConductor {
            alpha,
            alpha_u,
            alpha_v,
            ..
        }
        | MaterialConfig::RoughDielectric {
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
        MaterialConfig::RoughPlastic { alpha, .. } => {
            *alpha = a;
            true
        }
        MaterialConfig::Twosided { bsdf, .. } => set_roughness(bsdf, a),
        _ => false,
    }
}

/// Sets the interior index of refraction; false if the material has none.
pub fn set_ior(m: &mut MaterialConfig, n: f32) -> bool {
    match m {
        MaterialConfig::Dielectric { int_ior, .. }
        | MaterialConfig::RoughDielectric { int_ior, .. }
        | MaterialConfig::ThinDielectric { int_ior, .. }
        | MaterialConfig::Plastic { int_ior, .. }
        | MaterialConfig::RoughPlastic { int_ior, .. } => {
            *int_ior = IorConfig::Value(n);
            true
        }
        MaterialConfig::Twosided { bsdf, .. } => set_ior(bsdf, n),
        _ => false,
    }
}

/// The spectrum an unattached emitter emits; for an environment map, its `scale`.
pub enum EmitterSlot<'a> {
    Spectrum(&'a mut SpectrumConfig),
    Scale(&'a mut f32),
}

pub fn emitter_slot(e: &mut EmitterConfig) -> EmitterSlot<'_> {
    match e {
        EmitterConfig::Point { intensity, .. } | EmitterConfig::Spot { intensity, .. } => {
            EmitterSlot::Spectrum(intensity)
        }
        EmitterConfig::Constant { radiance } => EmitterSlot::Spectrum(radiance),
        EmitterConfig::Directional { irradiance, .. } => EmitterSlot::Spectrum(irradiance),
        EmitterConfig::Envmap { scale, .. } => EmitterSlot::Scale(scale),
    }
}

/// A rotation about +y by `degrees`.
pub fn yaw(degrees: f32) -> TransformOp {
    TransformOp::Rotate {
        axis: [0.0, 1.0, 0.0],
        angle: degrees,
    }
}
