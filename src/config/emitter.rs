//! Emitters in the scene file that are not attached to a shape (environment, point, spot,
//! directional lights).

use super::shape::one;
use super::{AnimationConfig, SpectrumConfig, TransformOp};
use serde::{Deserialize, Serialize};

/// Emitters not attached to a shape.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum EmitterConfig {
    /// `Point(position: (0, 2, 0), intensity: Named("A"))`, intensity in W sr⁻¹ nm⁻¹.
    /// `animation` (keys of a `to_world` carrying `position`, `config::motion`) moves it.
    Point {
        position: [f32; 3],
        intensity: SpectrumConfig,
        #[serde(default)]
        animation: Option<AnimationConfig>,
    },
    /// `Constant(radiance: Constant(1.0))`: radiance arriving from every direction.
    Constant { radiance: SpectrumConfig },
    /// A spot light (Mitsuba's `spot`) at the origin of `to_world`, emitting along its local +z:
    /// `Spot(intensity: Scaled(5, Named("D65")), cutoff_angle: 30, beam_width: 20,
    /// to_world: [LookAt(origin: (0, 3, 0), target: (0, 0, 0), up: (0, 0, 1))])`.
    /// Full `intensity` (W sr⁻¹ nm⁻¹, default `Named("D65")`) within `beam_width` degrees of the
    /// axis (default ¾ of `cutoff_angle`), falling linearly in angle to 0 at `cutoff_angle`
    /// (default 20, at most 90).
    Spot {
        #[serde(default = "d65")]
        intensity: SpectrumConfig,
        #[serde(default = "twenty")]
        cutoff_angle: f32,
        #[serde(default)]
        beam_width: Option<f32>,
        #[serde(default)]
        to_world: Vec<TransformOp>,
        /// Keyframes of `to_world`, replacing it (`config::motion::AnimationConfig`).
        #[serde(default)]
        animation: Option<AnimationConfig>,
    },
    /// A directional light at infinity (Mitsuba's `directional`):
    /// `Directional(irradiance: Scaled(3, Named("D65")), direction: (0, -1, -1))`.
    /// `irradiance` (W m⁻² nm⁻¹, default `Named("D65")`) is what a surface facing the light
    /// receives; `direction` is the way the light travels, or give `to_world` instead (the light
    /// then travels along its local +z, the default).
    Directional {
        #[serde(default = "d65")]
        irradiance: SpectrumConfig,
        #[serde(default)]
        direction: Option<[f32; 3]>,
        #[serde(default)]
        to_world: Vec<TransformOp>,
        /// Keyframes of `to_world`, replacing it; a `direction` is then turned by them.
        #[serde(default)]
        animation: Option<AnimationConfig>,
    },
    /// An environment map (Mitsuba's `envmap`): `Envmap(filename: "textures/sky.exr", scale: 2)`.
    /// A latitude-longitude image, twice as wide as high (OpenEXR, Radiance HDR or PNG; relative
    /// to the scene file) of linear RGB radiance, +y up, uplifted per texel as an illuminant;
    /// times `scale` (default 1); `to_world` may rotate it. `colour_space: "acescg"` (or
    /// "rec2020", "display_p3"; default "srgb") names the space of its linear RGB.
    Envmap {
        filename: String,
        #[serde(default = "one")]
        scale: f32,
        #[serde(default)]
        colour_space: Option<String>,
        #[serde(default)]
        to_world: Vec<TransformOp>,
        /// Keyframes of `to_world` (rotations only), replacing it.
        #[serde(default)]
        animation: Option<AnimationConfig>,
    },
}

fn d65() -> SpectrumConfig {
    SpectrumConfig::Named("D65".into())
}

fn twenty() -> f32 {
    20.0
}

/// What an emitter emits: a spectrum, or (an environment map) the scale of its image.
pub enum Emission<'a> {
    Spectrum(&'a mut SpectrumConfig),
    Scale(&'a mut f32),
}

/// Where an emitter's animation places it (`load::light_motion`): the field an instant's pose
/// is written to.
pub enum Placement<'a> {
    /// A point light's position (carried as a point).
    Position(&'a mut [f32; 3]),
    /// A directional light's `direction` (turned).
    Direction(&'a mut [f32; 3]),
    /// The light's `to_world` (replaced).
    ToWorld(&'a mut Vec<TransformOp>),
    /// An emitter that cannot move (`Constant`).
    Fixed,
}

impl EmitterConfig {
    /// The emitter's `animation` field, if its kind has one.
    pub fn animation_mut(&mut self) -> Option<&mut Option<AnimationConfig>> {
        match self {
            EmitterConfig::Point { animation, .. }
            | EmitterConfig::Spot { animation, .. }
            | EmitterConfig::Directional { animation, .. }
            | EmitterConfig::Envmap { animation, .. } => Some(animation),
            EmitterConfig::Constant { .. } => None,
        }
    }

    /// The emitter's animation, if it has one.
    pub fn animation(&self) -> Option<&AnimationConfig> {
        match self {
            EmitterConfig::Point { animation, .. }
            | EmitterConfig::Spot { animation, .. }
            | EmitterConfig::Directional { animation, .. }
            | EmitterConfig::Envmap { animation, .. } => animation.as_ref(),
            EmitterConfig::Constant { .. } => None,
        }
    }

    /// True if the emitter gives a `to_world` (which an animation replaces).
    pub fn has_to_world(&self) -> bool {
        match self {
            EmitterConfig::Spot { to_world, .. }
            | EmitterConfig::Directional { to_world, .. }
            | EmitterConfig::Envmap { to_world, .. } => !to_world.is_empty(),
            _ => false,
        }
    }

    /// Where an animation's pose at an instant is written.
    pub fn placement_mut(&mut self) -> Placement<'_> {
        match self {
            EmitterConfig::Point { position, .. } => Placement::Position(position),
            EmitterConfig::Directional {
                direction: Some(d), ..
            } => Placement::Direction(d),
            EmitterConfig::Spot { to_world, .. }
            | EmitterConfig::Directional { to_world, .. }
            | EmitterConfig::Envmap { to_world, .. } => Placement::ToWorld(to_world),
            EmitterConfig::Constant { .. } => Placement::Fixed,
        }
    }

    /// What the emitter emits, for a dataset's light variations.
    pub fn emission_mut(&mut self) -> Emission<'_> {
        match self {
            EmitterConfig::Point { intensity, .. } | EmitterConfig::Spot { intensity, .. } => {
                Emission::Spectrum(intensity)
            }
            EmitterConfig::Constant { radiance } => Emission::Spectrum(radiance),
            EmitterConfig::Directional { irradiance, .. } => Emission::Spectrum(irradiance),
            EmitterConfig::Envmap { scale, .. } => Emission::Scale(scale),
        }
    }

    /// The path of the image file an emitter reads itself (an environment map's), if any;
    /// the files of its spectrum are the spectrum's (`emission_mut`).
    pub fn file_mut(&mut self) -> Option<&mut String> {
        match self {
            EmitterConfig::Envmap { filename, .. } => Some(filename),
            _ => None,
        }
    }
}
