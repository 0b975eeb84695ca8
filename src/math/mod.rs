//! Small math pieces the renderer shares: frames, sampling warps, random numbers, transforms,
//! and floating-point error bounds.
pub mod chi2;
pub mod distribution;
pub mod float;
pub mod frame;
pub mod portable;
pub mod quadrature;
pub mod rng;
pub mod rotation;
pub mod sampling;
pub mod transform;
pub mod turns;

pub use frame::Frame;
pub use transform::Transform;
