//! The RGB spaces prism accepts as *input* (reflectance and emitter values, textures, envmaps):
//! linear sRGB, Rec. 2020, Display P3 and ACEScg, each uplifted with a sigmoid table fitted for
//! its gamut (`build.rs`, `rgb2spec_fit.rs`). Also the primaries, white points and the
//! primaries-to-XYZ algebra that the output spaces (`sensor::colour_space`) use, so both sides
//! share one set of facts.
//!
//! White point: prism's XYZ is D65-adapted (as its output spaces and colour-science's
//! `RGB_to_XYZ(rgb, space, illuminant=D65, chromatic_adaptation_transform="Bradford")`). An
//! input colour therefore means the XYZ that conversion gives, and every table is fitted under
//! D65: for ACEScg, whose own white is the ACES white (≈ D60), the matrix includes the Bradford
//! adaptation ACES white → D65. So in every space RGB (1, 1, 1) is the flat reflectance 1 and,
//! for an emitter, D65: an ACEScg white light renders neutral in prism's own ACEScg output, and
//! a D65-lit ACEScg patch reads back its value there. (pbrt-v4 fits its ACES table under a D60
//! spectrum instead and emits RGB × D60; in prism's D65-adapted output that light would render
//! warm, and a patch would not read back its value in any lighting.)
//!
//! Std-only: `build.rs` includes this file to fit the tables.

/// An input RGB space.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Gamut {
    /// Linear sRGB / Rec. 709, D65 (the default; `Rgb(r, g, b)`).
    Srgb,
    /// ITU-R BT.2020, D65.
    Rec2020,
    /// Display P3 (DCI-P3 primaries, D65 white).
    DisplayP3,
    /// ACEScg (AP1 primaries, ACES white; Academy S-2014-004), read D65-adapted (Bradford).
    AcesCg,
}

/// Every input space, in the order of their tables.
pub const ALL_GAMUTS: [Gamut; 4] = [Gamut::Srgb, Gamut::Rec2020, Gamut::DisplayP3, Gamut::AcesCg];

/// CIE xy of D65 as the colour spaces define it (4 digits, as in IEC 61966-2-1 and BT.2020).
pub const D65: [f64; 2] = [0.3127, 0.3290];
/// The ACES white (SMPTE ST 2065-1).
pub const ACES_WHITE: [f64; 2] = [0.32168, 0.33767];

/// Linear sRGB -> XYZ (D65 white): the matrix prism has always used (derived from the white
/// (0.31271, 0.32902)); kept so the sRGB table and every sRGB render stay as they were.
pub const SRGB_TO_XYZ: [[f64; 3]; 3] = [
    [0.4124564, 0.3575761, 0.1804375],
    [0.2126729, 0.7151522, 0.0721750],
    [0.0193339, 0.1191920, 0.9503041],
];

/// Bradford cone response (Lam 1985, as in ICC and colour-science).
const BRADFORD: [[f64; 3]; 3] = [
    [0.8951, 0.2664, -0.1614],
    [-0.7502, 1.7135, 0.0367],
    [0.0389, -0.0685, 1.0296],
];

pub type Mat = [[f64; 3]; 3];

impl Gamut {
    /// The name a scene writes (`ColourSpace("acescg", …)`, `colour_space: "acescg"`).
    pub fn name(self) -> &'static str {
        match self {
            Gamut::Srgb => "srgb",
            Gamut::Rec2020 => "rec2020",
            Gamut::DisplayP3 => "display_p3",
            Gamut::AcesCg => "acescg",
        }
    }

    /// By name, in any case; `None` for an unknown one (callers list [`gamut_names`]).
    pub fn from_name(name: &str) -> Option<Gamut> {
        ALL_GAMUTS
            .into_iter()
            .find(|g| g.name().eq_ignore_ascii_case(name))
    }

    /// Primaries (R, G, B as CIE xy) and white point, as the standards give them.
    pub fn primaries(self) -> ([[f64; 2]; 3], [f64; 2]) {
        match self {
            Gamut::Srgb => ([[0.64, 0.33], [0.30, 0.60], [0.15, 0.06]], D65),
            Gamut::Rec2020 => ([[0.708, 0.292], [0.170, 0.797], [0.131, 0.046]], D65),
            Gamut::DisplayP3 => ([[0.680, 0.320], [0.265, 0.690], [0.150, 0.060]], D65),
            Gamut::AcesCg => ([[0.713, 0.293], [0.165, 0.830], [0.128, 0.044]], ACES_WHITE),
        }
    }

    /// Linear RGB -> D65-adapted XYZ (RGB (1, 1, 1) gives the D65 white with Y = 1).
    pub fn to_xyz(self) -> Mat {
        if self == Gamut::Srgb {
            return SRGB_TO_XYZ;
        }
        let (p, w) = self.primaries();
        mat_mul(&bradford(xy_to_xyz(w), xy_to_xyz(D65)), &npm(p, w))
    }

    /// The table file `build.rs` writes and `rgb2spec.rs` embeds.
    pub fn table_file(self) -> &'static str {
        match self {
            Gamut::Srgb => "srgb_sigmoid.bin",
            Gamut::Rec2020 => "rec2020_sigmoid.bin",
            Gamut::DisplayP3 => "display_p3_sigmoid.bin",
            Gamut::AcesCg => "acescg_sigmoid.bin",
        }
    }
}

/// The names of every input space, for error messages.
pub fn gamut_names() -> Vec<&'static str> {
    ALL_GAMUTS.iter().map(|g| g.name()).collect()
}

/// XYZ (Y = 1) of the chromaticity `xy`.
pub fn xy_to_xyz([x, y]: [f64; 2]) -> [f64; 3] {
    [x / y, 1.0, (1.0 - x - y) / y]
}

/// The normalised primary matrix RGB → XYZ (SMPTE RP 177): columns are the primaries' XYZ,
/// scaled so RGB = (1, 1, 1) gives the white with Y = 1.
pub fn npm(p: [[f64; 2]; 3], w: [f64; 2]) -> Mat {
    let cols = p.map(xy_to_xyz);
    let m: Mat = [0, 1, 2].map(|r| [cols[0][r], cols[1][r], cols[2][r]]);
    let s = mat_vec(
        &inverse(&m).expect("primaries are independent"),
        xy_to_xyz(w),
    );
    [0, 1, 2].map(|r| [0, 1, 2].map(|c| m[r][c] * s[c]))
}

/// Bradford (von Kries in Bradford cone space) adaptation of XYZ from white `src` to `dst`.
pub fn bradford(src: [f64; 3], dst: [f64; 3]) -> Mat {
    if src == dst {
        return [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    }
    let (s, d) = (mat_vec(&BRADFORD, src), mat_vec(&BRADFORD, dst));
    let diag: Mat = [0, 1, 2].map(|r| [0, 1, 2].map(|c| if r == c { d[r] / s[r] } else { 0.0 }));
    let inv = inverse(&BRADFORD).expect("Bradford is invertible");
    mat_mul(&inv, &mat_mul(&diag, &BRADFORD))
}

/// `m · v`.
pub fn mat_vec(m: &Mat, v: [f64; 3]) -> [f64; 3] {
    m.map(|row| row[0] * v[0] + row[1] * v[1] + row[2] * v[2])
}

/// `a · b`.
pub fn mat_mul(a: &Mat, b: &Mat) -> Mat {
    [0, 1, 2].map(|r| [0, 1, 2].map(|c| (0..3).map(|k| a[r][k] * b[k][c]).sum()))
}

/// The inverse by cofactors; `None` if singular.
pub fn inverse(m: &Mat) -> Option<Mat> {
    let cof = |r: usize, c: usize| {
        let (r1, r2) = ((r + 1) % 3, (r + 2) % 3);
        let (c1, c2) = ((c + 1) % 3, (c + 2) % 3);
        m[r1][c1] * m[r2][c2] - m[r1][c2] * m[r2][c1]
    };
    let det = m[0][0] * cof(0, 0) + m[0][1] * cof(0, 1) + m[0][2] * cof(0, 2);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    // inverse[r][c] = cofactor(c, r) / det (the cyclic indices carry the signs).
    Some([0, 1, 2].map(|r| [0, 1, 2].map(|c| cof(c, r) / det)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// RGB (1, 1, 1) is the D65 white in every space (the sRGB matrix's own white differs in
    /// the fifth digit, hence 5e-4 there; 1e-12 for the derived ones).
    #[test]
    fn white_is_d65_in_every_space() {
        for g in ALL_GAMUTS {
            let w = mat_vec(&g.to_xyz(), [1.0; 3]);
            let d65 = xy_to_xyz(D65);
            let tol = if g == Gamut::Srgb { 5e-4 } else { 1e-12 };
            for k in 0..3 {
                assert!((w[k] - d65[k]).abs() < tol, "{g:?}: {w:?}");
            }
        }
    }

    /// colour-science 0.4.7: `RGB_COLOURSPACES['ACEScg'].matrix_RGB_to_XYZ`, and the
    /// BT.2020 matrix of ITU-R BT.2087 (both published to 4+ digits).
    #[test]
    fn matrices_match_published_ones() {
        let (p, w) = Gamut::AcesCg.primaries();
        let ap1 = npm(p, w);
        let published = [
            [0.6624541811, 0.1340042065, 0.1561876870],
            [0.2722287168, 0.6740817658, 0.0536895174],
            [-0.0055746495, 0.0040607335, 1.0103391003],
        ];
        let rec2020 = [
            [0.6370, 0.1446, 0.1689],
            [0.2627, 0.6780, 0.0593],
            [0.0000, 0.0281, 1.0610],
        ];
        let m = Gamut::Rec2020.to_xyz();
        for r in 0..3 {
            for c in 0..3 {
                assert!((ap1[r][c] - published[r][c]).abs() < 1e-6, "AP1 {r}{c}");
                assert!((m[r][c] - rec2020[r][c]).abs() < 1e-4, "BT.2020 {r}{c}");
            }
        }
    }

    #[test]
    fn names_round_trip_and_inverse_works() {
        for g in ALL_GAMUTS {
            assert_eq!(Gamut::from_name(&g.name().to_uppercase()), Some(g));
            let m = g.to_xyz();
            let i = mat_mul(&m, &inverse(&m).unwrap());
            for (r, row) in i.iter().enumerate() {
                for (c, v) in row.iter().enumerate() {
                    let e = if r == c { 1.0 } else { 0.0 };
                    assert!((v - e).abs() < 1e-12);
                }
            }
        }
        assert_eq!(Gamut::from_name("aces"), None);
        // `rgb2spec` indexes its tables by discriminant.
        for (i, g) in ALL_GAMUTS.into_iter().enumerate() {
            assert_eq!(g as usize, i);
        }
    }
}
