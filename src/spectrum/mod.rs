//! Spectra: sampled values along a path's wavelengths, and the data they come from.
pub mod table;
