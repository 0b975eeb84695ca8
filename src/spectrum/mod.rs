//! Spectra: values at a path's wavelengths (`Spectrum<N>`), how those wavelengths are drawn,
//! and the continuous spectra (`Curve`) they are evaluated from.

pub mod blackbody;
pub mod color;
pub mod curve;
pub mod data;
pub mod gamut;
pub mod ior;
pub mod knots;
pub mod metals;
pub mod rgb2spec;
pub mod rgb2spec_fit;
pub mod sampled;
pub mod table;
pub mod wavelengths;

#[cfg(test)]
mod uplift_tests;

pub use curve::Curve;
pub use ior::{Ior, RelativeIor};
pub use sampled::Spectrum;
pub use wavelengths::{WavelengthSampler, WavelengthSampling, Wavelengths};
