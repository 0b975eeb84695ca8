//! prism: a spectral path tracer for physically based dataset generation.
//!
//! Data flows one way: `config` (RON) → `scene` (render-ready) → `integrator` → `film` →
//! `output` files.

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
