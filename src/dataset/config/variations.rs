//! The variations of a dataset config by what they vary: the camera, the lights, the
//! materials and the objects (each struct's docs give its RON). `config.rs` holds the config
//! itself, its outputs and sensor, the environment map, and the checks made at load.

use super::Range;
use serde::{Deserialize, Serialize};

/// `camera: (look_at: Shell(..) | Poses([..]), up: (0, 1, 0), fov: (30, 45), roll: 5,
/// keep_in_view: ["mug"], max_attempts: 100)`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraVariation {
    /// Where the camera stands and looks; left out, the scene's camera transform stays.
    #[serde(default)]
    pub look_at: Option<LookAtVariation>,
    /// Up vector of the look-at. Default +y.
    #[serde(default = "y_up")]
    pub up: [f32; 3],
    /// Field of view range in degrees (along the scene camera's `fov_axis`).
    #[serde(default)]
    pub fov: Option<Range>,
    /// Roll about the view axis, uniform in [−roll, roll] degrees. Default 0.
    #[serde(default)]
    pub roll: f32,
    /// Shapes whose bounding boxes must lie wholly inside the image; a pose that cuts one is
    /// drawn again, up to `max_attempts` times.
    #[serde(default)]
    pub keep_in_view: Vec<String>,
    /// Default 100.
    #[serde(default = "hundred")]
    pub max_attempts: u32,
    /// OpenCV's K drawn per frame (replaces `fov`; src/dataset/intrinsics.rs).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub intrinsics: Option<IntrinsicsRange>,
    /// OpenCV's distortion coefficients drawn per frame (src/dataset/intrinsics.rs).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub distortion: Option<DistortionRange>,
}

/// `intrinsics: (fx: (450, 550), fy: (450, 550), cx: (62, 66), cy: (46, 50))`: pixels, OpenCV's
/// convention (pixel centres at integers); `fy` left out: fy = fx (square pixels).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IntrinsicsRange {
    pub fx: Range,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fy: Option<Range>,
    pub cx: Range,
    pub cy: Range,
}

/// `distortion: (k1: (-0.2, 0), k2: (0, 0.05))`: OpenCV's coefficients, each a range (default
/// (0, 0)); every corner of the ranges' box must map the frame one-to-one.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct DistortionRange {
    pub k1: Range,
    pub k2: Range,
    pub p1: Range,
    pub p2: Range,
    pub k3: Range,
}

fn y_up() -> [f32; 3] {
    [0.0, 1.0, 0.0]
}

fn hundred() -> u32 {
    100
}

/// How the camera is posed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum LookAtVariation {
    /// From a point on a spherical shell around `target`: `radius`, `elevation` above the
    /// xz-plane (degrees, −90..90) and `azimuth` about +y from +z towards +x (degrees).
    Shell {
        target: [f32; 3],
        radius: Range,
        elevation: Range,
        azimuth: Range,
    },
    /// One of these poses, uniformly.
    Poses(Vec<Pose>),
}

/// `(origin: (0, 1, 4), target: (0, 0, 0))`
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Pose {
    pub origin: [f32; 3],
    pub target: [f32; 3],
}

/// `(target: "lamp", intensity: (5, 20), temperature: (2700, 6500))`. `target` is a shape's
/// `name` (its area light) or `"emitters[i]"` (the scene's i-th emitter). `intensity` scales
/// the light's spectrum; with `temperature` (K) the spectrum becomes a blackbody of unit
/// luminance (like `Named("D65")`) times `intensity`; with `illuminants: ["D65", "F2",
/// "LED-B1"]` (CIE names, as `Named` takes) it becomes one of them, drawn uniformly per frame,
/// times `intensity` (each is of unit luminance). `illuminant_files: ["spd/led_4000k.csv"]`
/// (relative to the dataset config; a spectrum table as `File(path: ..)` in a scene reads,
/// its first column, covering the scene's spectral range) are drawn beside the named ones,
/// uniformly over both lists, each scaled to unit luminance (src/dataset/illuminant_files.rs).
/// `temperature` excludes `illuminants` and `illuminant_files`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LightVariation {
    pub target: String,
    #[serde(default)]
    pub intensity: Option<Range>,
    #[serde(default)]
    pub temperature: Option<Range>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub illuminants: Vec<String>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub illuminant_files: Vec<String>,
}

/// `(target: "paint", reflectance: Library("colorchecker"), roughness: (0.05, 0.4), ior: (1.4, 1.7))`
/// on the scene's material `target`: its base reflectance (a diffuse's `reflectance`, a
/// plastic's `diffuse_reflectance`, a conductor's `specular_reflectance`), its roughness `alpha`
/// (rough conductors, dielectrics, plastics) and its interior IOR (dielectrics, plastics).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialVariation {
    pub target: String,
    #[serde(default)]
    pub reflectance: Option<ReflectanceSource>,
    #[serde(default)]
    pub roughness: Option<Range>,
    #[serde(default)]
    pub ior: Option<Range>,
}

/// Where reflectances come from.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum ReflectanceSource {
    /// A measured set in `spectra/reflectances/`: `"colorchecker"` (24 patches) or
    /// `"cie1995_tcs"` (14 test colour samples); one entry uniformly.
    Library(String),
    /// Only these entries of a set: `Patches("colorchecker", ["red", "green", "blue"])`.
    Patches(String, Vec<String>),
}

/// `(target: "paint", folder: "textures/wood")`: the material's base reflectance becomes a
/// `Bitmap` of one image of `folder` (relative to the dataset config), uniformly per frame
/// (src/dataset/textures.rs).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TextureVariation {
    pub target: String,
    pub folder: String,
}

/// `(shape: "mug", materials: ["paint", "glass"])`: the shape's material, uniformly from the list.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSwap {
    pub shape: String,
    pub materials: Vec<String>,
}

/// `objects: (subsets: [..], place: (..))`
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ObjectVariation {
    pub subsets: Vec<Subset>,
    pub place: Option<Placement>,
    /// Meshes and glTF models drawn per frame from a folder (src/dataset/asset_folder.rs).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub assets: Option<AssetFolder>,
}

/// `(folder: "assets", classes: "classes.csv", material: "plastic", size: 0.3, shown: (1, 3))`:
/// the OBJ, PLY and glTF (`.gltf`, `.glb`) files of `folder` (relative to the dataset config)
/// join the scene as shapes `asset:<file name>` of the class `classes` maps their file name to
/// (`pattern,class` lines), meshes wearing the scene's `material` and glTF models their own
/// (each model one object, whatever its parts), scaled so their box's longest side is `size`;
/// each frame shows a uniform number in `shown` of them, placed by `objects.place`
/// (src/dataset/asset_folder.rs).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AssetFolder {
    pub folder: String,
    pub classes: String,
    pub material: String,
    pub size: f32,
    pub shown: (u32, u32),
}

/// `(shapes: ["mug", "ball", "box"], shown: (1, 2))`: a uniform number in `shown` of these
/// shapes (a uniform subset of that size) appear; the others are left out of the frame.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Subset {
    pub shapes: Vec<String>,
    pub shown: (u32, u32),
}

/// `(support: "table", shapes: ["mug", "ball"], yaw: (0, 360), scale: (0.8, 1.2), gap: 0.02)`:
/// each shown shape is scaled about its base, turned about +y, and stood on the top face of the
/// `support` shape's bounding box (+y up) at a uniform position where its footprint (the circle
/// around its bounding box, scaled) stays on the support and clear of the others by `gap`;
/// drawn again up to `max_attempts` times per shape.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Placement {
    pub support: String,
    pub shapes: Vec<String>,
    #[serde(default)]
    pub yaw: Option<Range>,
    #[serde(default)]
    pub scale: Option<Range>,
    #[serde(default)]
    pub gap: f32,
    #[serde(default = "hundred")]
    pub max_attempts: u32,
}
