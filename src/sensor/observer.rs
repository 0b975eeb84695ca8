//! The standard observers whose colour-matching functions give the X, Y, Z channels.

use crate::spectrum::color::{cie1931, cie1964, Cmf};
use serde::{Deserialize, Serialize};

/// `observer: Cie1931` (default) or `Cie1964`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Observer {
    /// CIE 1931 2° (`spectra/cmf/CIE1931_2deg.txt`).
    #[default]
    Cie1931,
    /// CIE 1964 10° (`spectra/cmf/CIE1964_10deg.txt`).
    Cie1964,
}

impl Observer {
    pub fn cmf(self) -> &'static Cmf {
        match self {
            Observer::Cie1931 => cie1931(),
            Observer::Cie1964 => cie1964(),
        }
    }

    pub fn label(self) -> &'static str {
        match self {
            Observer::Cie1931 => "CIE 1931 2 degree",
            Observer::Cie1964 => "CIE 1964 10 degree",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫ȳ₁₀ over 360–830 nm at 1 nm is 116.6 (the CIE 1964 table's sum, as colour-science's
    /// `sd_to_XYZ` normalisation uses); the 1931 value is 106.857.
    #[test]
    fn y_integrals() {
        assert!((Observer::Cie1931.cmf().y_integral - 106.857).abs() < 0.01);
        let y10 = Observer::Cie1964.cmf().y_integral;
        assert!((y10 - 116.6).abs() < 0.1, "{y10}");
    }
}
