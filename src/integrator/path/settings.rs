//! The `path` integrator's settings (`PathSettings`, Mitsuba 3's names and defaults) and how it
//! treats lanes at a dispersive event (`Dispersion`).

use crate::integrator::caustics::CausticSettings;
use serde::{Deserialize, Serialize};

/// Settings of the `path` integrator, with Mitsuba 3's names and defaults.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PathSettings {
    /// Longest path in segments; −1 = unbounded.
    pub max_depth: i32,
    /// Depth from which Russian roulette may end paths.
    pub rr_depth: u32,
    /// Hide emitters seen directly by the camera.
    pub hide_emitters: bool,
    /// Opt-in firefly clamp: a camera sample's radiance is cut to at most this value
    /// (W m^-2 sr^-1 nm^-1) in every lane. Off by default: clamping removes energy, so it biases
    /// ground truth (darker highlights and caustics); prism counts the samples it clamped.
    pub clamp: Option<f32>,
    /// Opt-in caustic light tracing (`caustics: Some(())` for the defaults): caustics of an
    /// environment map's sun, of directional and of area lights, seen on surfaces the camera
    /// sees, are traced from the light instead of found by chance (`integrator::caustics`).
    /// Unbiased.
    pub caustics: Option<CausticSettings>,
}

impl Default for PathSettings {
    fn default() -> Self {
        Self {
            max_depth: -1,
            rr_depth: 5,
            hide_emitters: false,
            clamp: None,
            caustics: None,
        }
    }
}

/// How lanes are treated where sampling depends on wavelength (dispersion).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Dispersion {
    /// Keep every lane, weighted by spectral MIS over the lanes' sampling densities (Wilkie et
    /// al. 2014): lanes that could have produced the hero's direction keep contributing.
    #[default]
    SpectralMis,
    /// Drop the secondary lanes at the first dispersive event (pbrt-v4's approach); kept for
    /// comparison.
    TerminateSecondary,
}
