//! Time in the scene file: keyframed transforms (`animation`) and the camera's `shutter`.

use super::TransformOp;
use serde::{Deserialize, Serialize};

/// `animation: (interpolation: Linear, keys: [(time: 0, to_world: [...]), (time: 1, to_world: [...])])`
///
/// Keyframes of a camera's or shape's `to_world` (which the animation replaces). Each key's
/// transform is split into translation, rotation and scale, and those are interpolated:
/// `Linear` (default: straight lines, rotations by slerp), `Step` (each key held until the
/// next) or `Cubic` (a Catmull-Rom spline through the keys). Times are seconds, strictly
/// increasing; before the first key the first holds, after the last the last.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AnimationConfig {
    #[serde(default)]
    pub interpolation: Interpolation,
    pub keys: Vec<KeyConfig>,
}

/// One keyframe: `(time: 0.5, to_world: [Translate((1, 0, 0))])`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KeyConfig {
    pub time: f32,
    #[serde(default)]
    pub to_world: Vec<TransformOp>,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Interpolation {
    Step,
    #[default]
    Linear,
    Cubic,
}

/// `shutter: (open: 0, close: 0.02, readout: 0.00002)`
///
/// When the film records, in seconds. `open` = `close` renders the instant (as
/// `prism render --time T`); `open` < `close` blurs what moves in between. `readout` > 0 makes
/// it a rolling shutter: row y records from open + y·readout to close + y·readout, top row
/// first. Without a shutter the scene is rendered at time 0.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShutterConfig {
    pub open: f32,
    pub close: f32,
    #[serde(default)]
    pub readout: f32,
}
