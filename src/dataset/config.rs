//! The dataset config (RON): a base scene, how many frames, a seed, what each frame writes, and
//! how named elements of the scene vary from frame to frame. `configs/README.md` documents it.
//! The variations of camera, lights, materials and objects are in `config/variations.rs`.
//!
//! ```ron
//! (
//!     scene: "tabletop.ron",              // relative to this file
//!     frames: 100,
//!     seed: 7,
//!     outputs: (preview: true, spp: 32),
//!     camera: (
//!         look_at: Shell(target: (0, 0.3, 0), radius: (2.5, 3.5), elevation: (15, 45), azimuth: (0, 360)),
//!         fov: (30, 45), roll: 3, keep_in_view: ["mug"],
//!     ),
//!     lights: [(target: "lamp", intensity: (5, 20), temperature: (2700, 6500))],
//!     materials: [(target: "paint", reflectance: Library("colorchecker"), roughness: (0.05, 0.4))],
//!     swaps: [(shape: "mug", materials: ["paint", "glass"])],
//!     sensor: (files: ["../sensors/nikon_d810.ron", "../sensors/cie1931.ron"], exposure: (-1, 1)),
//!     objects: (
//!         subsets: [(shapes: ["mug", "ball", "box"], shown: (1, 3))],
//!         place: (support: "table", shapes: ["mug", "ball", "box"], yaw: (0, 360), scale: (0.8, 1.2)),
//!     ),
//! )
//! ```

use crate::error::{Error, InputError};
use ron::extensions::Extensions;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

mod variations;
pub use variations::{
    AssetFolder, CameraVariation, DistortionRange, IntrinsicsRange, LightVariation,
    LookAtVariation, MaterialSwap, MaterialVariation, ObjectVariation, Placement, Pose,
    ReflectanceSource, Subset, TextureVariation,
};

/// A whole dataset config.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DatasetConfig {
    /// The base scene file, relative to the dataset config.
    pub scene: String,
    /// Number of frames (indices 0 .. frames); with `sequences`, their product (may be left out).
    #[serde(default)]
    pub frames: u32,
    /// Dataset seed: frame i's parameters and render seed derive from (seed, i) alone.
    #[serde(default)]
    pub seed: u64,
    #[serde(default)]
    pub outputs: FrameOutputs,
    #[serde(default)]
    pub camera: Option<CameraVariation>,
    /// Intensity and colour temperature of named lights.
    #[serde(default)]
    pub lights: Vec<LightVariation>,
    /// An environment map from a list, rotated about +y.
    #[serde(default)]
    pub envmap: Option<EnvmapVariation>,
    /// Parameters of named materials.
    #[serde(default)]
    pub materials: Vec<MaterialVariation>,
    /// A named shape's material chosen from a list.
    #[serde(default)]
    pub swaps: Vec<MaterialSwap>,
    /// A material's base reflectance as a bitmap drawn from a folder of images.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub textures: Vec<TextureVariation>,
    #[serde(default)]
    pub objects: ObjectVariation,
    /// The sensor chosen from a list, and an exposure in stops.
    #[serde(default)]
    pub sensor: Option<SensorVariation>,
    /// Named frame ranges for training: `splits: {"train": (0, 80), "val": (80, 90), "test":
    /// (90, 100)}`, each half-open `lo..hi`, disjoint, within the frames; `dataset.json` lists
    /// them.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub splits: BTreeMap<String, (u32, u32)>,
    /// Video (src/dataset/sequence.rs): `sequences` runs of `frames_per_sequence` frames at
    /// `fps`, each moved by `motion`. 0: frames are independent.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub sequences: u32,
    #[serde(default, skip_serializing_if = "is_zero")]
    pub frames_per_sequence: u32,
    #[serde(default, skip_serializing_if = "is_zero_f32")]
    pub fps: f32,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub motion: Option<super::sequence::MotionConfig>,
}

fn is_zero(n: &u32) -> bool {
    *n == 0
}

fn is_zero_f32(x: &f32) -> bool {
    *x == 0.0
}

/// `sensor: (files: ["../sensors/nikon_d810.ron", "../sensors/cie1931.ron"], exposure: (-1, 1))`:
/// each frame's sensor is a file from `files` (relative to the dataset config; sensor files as
/// `configs/sensors/` holds, replacing the scene's `sensor`/`outputs`), uniformly; left out, the
/// scene's sensor stays. `exposure` is a uniform number of stops e: every channel the sensor
/// writes (not the AOVs) is scaled by 2^e after rendering, as if every light were 2^e as bright.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SensorVariation {
    #[serde(default)]
    pub files: Option<Vec<String>>,
    #[serde(default)]
    pub exposure: Option<Range>,
}

/// `outputs: (preview: true, exposure: 0, spp: 16, resolution: (128, 96), aovs: ["depth"])`: what each frame writes besides its EXR and
/// JSON. The EXR carries every channel the base scene's `outputs` asks for.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct FrameOutputs {
    /// Also write an 8-bit sRGB preview `OUT/frames/NNNNNN.png`. Default false.
    pub preview: bool,
    /// Exposure of the preview in stops. Default 0.
    pub exposure: f32,
    /// Samples per pixel for every frame (overrides the scene's `sampler.spp`): a number or
    /// `Adaptive(rel_error: 0.01, min: 16, max: 4096)`, as in a scene.
    pub spp: Option<crate::config::Spp>,
    /// Image size (width, height) for every frame (overrides the scene's `film`).
    pub resolution: Option<(u32, u32)>,
    /// The AOV layers of every frame (overrides the base scene's `aovs`): `aovs: ["depth",
    /// "instance", "label"]`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub aovs: Option<Vec<String>>,
    /// Further sensors of every frame, on the same paths as its main sensor (overrides the base
    /// scene's `sensors`; files relative to the dataset config): `sensors: [(name: "nikon",
    /// sensor: File("../sensors/nikon_d810.ron"))]` writes `nikon.camera.R` … beside the
    /// main sensor's channels (src/sensor/multi.rs).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sensors: Option<Vec<crate::config::sensor::NamedSensor>>,
    /// Layers the contact sheet shows beside each frame's preview, in false colour:
    /// `sheet_layers: ["depth", "normal", "label"]` (src/dataset/sheet_layers.rs). Every tile
    /// carries its frame number.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub sheet_layers: Vec<String>,
}

/// A closed range `(lo, hi)` sampled uniformly; `lo == hi` is a constant.
pub type Range = (f32, f32);

/// `envmap: (target: "emitters[0]", files: ["sky1.exr", "sky2.exr"], rotate: true)`: the
/// `Envmap` emitter `target` takes a file from `files` (relative to the dataset config) and,
/// with `rotate` (default true), a uniform rotation about +y.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EnvmapVariation {
    pub target: String,
    #[serde(default)]
    pub files: Vec<String>,
    #[serde(default = "yes")]
    pub rotate: bool,
}

fn yes() -> bool {
    true
}

/// The most frames one dataset config may have (each is planned before the first renders).
pub const MAX_FRAMES: u32 = 1_000_000;

/// The most draws `max_attempts` may allow per frame.
pub const MAX_ATTEMPTS: u32 = 10_000;

impl DatasetConfig {
    /// Reads and parses a dataset config file (syntax errors with line and column).
    pub fn load(path: &Path) -> Result<DatasetConfig, Error> {
        use crate::io::input_file::{self, Kind};
        let bytes = input_file::read(path, Kind::Dataset)
            .map_err(|e| InputError::new(path, e).hint("check the path"))?;
        let text = String::from_utf8(bytes).map_err(|e| {
            InputError::new(
                path,
                format!(
                    "the dataset config is not UTF-8 text (byte {})",
                    e.utf8_error().valid_up_to()
                ),
            )
            .hint("save the config as UTF-8 text")
        })?;
        let mut config = Self::parse(&text, path)?;
        super::sequence::check(&mut config, path)?;
        // Every frame is planned (and listed) before the first renders: bound the list.
        if config.frames == 0 || config.frames > MAX_FRAMES {
            return Err(InputError::new(
                path,
                format!("frames: {} must lie in 1..={MAX_FRAMES}", config.frames),
            )
            .field("frames")
            .hint("split a larger dataset into several configs with different seeds")
            .into());
        }
        // Draws per frame: a keep-in-view or a placement that cannot succeed tries this often
        // for every frame before the first renders.
        let attempts = [
            (
                "camera.max_attempts",
                config.camera.as_ref().map(|c| c.max_attempts),
            ),
            (
                "objects.place.max_attempts",
                config.objects.place.as_ref().map(|p| p.max_attempts),
            ),
        ];
        for (field, n) in attempts {
            if let Some(n) = n.filter(|&n| n == 0 || n > MAX_ATTEMPTS) {
                return Err(InputError::new(path, format!("{n} must lie in 1..={MAX_ATTEMPTS}"))
                    .field(field)
                    .hint("a draw that fails 100 times (the default) rarely succeeds later: relax keep_in_view, the ranges or the placement instead")
                    .into());
            }
        }
        // A shape placed twice would be moved twice: the position recorded is not where it is.
        if let Some(p) = &config.objects.place {
            for (i, n) in p.shapes.iter().enumerate() {
                if p.shapes[..i].contains(n) {
                    return Err(InputError::new(path, format!("\"{n}\" is listed twice"))
                        .field(format!("objects.place.shapes[{i}]"))
                        .hint("list each shape to place once")
                        .into());
                }
            }
        }
        Ok(config)
    }

    pub fn parse(text: &str, file: &Path) -> Result<DatasetConfig, InputError> {
        let opts = ron::Options::default().with_default_extension(Extensions::IMPLICIT_SOME);
        opts.from_str::<DatasetConfig>(text).map_err(|e| {
            InputError::new(file, e.code.to_string())
                .at(e.span.start.line, e.span.start.col)
                .hint("configs/README.md lists every field of a dataset config")
        })
    }
}
