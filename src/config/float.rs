//! A material's scalar parameters in the scene file: a number or a texture.

use crate::texture::{TexFilter, Wrap};
use serde::{Deserialize, Serialize};

/// A scalar parameter: a number, or a texture (`Checkerboard(...)`, `Bitmap(...)`, whose
/// luminance is used).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(
    untagged,
    expecting = "a number, or a texture: Checkerboard(value0: .., value1: ..) or Bitmap(path: \"...\")"
)]
pub enum FloatConfig {
    Value(f32),
    Texture(FloatTextureConfig),
}

/// Textured scalar parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum FloatTextureConfig {
    /// `value0` where frac(u) and frac(v) fall in the same half, else `value1` (defaults 0.4, 0.2).
    Checkerboard {
        #[serde(default = "point_four")]
        value0: f32,
        #[serde(default = "point_two")]
        value1: f32,
        #[serde(default = "unit_scale")]
        uv_scale: (f32, f32),
        #[serde(default)]
        uv_offset: (f32, f32),
    },
    /// The luminance of an image (PNG, JPEG, EXR or HDR), relative to the scene file.
    Bitmap {
        path: String,
        #[serde(default)]
        filter: TexFilter,
        #[serde(default)]
        wrap: Wrap,
        #[serde(default)]
        raw: bool,
        #[serde(default = "unit_scale")]
        uv_scale: (f32, f32),
        #[serde(default)]
        uv_offset: (f32, f32),
    },
}

fn point_four() -> f32 {
    0.4
}

fn point_two() -> f32 {
    0.2
}

pub(crate) fn unit_scale() -> (f32, f32) {
    (1.0, 1.0)
}
