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
pub mod colour_space;
pub mod input_file;
pub mod ior;
mod parse;
pub mod sensor;
pub mod spectrum;
mod unique_keys;

use crate::accel::AccelKind;
use crate::bsdf::microfacet::Distribution;
use crate::camera::FovAxis;
use crate::filter::FilterConfig;
use crate::integrator::{Dispersion, PathSettings};
use crate::sampler::SamplerKind;
use crate::spectrum::WavelengthSampling;
use crate::texture::{TexFilter, Wrap};
pub use camera::{CameraModel, DistortionConfig, IntrinsicsConfig};
pub use ior::{IorConfig, IorForm, MAX_IOR, MIN_IOR};
pub use parse::{parse_file, parse_str};
use serde::{Deserialize, Serialize};
pub use spectrum::{Context as SpectrumContext, Role, SpectrumConfig, MAX_EMISSION};
use std::collections::BTreeMap;
use std::path::Path;

/// The context in which a spectrum field is resolved (for errors and relative paths).
pub fn spectrum_ctx<'a>(file: &'a Path, field: &'a str, range: (f32, f32)) -> SpectrumContext<'a> {
    SpectrumContext { file, field, range }
}

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
}

impl Default for FilmConfig {
    fn default() -> Self {
        Self {
            width: 768,
            height: 576,
            filter: FilterConfig::default(),
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
    /// Samples per pixel. Default 64.
    pub spp: u32,
    /// Seed; the same seed gives the same image, bit for bit. Default 0.
    pub seed: u64,
}

impl Default for SamplerConfig {
    fn default() -> Self {
        Self {
            kind: SamplerKind::Sobol,
            spp: 64,
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

/// A shape: `(shape: Rectangle, material: "white", to_world: [Scale((2, 2, 1))])`.
/// `material` defaults to a grey diffuse (0.5); `emitter: (radiance: ...)` makes it an area light.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShapeConfig {
    pub shape: ShapeKind,
    #[serde(default)]
    pub material: Option<String>,
    #[serde(default)]
    pub emitter: Option<AreaEmitterConfig>,
    #[serde(default)]
    pub to_world: Vec<TransformOp>,
    /// Turn the surface around: its front (emitting, reflecting) side becomes the other one.
    #[serde(default)]
    pub flip_normals: bool,
    /// The object's name: in the sidecar (unique; default `shape<i>`) and what a dataset config
    /// (`prism dataset`) refers to the shape by.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// A class label (the `label` AOV's id; shapes may share one).
    #[serde(default)]
    pub label: Option<String>,
}

/// The geometry of a shape, before `to_world`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum ShapeKind {
    /// [-1,1]² in the z = 0 plane, normal +z.
    Rectangle,
    /// [-1,1]³, normals outward.
    Cube,
    /// The unit disk in the z = 0 plane, normal +z.
    Disk,
    /// `Sphere(center: (0, 0, 0), radius: 1)`; `to_world` may move it and scale it uniformly.
    Sphere {
        #[serde(default)]
        center: [f32; 3],
        #[serde(default = "one")]
        radius: f32,
    },
    /// `Mesh(path: "meshes/bunny.ply")`: an OBJ or PLY file, relative to the scene file.
    Mesh { path: String },
    /// A glTF 2.0 file (`.gltf` or `.glb`, relative to the scene file): every mesh of its default
    /// scene, placed by its node tree and then by `to_world`, with its materials, its emissive
    /// materials as area lights and (unless `lights: false`) its KHR_lights_punctual lights.
    /// `materials` replaces glTF materials by name with the scene's own; the shape's `material`
    /// replaces them all.
    ///
    /// ```ron
    /// Gltf(path: "models/car.glb", materials: {"Paint": "red metal"}, lights: false)
    /// ```
    Gltf {
        path: String,
        #[serde(default)]
        materials: BTreeMap<String, String>,
        #[serde(default = "yes")]
        lights: bool,
    },
}

fn yes() -> bool {
    true
}

fn one() -> f32 {
    1.0
}

/// `emitter: (radiance: Rgb(18.4, 14.0, 6.8))` on a shape: emits from its front side.
/// On a triangle mesh the radiance may be a texture over its uv (`scene::emission`):
/// `emitter: (radiance: Scaled(5, Bitmap(path: "panel.exr", filter: Nearest)))`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AreaEmitterConfig {
    /// Radiance, W m⁻² sr⁻¹ nm⁻¹ (an `Rgb`, or each texel of a `Bitmap`, is uplifted as an
    /// illuminant, times D65).
    pub radiance: SpectrumConfig,
}

/// Emitters not attached to a shape.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum EmitterConfig {
    /// `Point(position: (0, 2, 0), intensity: Named("A"))`, intensity in W sr⁻¹ nm⁻¹.
    Point {
        position: [f32; 3],
        intensity: SpectrumConfig,
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
    },
}

fn d65() -> SpectrumConfig {
    SpectrumConfig::Named("D65".into())
}

fn twenty() -> f32 {
    20.0
}

/// One step of a transform; a list applies its steps in order (the first acts first).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum TransformOp {
    /// A 4×4 matrix in row-major order (as Mitsuba prints it).
    Matrix([[f32; 4]; 4]),
    Translate([f32; 3]),
    Scale([f32; 3]),
    /// `Rotate(axis: (0, 1, 0), angle: 90)`, angle in degrees, counter-clockwise about the axis.
    Rotate {
        axis: [f32; 3],
        angle: f32,
    },
    /// `LookAt(origin: (0, 0, 4), target: (0, 0, 0), up: (0, 1, 0))` (camera convention: +z towards the target).
    LookAt {
        origin: [f32; 3],
        target: [f32; 3],
        up: [f32; 3],
    },
}
