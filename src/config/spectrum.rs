//! How a scene writes a spectrum (the schema only; `load::spectrum` resolves it into a `Curve`
//! or a texture with the checks of what the spectrum means).

use crate::texture::{TexFilter, Wrap};
use serde::{Deserialize, Serialize};

/// A spectrum in a scene file.
///
/// ```ron
/// Constant(0.5)
/// Rgb(0.8, 0.2, 0.1)                      // linear sRGB, uplifted (Jakob & Hanika 2019)
/// ColourSpace("acescg", Rgb(0.8, 0.2, 0.1))   // linear RGB of another space: "srgb",
///                                         // "rec2020", "display_p3", "acescg" (its own table)
/// ColourSpace("rec2020", Bitmap(path: "wood.exr"))  // a texture in that space
/// Tabulated([(400, 0.1), (550, 0.6), (700, 0.3)])   // (nm, value), linear in between
/// File(path: "spectra/paint.txt")         // a table file, relative to the scene file
/// File(path: "data/leaf.txt", column: "reflectance")
/// Named("D65")                            // a CIE illuminant, unit luminance
/// Blackbody(5500)                         // Planck's law in W m⁻² sr⁻¹ nm⁻¹, temperature in K
/// Scaled(10, Named("A"))                  // any spectrum times a factor
/// Gaussian(centre: 850, fwhm: 40)         // peak 1 at `centre` nm (an LED line, a filter)
/// Checkerboard(color0: Constant(0.8), color1: Rgb(0.1, 0.1, 0.5), uv_scale: (8, 8))  // a texture
/// Bitmap(path: "wood.png", filter: Bilinear, wrap: Repeat, raw: false, uv_scale: (1, 1))  // a texture
/// ```
///
/// Textures are allowed where a material parameter varies over a surface (reflectances), and a
/// `Bitmap` as a shape's area-emitter radiance (`load::emission`); other emitters and indices
/// of refraction take plain spectra.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum SpectrumConfig {
    Constant(f32),
    Rgb(f32, f32, f32),
    /// An `Rgb` value or a `Bitmap` texture whose linear RGB is in the named space (see
    /// `spectrum::gamut`), uplifted with that space's table.
    ColourSpace(String, Box<SpectrumConfig>),
    Tabulated(Vec<(f32, f32)>),
    File {
        path: String,
        #[serde(default)]
        column: Option<String>,
    },
    Named(String),
    Blackbody(f32),
    Scaled(f32, Box<SpectrumConfig>),
    /// exp(−4 ln 2 (λ − centre)² / fwhm²): peak 1, full width `fwhm` nm at half maximum.
    Gaussian {
        centre: f32,
        fwhm: f32,
    },
    /// Mitsuba's `checkerboard` (defaults 0.4 and 0.2).
    Checkerboard {
        #[serde(default = "point_four")]
        color0: Box<SpectrumConfig>,
        #[serde(default = "point_two")]
        color1: Box<SpectrumConfig>,
        #[serde(default = "super::unit_scale")]
        uv_scale: (f32, f32),
        #[serde(default)]
        uv_offset: (f32, f32),
    },
    /// Mitsuba's `bitmap`: an RGB image uplifted texel by texel at load.
    Bitmap {
        path: String,
        #[serde(default)]
        filter: TexFilter,
        #[serde(default)]
        wrap: Wrap,
        #[serde(default)]
        raw: bool,
        #[serde(default = "super::unit_scale")]
        uv_scale: (f32, f32),
        #[serde(default)]
        uv_offset: (f32, f32),
    },
}

fn point_four() -> Box<SpectrumConfig> {
    Box::new(SpectrumConfig::Constant(0.4))
}

fn point_two() -> Box<SpectrumConfig> {
    Box::new(SpectrumConfig::Constant(0.2))
}

/// The largest emitted radiance, intensity or irradiance (or envmap texel times its scale)
/// prism accepts: 16 orders of magnitude above the sun's spectral radiance, and 18 below
/// f32's largest value (3.4e38), a margin for what a path multiplies it by.
pub const MAX_EMISSION: f32 = 1e20;
