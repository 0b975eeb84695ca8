//! Edits of a scene config for one frame: which field of a material or emitter a variation
//! writes. (The dataset layer edits the config and builds the frame from it, so whatever a
//! scene can say — channels, AOVs, sensors — comes along unchanged.)

use crate::config::{EmitterConfig, MaterialConfig, SpectrumConfig, TransformOp};

/// The base reflectance of a material (`MaterialConfig::base_reflectance_mut`).
pub fn reflectance_slot(m: &mut MaterialConfig) -> Option<&mut SpectrumConfig> {
    m.base_reflectance_mut()
}

/// Sets the (isotropic) roughness α; false if the material has none.
pub fn set_roughness(m: &mut MaterialConfig, a: f32) -> bool {
    m.set_roughness(a)
}

/// Sets the interior index of refraction; false if the material has none.
pub fn set_ior(m: &mut MaterialConfig, n: f32) -> bool {
    m.set_int_ior(n)
}

/// The spectrum an unattached emitter emits; for an environment map, its `scale`.
pub use crate::config::Emission as EmitterSlot;

pub fn emitter_slot(e: &mut EmitterConfig) -> EmitterSlot<'_> {
    e.emission_mut()
}

/// A rotation about +y by `degrees`.
pub fn yaw(degrees: f32) -> TransformOp {
    TransformOp::Rotate {
        axis: [0.0, 1.0, 0.0],
        angle: degrees,
    }
}
