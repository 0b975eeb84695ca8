//! How a scene writes an index of refraction (the schema only; `load::ior` resolves it into an
//! `Ior` checked over the render's wavelength range).

use super::spectrum::SpectrumConfig;
use serde::{Deserialize, Serialize};

/// An index of refraction in a scene file (the `int_ior` and `ext_ior` of dielectrics, and of
/// plastics, which take constant ones only).
///
/// ```ron
/// 1.5                                   // a number
/// "water"                               // one of Mitsuba 3's named values (same as Named)
/// Named("fused quartz")                 // Mitsuba 3's named values: vacuum, air, water, bk7, diamond, …
/// Glass("SF11")                         // a dispersive glass of spectra/glasses.txt (Sellmeier)
/// Sellmeier(b: (1.0396, 0.2318, 1.0105), c: (0.0060, 0.0200, 103.56))  // λ in µm, c in µm²
/// Cauchy(a: 1.5046, b: 0.0042)          // n = a + b/λ², λ in µm
/// Spectrum(Tabulated([(400, 1.53), (700, 1.51)]))  // n(λ) as a spectrum (nm, value)
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(
    untagged,
    expecting = "an index of refraction: a number (1.5), a name (\"water\"), Named(\"water\"), Glass(\"BK7\"), Sellmeier(b: (..), c: (..)), Cauchy(a: .., b: ..) or Spectrum(...)"
)]
pub enum IorConfig {
    Value(f32),
    Name(String),
    Form(IorForm),
}

/// The written-out forms of `IorConfig`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum IorForm {
    Value(f32),
    /// Mitsuba 3's named constants (case-insensitive).
    Named(String),
    /// A dispersive glass from `spectra/glasses.txt`.
    Glass(String),
    /// n² = 1 + Σ bᵢλ²/(λ² − cᵢ), λ in µm; three terms (unused ones 0).
    Sellmeier {
        b: [f32; 3],
        c: [f32; 3],
    },
    /// n = a + b/λ², λ in µm.
    Cauchy {
        a: f32,
        b: f32,
    },
    /// A tabulated or file spectrum of n over wavelength.
    Spectrum(SpectrumConfig),
}

impl IorConfig {
    pub fn named(name: &str) -> Self {
        IorConfig::Form(IorForm::Named(name.into()))
    }
}

/// The indices of refraction a scene may give (see `IorConfig::resolve`).
pub const MIN_IOR: f32 = 0.01;
pub const MAX_IOR: f32 = 100.0;
