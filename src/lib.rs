//! prism: a spectral path tracer for physically based dataset generation.
//!
//! Modules stand on floors and import only downwards (docs/ARCHITECTURE.md, checked by
//! tests/layers.rs): base (math, spectrum, film, io) → engine (scene, shapes, BSDFs, emitters,
//! sensor) → render (integrator) → describe (config) → load → pipeline → dataset → cli.

pub mod accel;
pub mod bsdf;
pub mod camera;
pub mod cli;
pub mod config;
pub mod dataset;
pub mod emitter;
pub mod error;
pub mod export;
pub mod film;
pub mod filter;
pub mod integrator;
pub mod interaction;
pub mod io;
pub mod load;
pub mod math;
pub mod motion;
pub mod output;
pub mod pipeline;
pub mod probe;
pub mod ray;
pub mod resources;
pub mod sampler;
pub mod scene;
pub mod sensor;
pub mod shape;
pub mod spectrum;
pub mod texture;
