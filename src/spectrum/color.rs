//! CIE 1931 and 1964 colour matching and the XYZ ↔ linear sRGB conversion.

use super::{data, table};
use crate::math::portable;
use glam::{Mat3, Vec3};
use std::sync::OnceLock;

/// CIE 1931 2° colour-matching functions on a 1 nm grid, linearly interpolated between samples.
#[derive(Debug)]
pub struct Cmf {
    start: f32,
    end: f32,
    xyz: Vec<[f32; 3]>,
    /// ∫ ȳ(λ) dλ of the interpolated curve (trapezoid rule on the 1 nm grid, which is exact for
    /// a piecewise-linear function). Dividing XYZ by it makes a constant spectrum of 1 give Y = 1.
    pub y_integral: f32,
}

impl Cmf {
    /// (x̄, ȳ, z̄) at `lambda` nm; zero outside 360–830 nm.
    #[inline]
    pub fn eval(&self, lambda: f32) -> [f32; 3] {
        if !(self.start..=self.end).contains(&lambda) {
            return [0.0; 3];
        }
        let x = lambda - self.start;
        // Through i32: x is in range here, and f32 → i32 is a cheaper conversion than → usize.
        let i = (x as i32 as usize).min(self.xyz.len() - 2);
        let t = x - i as f32;
        let (a, b) = (self.xyz[i], self.xyz[i + 1]);
        [
            a[0] + t * (b[0] - a[0]),
            a[1] + t * (b[1] - a[1]),
            a[2] + t * (b[2] - a[2]),
        ]
    }

    pub fn range(&self) -> (f32, f32) {
        (self.start, self.end)
    }
}

/// The CIE 1931 2° observer from `spectra/cmf/CIE1931_2deg.txt`.
pub fn cie1931() -> &'static Cmf {
    static CMF: OnceLock<Cmf> = OnceLock::new();
    CMF.get_or_init(|| load_cmf("cmf/CIE1931_2deg"))
}

/// The CIE 1964 10° observer from `spectra/cmf/CIE1964_10deg.txt`.
pub fn cie1964() -> &'static Cmf {
    static CMF: OnceLock<Cmf> = OnceLock::new();
    CMF.get_or_init(|| load_cmf("cmf/CIE1964_10deg"))
}

fn load_cmf(key: &str) -> Cmf {
    let text = data::embedded(key).expect("CMF data is embedded");
    let t = table::parse(text).expect("embedded CMF table parses");
    let (x, y, z) = (
        t.column("x").unwrap(),
        t.column("y").unwrap(),
        t.column("z").unwrap(),
    );
    let start = t.wavelengths[0];
    for (i, &w) in t.wavelengths.iter().enumerate() {
        assert_eq!(w, start + i as f64, "the CMF table is on a 1 nm grid");
    }
    let xyz: Vec<[f32; 3]> = (0..x.len())
        .map(|i| [x[i] as f32, y[i] as f32, z[i] as f32])
        .collect();
    let y_integral = y.iter().sum::<f64>() - 0.5 * (y[0] + y[y.len() - 1]);
    Cmf {
        start: start as f32,
        end: *t.wavelengths.last().unwrap() as f32,
        xyz,
        y_integral: y_integral as f32,
    }
}

/// XYZ → linear sRGB (IEC 61966-2-1, D65 white).
pub const XYZ_TO_SRGB: Mat3 = Mat3::from_cols_array(&[
    3.240_454_2,
    -0.969_266,
    0.055_643_4,
    -1.537_138_5,
    1.876_010_8,
    -0.204_025_9,
    -0.498_531_4,
    0.041_556,
    1.057_225_2,
]);

/// Linear sRGB → XYZ.
pub const SRGB_TO_XYZ: Mat3 = Mat3::from_cols_array(&[
    0.412_456_4,
    0.212_672_9,
    0.019_333_9,
    0.357_576_1,
    0.715_152_2,
    0.119_192,
    0.180_437_5,
    0.072_175,
    0.950_304_1,
]);

pub fn xyz_to_srgb(xyz: Vec3) -> Vec3 {
    XYZ_TO_SRGB * xyz
}

/// The sRGB transfer function (for 8-bit previews).
#[inline]
pub fn srgb_encode(v: f32) -> f32 {
    if v <= 0.003_130_8 {
        12.92 * v.max(0.0)
    } else {
        1.055 * portable::powf(v, 1.0 / 2.4) - 0.055
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cmf_values_and_normalisation() {
        let c = cie1931();
        assert!((c.eval(560.0)[1] - 0.995).abs() < 1e-6);
        assert_eq!(c.eval(300.0), [0.0; 3]);
        // CIE 1931 2°, 1 nm, 360–830: ∫ȳ = 106.857 (colour-science / pbrt's CIE_Y_integral).
        assert!((c.y_integral - 106.857).abs() < 0.01, "{}", c.y_integral);
        let m = XYZ_TO_SRGB * SRGB_TO_XYZ;
        assert!(m.abs_diff_eq(Mat3::IDENTITY, 1e-5));
        // D65 white (x, y) = (0.3127, 0.3290) maps to sRGB (1, 1, 1).
        let w = Vec3::new(0.3127 / 0.329, 1.0, (1.0 - 0.3127 - 0.329) / 0.329);
        assert!((xyz_to_srgb(w) - Vec3::ONE).abs().max_element() < 1e-3);
    }
}
