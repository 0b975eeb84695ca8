//! CIE 1931 and 1964 colour matching and the XYZ ↔ linear sRGB conversion.

use super::curve::cells4;
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

    /// `eval` at every lane, as (x̄, ȳ, z̄) rows, four lanes at a time: the same IEEE operations
    /// per lane, so the same bits (tested), with one SIMD float-to-index conversion and one
    /// interpolation per component for four lanes.
    #[inline]
    pub fn eval_lanes<const N: usize>(&self, lambda: &[f32; N]) -> [[f32; N]; 3] {
        use wide::{f32x4, i32x4, CmpGe, CmpLe};
        let mut out = [[0.0; N]; 3];
        let (start, end) = (f32x4::splat(self.start), f32x4::splat(self.end));
        let zero = f32x4::splat(0.0);
        let (last, max_i) = (end - start, i32x4::splat(self.xyz.len() as i32 - 2));
        let whole = N - N % 4;
        for c in (0..whole).step_by(4) {
            let l = f32x4::from([lambda[c], lambda[c + 1], lambda[c + 2], lambda[c + 3]]);
            // NaN fails both comparisons, like the scalar range test.
            let inside = l.cmp_ge(start) & l.cmp_le(end);
            let (k, t) = cells4(l - start, last, max_i);
            // Written out: `k.map` kept its closure out of line (74·10⁶ instructions of a
            // tabletop frame at 8 spp).
            let k = k.map(|k| k as usize);
            let t4 = &self.xyz;
            let a = [t4[k[0]], t4[k[1]], t4[k[2]], t4[k[3]]];
            let b = [t4[k[0] + 1], t4[k[1] + 1], t4[k[2] + 1], t4[k[3] + 1]];
            for (comp, row) in out.iter_mut().enumerate() {
                let a = f32x4::from([a[0][comp], a[1][comp], a[2][comp], a[3][comp]]);
                let b = f32x4::from([b[0][comp], b[1][comp], b[2][comp], b[3][comp]]);
                let v = inside.blend(a + t * (b - a), zero).to_array();
                row[c..c + 4].copy_from_slice(&v);
            }
        }
        for j in whole..N {
            let v = self.eval(lambda[j]);
            for (row, v) in out.iter_mut().zip(v) {
                row[j] = v;
            }
        }
        out
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
    #[test]
    fn lanes_are_the_scalar_lookup_bit_for_bit() {
        // Every 1/64 nm over the table and past both ends, each table's end points, the
        // floats next to them, and NaN: four and three lanes (the scalar tail).
        for cmf in [super::cie1931(), super::cie1964()] {
            let (lo, hi) = cmf.range();
            let mut ls: Vec<f32> = (0..(hi - lo + 20.0) as i32 * 64)
                .map(|k| lo - 10.0 + k as f32 / 64.0)
                .collect();
            for e in [lo, hi] {
                ls.extend([e, e.next_up(), e.next_down()]);
            }
            ls.extend([f32::NAN, f32::INFINITY, -f32::INFINITY, 0.0]);
            for chunk in ls.chunks(8) {
                let mut l4 = [0.0f32; 4];
                let mut l3 = [0.0f32; 3];
                l4.iter_mut().zip(chunk).for_each(|(a, b)| *a = *b);
                l3.iter_mut().zip(chunk).for_each(|(a, b)| *a = *b);
                let (v4, v3) = (cmf.eval_lanes(&l4), cmf.eval_lanes(&l3));
                for (j, &l) in l4.iter().enumerate() {
                    let want = cmf.eval(l);
                    for c in 0..3 {
                        assert_eq!(
                            v4[c][j].to_bits(),
                            want[c].to_bits(),
                            "λ {l}, component {c}"
                        );
                        if j < 3 {
                            assert_eq!(v3[c][j].to_bits(), cmf.eval(l3[j])[c].to_bits());
                        }
                    }
                }
            }
        }
    }

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
