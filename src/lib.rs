//! prism: a spectral path tracer for physically based dataset generation.
pub mod spectrum;
