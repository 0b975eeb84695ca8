//! The loader: the one place that turns a scene description (RON `config`, glTF) into engine
//! objects — materials, emitters, geometry, instancing, objects, the camera, the sensor and its
//! raw read-out — with every check of a value against its range. It sits above `config` and the
//! engine; nothing in the engine or the integrator imports it (docs/ARCHITECTURE.md).

mod build;
mod camera;
mod check;
pub mod colour_space;
mod emission;
mod emitters;
pub mod extent;
pub mod flow;
mod geometry;
pub mod gltf;
pub mod instancing;
pub mod ior;
mod light_motion;
mod materials;
pub mod motion;
mod objects;
mod principled;
mod relight;
pub mod sensor;
mod settings;
pub mod spectrum;

/// The input-file record, as the loader's modules name it (`super::inputs`).
use crate::io::inputs;
/// The scene the loader builds (`super::Scene`).
use crate::scene::Scene;
pub use build::{build, load, load_str, Job, MAX_NM};
pub use geometry::transform;
pub use objects::{Object, Objects};
pub use relight::{geometry_key, relight};
pub use spectrum::{spectrum_ctx, Context as SpectrumContext, Role};
