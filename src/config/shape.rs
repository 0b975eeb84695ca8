//! Shapes in the scene file: their geometry, material, area emitter and transform.

use super::SpectrumConfig;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

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
    /// Keyframes of `to_world`, replacing it (`config::motion::AnimationConfig`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub animation: Option<super::AnimationConfig>,
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
    /// The instance id (`instance.ID`, the sidecar's `instance_id`); a glTF shape's parts get
    /// `id`, `id + 1`, …. Default: 1 + the index of the built shape. `prism dataset` sets it
    /// from the base scene, so an object keeps its id in frames where others are hidden.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub id: Option<u32>,
    /// A glTF shape's parts are one object: one instance id (`id`, else 1 + the index of its
    /// first built shape), the shape's name and label, one sidecar entry (its box the union of
    /// its parts'). `prism dataset` sets it for the glTF models of an asset folder.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub one_object: bool,
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
    /// replaces them all. The buffer and image URIs the file names must lie in its folder
    /// (below it) unless `allow_outside: true`.
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
        /// Lets buffer and image URIs leave the model's folder (`../shared.bin`, absolute
        /// paths, `file:` URIs); off, such a URI is refused, as a model from elsewhere could
        /// otherwise read any file the user can.
        #[serde(default)]
        allow_outside: bool,
        /// Which of the file's animations poses its nodes: a name, or an index as text
        /// (`"0"`); default the first. Its nodes are posed at the render's time, and move
        /// while the shutter is open (`config::motion`).
        #[serde(default)]
        animation: Option<String>,
    },
}

fn yes() -> bool {
    true
}

pub(super) fn one() -> f32 {
    1.0
}

/// `emitter: (radiance: Rgb(18.4, 14.0, 6.8))` on a shape: emits from its front side.
/// On a triangle mesh the radiance may be a texture over its uv (`load::emission`):
/// `emitter: (radiance: Scaled(5, Bitmap(path: "panel.exr", filter: Nearest)))`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AreaEmitterConfig {
    /// Radiance, W m⁻² sr⁻¹ nm⁻¹ (an `Rgb`, or each texel of a `Bitmap`, is uplifted as an
    /// illuminant, times D65).
    pub radiance: SpectrumConfig,
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
