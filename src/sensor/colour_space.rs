//! RGB output spaces: XYZ → linear RGB from each space's primaries and white point, with a
//! Bradford chromatic adaptation from D65 where the space's white differs (the ACES spaces).
//!
//! The rendered XYZ has no white point of its own; as in colour-science's `XYZ_to_RGB(...,
//! illuminant=D65, chromatic_adaptation_transform="Bradford")`, it is taken as seen under D65
//! adaptation, so a D65 white maps to R = G = B in every space.

use crate::spectrum::color::XYZ_TO_SRGB;
use crate::spectrum::gamut::{self, Gamut, ACES_WHITE, D65};
use glam::{DMat3, DVec3, Mat3};
use serde::{Deserialize, Serialize};

/// A linear RGB output space.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum RgbSpace {
    /// Linear sRGB / Rec. 709 (IEC 61966-2-1), D65: channels `R`, `G`, `B`.
    Srgb,
    /// ITU-R BT.2020, D65: `rec2020.R` …
    Rec2020,
    /// Display P3 (DCI-P3 primaries, D65): `p3.R` …
    DisplayP3,
    /// ACES2065-1 (AP0 primaries, ACES white, SMPTE ST 2065-1): `aces.R` …
    Aces2065,
    /// ACEScg (AP1 primaries, ACES white, S-2014-004): `acescg.R` …
    AcesCg,
}

pub const ALL_SPACES: [RgbSpace; 5] = [
    RgbSpace::Srgb,
    RgbSpace::Rec2020,
    RgbSpace::DisplayP3,
    RgbSpace::Aces2065,
    RgbSpace::AcesCg,
];

impl RgbSpace {
    /// The EXR layer prefix (`None`: the plain `R`, `G`, `B` channels of today's output).
    pub fn layer(self) -> Option<&'static str> {
        match self {
            RgbSpace::Srgb => None,
            RgbSpace::Rec2020 => Some("rec2020"),
            RgbSpace::DisplayP3 => Some("p3"),
            RgbSpace::Aces2065 => Some("aces"),
            RgbSpace::AcesCg => Some("acescg"),
        }
    }

    /// Primaries (R, G, B as CIE xy) and white point: the input spaces' (`spectrum::gamut`,
    /// one set of facts for both sides), and ACES2065-1's AP0, which is output only.
    fn primaries(self) -> ([[f64; 2]; 3], [f64; 2]) {
        match self {
            RgbSpace::Srgb => Gamut::Srgb.primaries(),
            RgbSpace::Rec2020 => Gamut::Rec2020.primaries(),
            RgbSpace::DisplayP3 => Gamut::DisplayP3.primaries(),
            RgbSpace::Aces2065 => (
                [[0.7347, 0.2653], [0.0, 1.0], [0.0001, -0.0770]],
                ACES_WHITE,
            ),
            RgbSpace::AcesCg => Gamut::AcesCg.primaries(),
        }
    }

    /// True where a Bradford adaptation from D65 is applied.
    pub fn adapted(self) -> bool {
        self.primaries().1 != D65
    }

    /// XYZ (D65-adapted) → this space's linear RGB. sRGB keeps the matrix prism has always
    /// used (so its pixels do not change; derived from the white (0.31271, 0.32902), it differs
    /// from one derived from (0.3127, 0.3290) by < 1e-3); the others are derived here.
    pub fn from_xyz(self) -> Mat3 {
        if self == RgbSpace::Srgb {
            return XYZ_TO_SRGB;
        }
        let (p, w) = self.primaries();
        let m = npm(p, w).inverse() * bradford(xy_to_xyz(D65), xy_to_xyz(w));
        m.as_mat3()
    }
}

fn xy_to_xyz(xy: [f64; 2]) -> DVec3 {
    DVec3::from_array(gamut::xy_to_xyz(xy))
}

fn mat(m: gamut::Mat) -> DMat3 {
    DMat3::from_cols_array_2d(&m).transpose()
}

/// The normalised primary matrix RGB → XYZ (SMPTE RP 177; `gamut::npm`).
fn npm(p: [[f64; 2]; 3], w: [f64; 2]) -> DMat3 {
    mat(gamut::npm(p, w))
}

/// Bradford adaptation of XYZ from white `src` to `dst` (`gamut::bradford`).
fn bradford(src: DVec3, dst: DVec3) -> DMat3 {
    mat(gamut::bradford(src.to_array(), dst.to_array()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every space maps the D65 white (0.3127, 0.3290) to R = G = B = 1: to 1e-5 (f32
    /// rounding) for the derived matrices; to 5e-4 for sRGB, whose matrix (kept from prism's
    /// first version) was derived from the white (0.31271, 0.32902).
    #[test]
    fn d65_white_is_neutral_in_every_space() {
        let w = xy_to_xyz(D65).as_vec3();
        for s in ALL_SPACES {
            let rgb = s.from_xyz() * w;
            let tol = if s == RgbSpace::Srgb { 5e-4 } else { 1e-5 };
            assert!(
                (rgb - glam::Vec3::ONE).abs().max_element() < tol,
                "{s:?}: {rgb}"
            );
        }
    }

    /// The sRGB matrix derived from the 4-digit white agrees with prism's to 1e-3 (the two
    /// white points differ in the fifth digit); a wrong primary would be off by > 0.01.
    #[test]
    fn srgb_matrix_from_primaries_matches_prisms() {
        let (p, w) = RgbSpace::Srgb.primaries();
        let m = npm(p, w).inverse().as_mat3();
        assert!(m.abs_diff_eq(XYZ_TO_SRGB, 1e-3), "{m}");
    }
}
