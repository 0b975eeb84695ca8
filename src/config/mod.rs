//! The scene file format (RON). Every field has a default unless it says otherwise, so a scene
//! writes only what it needs; `scenes/README.md` documents each entry with an example.
//!
//! ```ron
//! (
//!     camera: (fov: 40, to_world: [LookAt(origin: (0, 1, 4), target: (0, 0, 0), up: (0, 1, 0))]),
//!     film: (width: 320, height: 240),
//!     materials: { "grey": Diffuse(reflectance: Constant(0.5)) },
//!     shapes: [(shape: Sphere(radius: 1), material: "grey")],
//!     emitters: [Constant(radiance: Named("D65"))],
//! )
//! ```

pub mod camera;
mod emitter;
mod float;
pub mod ior;
mod material;
pub mod motion;
mod parse;
pub mod sensor;
mod shape;
pub mod spectrum;
pub mod spp;
mod unique_keys;

use crate::accel::AccelKind;
use crate::camera::FovAxis;
use crate::filter::FilterConfig;
use crate::integrator::{Dispersion, PathSettings};
use crate::sampler::SamplerKind;
use crate::spectrum::WavelengthSampling;
pub use camera::{CameraModel, DistortionConfig, IntrinsicsConfig};
pub use emitter::{Emission, EmitterConfig, Placement};
pub(crate) use float::unit_scale;
pub use float::{FloatConfig, FloatTextureConfig};
pub use ior::{IorConfig, IorForm, MAX_IOR, MIN_IOR};
pub use material::{Field, MaterialConfig, Roughness};
pub use motion::{AnimationConfig, Interpolation, KeyConfig, ShutterConfig};
pub(crate) use parse::utf8;
pub use parse::{parse_file, parse_str};
use serde::{Deserialize, Serialize};
pub use shape::{AreaEmitterConfig, ShapeConfig, ShapeKind, TransformOp};
pub use spectrum::{SpectrumConfig, MAX_EMISSION};
pub use spp::{AdaptiveSpp, ErrorTarget, Spp};
use std::collections::BTreeMap;

/// A whole scene file.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SceneConfig {
    pub camera: CameraConfig,
    pub film: FilmConfig,
    pub sampler: SamplerConfig,
    /// The `path` integrator: `(max_depth: -1, rr_depth: 5, hide_emitters: false)`.
    pub integrator: PathSettings,
    pub spectral: SpectralConfig,
    pub outputs: OutputConfig,
    /// What the camera records: inline `(observer: ..., rgb: [...], bands: [...], camera: ...)`
    /// or `File("sensor.ron")` (relative to the scene file); replaces `outputs`
    /// (configs/README.md).
    pub sensor: Option<sensor::SensorField>,
    /// Further sensors on the same paths, each writing its channels prefixed `<name>.`:
    /// `sensors: [(name: "nikon", sensor: File("nikon.ron")), (name: "hsi", sensor: (bands:
    /// [Even(count: 60, range: (400, 1000))]))]` (src/sensor/multi.rs).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub sensors: Vec<sensor::NamedSensor>,
    /// Materials by name; shapes refer to them. `{ "white": Diffuse(reflectance: Rgb(0.8, 0.8, 0.8)) }`
    #[serde(deserialize_with = "unique_keys::materials")]
    pub materials: BTreeMap<String, MaterialConfig>,
    pub shapes: Vec<ShapeConfig>,
    /// Emitters that are not attached to a shape (area lights are given on their shape).
    pub emitters: Vec<EmitterConfig>,
    /// Acceleration structure: `Bvh` (default), `Embree` (needs prism built with the `embree`
    /// feature) or `BruteForce` (for testing).
    pub accel: AccelKind,
    /// `flatten: true` copies every mesh into world space, also one used by several shapes or
    /// glTF nodes, which by default is stored once and instanced (scenes/README.md).
    pub flatten: bool,
    /// AOV layers beside the colour channels: `aovs: ["depth", "normal", "instance"]`
    /// (`film::aov`; scenes/README.md lists them).
    pub aovs: Vec<String>,
    /// The sidecar's per-object 2D boxes and visible pixel counts even when no AOV layer traces
    /// the pixel-centre rays they come from: `boxes: true` (`prism render --boxes`). Default
    /// false: they are written whenever a geometry or id AOV runs, and otherwise cost nothing.
    pub boxes: bool,
    /// The class table: label `labels[i]` has id i + 1 (`label.ID`, the sidecar's `labels`).
    /// Default: the shapes' distinct labels, sorted. `prism dataset` sets it from the base
    /// scene, so a class keeps its id in frames where some of its shapes are hidden.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub labels: Vec<String>,
}

/// `camera: (fov: 39.3077, fov_axis: Smaller, near_clip: 0.001, to_world: [LookAt(...)])`
///
/// A perspective camera looking along its local +z, +y up, +x left (Mitsuba 3's convention).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CameraConfig {
    /// Field of view in degrees along `fov_axis`. Default 45.
    pub fov: f32,
    /// `X` (default), `Y`, `Diagonal`, `Smaller` or `Larger`.
    pub fov_axis: FovAxis,
    /// Distance of the near clip plane. Default 0.01.
    pub near_clip: f32,
    /// Distance of the far clip plane. Default 10000.
    pub far_clip: f32,
    /// Camera-to-world transform. Default identity (at the origin, looking along +z).
    pub to_world: Vec<TransformOp>,
    /// `Pinhole` (default), `ThinLens(aperture_radius, focus_distance)`, `Orthographic(width)`.
    pub model: CameraModel,
    /// OpenCV's K `(fx, fy, cx, cy)` (pixels, centres at integers) instead of `fov`.
    pub intrinsics: Option<IntrinsicsConfig>,
    /// OpenCV's `(k1, k2, p1, p2, k3)`, rendered exactly.
    pub distortion: Option<DistortionConfig>,
    /// Keyframes of `to_world` (`motion::AnimationConfig`), replacing it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub animation: Option<AnimationConfig>,
    /// When the film records (`motion::ShutterConfig`); default: the instant 0.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shutter: Option<ShutterConfig>,
    /// Frames per second: the flow layers follow each pixel's surface point to the frames
    /// 1/fps later and earlier (`flow_forward`, `flow_backward`; docs/sidecar.md, "Flow").
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fps: Option<f32>,
}

impl Default for CameraConfig {
    fn default() -> Self {
        Self {
            fov: 45.0,
            fov_axis: FovAxis::X,
            near_clip: 0.01,
            far_clip: 1e4,
            to_world: Vec::new(),
            model: CameraModel::Pinhole,
            intrinsics: None,
            distortion: None,
            animation: None,
            shutter: None,
            fps: None,
        }
    }
}

/// `film: (width: 256, height: 256, filter: Box())`
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct FilmConfig {
    /// Default 768 (Mitsuba's).
    pub width: u32,
    /// Default 576 (Mitsuba's).
    pub height: u32,
    /// `Box(radius: 0.5)` or `Gaussian(stddev: 0.5)` (default, Mitsuba's).
    pub filter: FilterConfig,
    /// The EXR's lossless compression: `Zip` (default), `Piz`, `Rle` or `None`.
    #[serde(skip_serializing_if = "ExrCompression::is_default")]
    pub exr_compression: ExrCompression,
}

/// Lossless EXR compression. Rendered floats carry noise in their low bits, which deflate
/// cannot squeeze: on a 47-band render `Zip` (deflate level 1, `output::exr_zip`) saves 2% of
/// the file for 0.06 s of CPU, `None` writes it in 0.01 s (docs/performance.md, "EXR
/// compression"). Masks, ids and depth compress well, so `Zip` stays the default.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
pub enum ExrCompression {
    /// Uncompressed: the fastest to write and read, the largest file.
    None,
    /// Run lengths: cheap, gains only on flat channels (masks, ids).
    Rle,
    /// Deflate on blocks of 16 rows (OpenEXR's ZIP), at deflate's fastest level.
    #[default]
    Zip,
    /// Wavelet and Huffman (OpenEXR's PIZ): smaller than `Zip` on noisy channels, faster to
    /// write, slower to read.
    Piz,
}

impl ExrCompression {
    /// `Zip`: left out of serialized configs, so a dataset's identity (a hash of its config)
    /// is what it was before the option existed.
    pub fn is_default(&self) -> bool {
        *self == ExrCompression::default()
    }
}

impl Default for FilmConfig {
    fn default() -> Self {
        Self {
            width: 768,
            height: 576,
            filter: FilterConfig::default(),
            exr_compression: ExrCompression::default(),
        }
    }
}

/// `sampler: (kind: Sobol, spp: 256, seed: 7)`
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SamplerConfig {
    /// `Sobol` (default: padded Owen-scrambled Sobol, at most 65536 spp, best with powers of
    /// two) or `Independent` (PCG32).
    pub kind: SamplerKind,
    /// Samples per pixel: a number (default 64) or `Adaptive(rel_error: 0.01, min: 16,
    /// max: 4096)` (`spp::AdaptiveSpp`).
    pub spp: Spp,
    /// Seed; the same seed gives the same image, bit for bit. Default 0.
    pub seed: u64,
}

impl Default for SamplerConfig {
    fn default() -> Self {
        Self {
            kind: SamplerKind::Sobol,
            spp: Spp::Fixed(64),
            seed: 0,
        }
    }
}

/// `spectral: (wavelengths: 8, range: (360, 830), sampling: Visible)`
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SpectralConfig {
    /// Wavelengths per path: 1, 2, 4, 8 (default) or 16. Eight cost ~10% more time per sample
    /// than four and cut colour noise enough to reach a given error sooner on every benchmark
    /// scene (docs/performance.md, "Error against time").
    pub wavelengths: usize,
    /// Wavelength range in nm. Default (360, 830), the CIE observer's range; any range the
    /// scene's spectra cover works (e.g. (300, 1100) for NIR bands).
    pub range: (f32, f32),
    /// `Visible` (default: importance-samples the eye's sensitivity, as Mitsuba 3) or `Uniform`
    /// (equal noise in every band: better for spectral outputs and ranges beyond the visible)
    /// or `Sensor` (from the sensor's curves, as Mitsuba's `specfilm`; src/sensor/sampling.rs).
    pub sampling: WavelengthSampling,
    /// Where sampling depends on wavelength (dispersive glass): `SpectralMis` (default: keep
    /// every lane, weighted by spectral MIS) or `TerminateSecondary` (keep only the hero, as
    /// pbrt-v4 does; for comparisons).
    pub dispersion: Dispersion,
}

impl Default for SpectralConfig {
    fn default() -> Self {
        Self {
            wavelengths: 8,
            range: (360.0, 830.0),
            sampling: WavelengthSampling::Visible,
            dispersion: Dispersion::SpectralMis,
        }
    }
}

/// `outputs: (rgb: true, xyz: true, bands: 47, band_range: (360, 830))`
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct OutputConfig {
    /// Linear sRGB channels R, G, B. Default true.
    pub rgb: bool,
    /// CIE 1931 X, Y, Z channels. Default true.
    pub xyz: bool,
    /// Number of spectral bands (channels `S0.<centre>nm`, each the band's mean radiance);
    /// 0 for none. Default: 10 nm bands over `band_range`.
    pub bands: Option<u32>,
    /// Range the bands cover, within the spectral range. Default: the spectral range.
    pub band_range: Option<(f32, f32)>,
}

impl Default for OutputConfig {
    fn default() -> Self {
        Self {
            rgb: true,
            xyz: true,
            bands: None,
            band_range: None,
        }
    }
}
