//! Fitting of the RGB-to-spectrum coefficient table of Jakob & Hanika, "A Low-Dimensional
//! Function Space for Efficient Spectral Upsampling" (EG 2019).
//!
//! A reflectance is `s(λ) = S(c0 λ² + c1 λ + c2)` with `S(x) = 1/2 + x / (2 sqrt(1 + x²))`. For a
//! linear RGB colour (sRGB, or another space of `gamut.rs`, in its D65-adapted XYZ) we solve for `c` so that the spectrum, lit by D65 and seen by the CIE 1931
//! 2° observer, has that colour. The residual is the CIELAB difference (perceptually even, so the
//! solver spends its accuracy evenly across dark and bright colours), driven to zero by Newton
//! steps on the square 3×3 system with an analytic Jacobian.
//!
//! This file and its child `coeffs.rs` (the table) have no dependencies beyond `std`: `build.rs`
//! includes them (with `table.rs` as their sibling, so `super::table` resolves there as in the
//! crate) to fit the table at build time; the crate compiles them too so tests can check the fit
//! and the runtime can decode the table.

mod coeffs;

use super::table;
use crate::math::portable;
pub use coeffs::{fit_table, scale, CoeffTable};

/// The integration range (nm): that of the CIE 1931 data in `spectra/cmf`.
pub const LAMBDA_MIN: f64 = 360.0;
pub const LAMBDA_MAX: f64 = 830.0;

/// XYZ -> linear sRGB (D65 white).
pub const XYZ_TO_SRGB: [[f64; 3]; 3] = [
    [3.2404542, -1.5371385, -0.4985314],
    [-0.9692660, 1.8760108, 0.0415560],
    [0.0556434, -0.2040259, 1.0572252],
];

/// Linear sRGB -> XYZ (D65 white), the inverse of [`XYZ_TO_SRGB`].
pub use super::gamut::SRGB_TO_XYZ;

/// Bound on each coefficient in the normalised wavelength variable. Black, white and the sRGB
/// primaries are approached only as the sigmoid tends to a step, i.e. as the coefficients
/// diverge; the bound keeps them finite and the table interpolable. Dark saturated colours need
/// a narrow, low bump whose tails (which decay like 1/x²) stay small, i.e. |c| of order 1e3, so
/// the bound must be well above that: at 3000 every table entry is fitted to < 1e-3 in linear
/// sRGB. Transitions may then be sharper than the 1 nm grid, yet for the table's spectra the
/// 1 nm Simpson integral stays within 5e-5 of a 0.01 nm one.
const C_MAX: f64 = 3000.0;
/// Convergence threshold on the CIELAB residual ΔE; Newton converges quadratically, so going
/// well below the 1e-3 that matters costs about one extra iteration.
const TOLERANCE: f64 = 1e-5;
const MAX_ITERATIONS: usize = 40;
/// An accepted step must shrink ΔE below this fraction of its value to go on iterating.
const STALL: f64 = 0.99;
/// Step halvings tried before giving up on a direction (only far starts need any).
const MAX_HALVINGS: usize = 12;

/// The colorimetric data of the fit, sampled on one wavelength grid.
#[derive(Debug, Clone)]
pub struct FitData {
    /// Wavelengths (nm) of the quadrature nodes.
    pub lambda: Vec<f64>,
    /// CIE 1931 2° x̄ȳz̄ at `lambda`.
    pub cmf: Vec<[f64; 3]>,
    /// D65 relative power at `lambda` (linearly interpolated from its 5 nm table).
    pub illum: Vec<f64>,
    /// `lambda` mapped to [0, 1] over [LAMBDA_MIN, LAMBDA_MAX]: the optimisation variable,
    /// which keeps the three polynomial terms of similar size (good conditioning).
    t: Vec<f64>,
    /// Quadrature weight × illuminant × CMF, normalised so the illuminant has Y = 1:
    /// XYZ = Σ_k weights[k] s(λ_k).
    weights: Vec<[f64; 3]>,
    /// XYZ of the illuminant itself (s = 1), the CIELAB reference white.
    white: [f64; 3],
    /// The RGB space's RGB -> XYZ matrix: a target colour's XYZ (linear sRGB unless
    /// [`FitData::with_matrix`] sets another).
    to_xyz: [[f64; 3]; 3],
}

/// Result of [`FitData::fit_one`].
#[derive(Debug, Clone, Copy)]
pub struct Fit {
    /// Coefficients in the normalised wavelength variable (see [`FitData::to_nm`]).
    pub coeffs: [f64; 3],
    /// CIELAB distance ΔE between the spectrum's colour and the target.
    pub residual: f64,
}

impl FitData {
    /// Builds the data from the texts of `spectra/cmf/CIE1931_2deg.txt` (1 nm) and
    /// `spectra/illuminants/D65.txt`. Integration is composite Simpson on the 1 nm CMF grid over
    /// 360–830 nm (470 intervals), with D65 linearly interpolated onto it.
    pub fn from_texts(cmf_text: &str, d65_text: &str) -> Result<FitData, String> {
        let cmf = table::parse(cmf_text).map_err(|e| format!("CMF table: {e}"))?;
        let d65 = table::parse(d65_text).map_err(|e| format!("D65 table: {e}"))?;
        if cmf.values.len() != 3 {
            return Err("CMF table: expected 3 value columns (x y z)".into());
        }
        let lambda: Vec<f64> = cmf
            .wavelengths
            .iter()
            .copied()
            .filter(|&l| (LAMBDA_MIN..=LAMBDA_MAX).contains(&l))
            .collect();
        let n = lambda.len();
        // Simpson needs an even number of equal intervals spanning the whole range.
        let h = (LAMBDA_MAX - LAMBDA_MIN) / (n.max(2) - 1) as f64;
        let uniform = lambda
            .iter()
            .enumerate()
            .all(|(k, &l)| (l - (LAMBDA_MIN + k as f64 * h)).abs() < 1e-9);
        if n < 3 || n % 2 == 0 || !uniform || lambda[0] != LAMBDA_MIN || lambda[n - 1] != LAMBDA_MAX
        {
            return Err(
                "CMF table: need an odd number of uniformly spaced samples over 360-830 nm".into(),
            );
        }
        let cmf_values: Vec<[f64; 3]> = lambda
            .iter()
            .map(|&l| [0, 1, 2].map(|c| cmf.interpolate(c, l)))
            .collect();
        let illum: Vec<f64> = lambda.iter().map(|&l| d65.interpolate(0, l)).collect();
        let simpson = |k: usize| {
            h / 3.0
                * if k == 0 || k == n - 1 {
                    1.0
                } else if k % 2 == 1 {
                    4.0
                } else {
                    2.0
                }
        };
        let mut weights: Vec<[f64; 3]> = (0..n)
            .map(|k| cmf_values[k].map(|v| simpson(k) * illum[k] * v))
            .collect();
        let y_white: f64 = weights.iter().map(|w| w[1]).sum();
        if y_white.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return Err("D65 × ȳ integrates to zero".into());
        }
        for w in &mut weights {
            *w = w.map(|v| v / y_white);
        }
        let mut white = [0.0; 3];
        for w in &weights {
            for c in 0..3 {
                white[c] += w[c];
            }
        }
        let t = lambda
            .iter()
            .map(|&l| (l - LAMBDA_MIN) / (LAMBDA_MAX - LAMBDA_MIN))
            .collect();
        Ok(FitData {
            lambda,
            cmf: cmf_values,
            illum,
            t,
            weights,
            white,
            to_xyz: SRGB_TO_XYZ,
        })
    }

    /// The same data fitting colours of the RGB space whose RGB -> XYZ matrix is `to_xyz`
    /// (XYZ relative to this illuminant: its white must be that space's white).
    pub fn with_matrix(mut self, to_xyz: [[f64; 3]; 3]) -> FitData {
        self.to_xyz = to_xyz;
        self
    }

    /// XYZ of the RGB colour `rgb` of the space being fitted.
    pub fn rgb_to_xyz(&self, rgb: [f64; 3]) -> [f64; 3] {
        mat_vec(&self.to_xyz, rgb)
    }

    /// XYZ (illuminant Y = 1) of the reflectance `s` under the illuminant.
    pub fn xyz(&self, s: impl Fn(f64) -> f64) -> [f64; 3] {
        let mut xyz = [0.0; 3];
        for (w, &l) in self.weights.iter().zip(&self.lambda) {
            let v = s(l);
            for c in 0..3 {
                xyz[c] += w[c] * v;
            }
        }
        xyz
    }

    /// CIELAB of `xyz` relative to the illuminant's white.
    pub fn lab(&self, xyz: [f64; 3]) -> [f64; 3] {
        let f = [0, 1, 2].map(|c| lab_f(xyz[c] / self.white[c]).0);
        [
            116.0 * f[1] - 16.0,
            500.0 * (f[0] - f[1]),
            200.0 * (f[1] - f[2]),
        ]
    }

    /// XYZ of the spectrum with normalised coefficients `c`; also stores S'(x) at every node in
    /// `slopes` for [`FitData::lab_jacobian`], so a step that is rejected or that converges does
    /// not pay for a Jacobian.
    fn xyz_and_slopes(&self, c: [f64; 3], slopes: &mut [f64]) -> [f64; 3] {
        let mut xyz = [0.0; 3];
        // Two passes per block: the first has no loop-carried dependency, so it vectorises
        // (packed sqrt and division, the bulk of the cost); the second accumulates the sums.
        let mut sv = [0.0f64; 64];
        let blocks = self.weights.chunks(64).zip(self.t.chunks(64));
        for ((ws, ts), dv) in blocks.zip(slopes.chunks_mut(64)) {
            let n = ts.len();
            for ((t, s), d) in ts.iter().zip(&mut sv[..n]).zip(dv.iter_mut()) {
                let x = (c[0] * t + c[1]) * t + c[2];
                let r = 1.0 / (1.0 + x * x).sqrt();
                *s = 0.5 + 0.5 * x * r;
                *d = 0.5 * r * r * r; // S'(x) = 1 / (2 (1 + x²)^{3/2})
            }
            for (w, &s) in ws.iter().zip(&sv[..n]) {
                for k in 0..3 {
                    xyz[k] += w[k] * s;
                }
            }
        }
        xyz
    }

    /// `jac[row][j] = ∂Lab[row] / ∂c[j]` at the spectrum whose XYZ and slopes
    /// [`FitData::xyz_and_slopes`] computed.
    fn lab_jacobian(&self, xyz: [f64; 3], slopes: &[f64]) -> [[f64; 3]; 3] {
        let mut dxyz = [[0.0; 3]; 3]; // ∂XYZ[k] / ∂c[j]
        for ((w, &t), &ds) in self.weights.iter().zip(&self.t).zip(slopes) {
            let basis = [t * t, t, 1.0];
            for k in 0..3 {
                let d = w[k] * ds;
                for j in 0..3 {
                    dxyz[k][j] += d * basis[j];
                }
            }
        }
        let df = [0, 1, 2].map(|k| lab_f(xyz[k] / self.white[k]).1 / self.white[k]);
        let mut jac = [[0.0; 3]; 3];
        for j in 0..3 {
            let (fx, fy, fz) = (df[0] * dxyz[0][j], df[1] * dxyz[1][j], df[2] * dxyz[2][j]);
            jac[0][j] = 116.0 * fy;
            jac[1][j] = 500.0 * (fx - fy);
            jac[2][j] = 200.0 * (fy - fz);
        }
        jac
    }

    /// Solves for the normalised coefficients whose spectrum has the RGB colour `rgb`,
    /// starting from `start` (a neighbouring solution, or zeros: the flat 0.5 spectrum).
    /// Damped Newton: a step is halved until it lowers ΔE; the iteration stops at convergence,
    /// or when no step helps (a target outside the bounded model's reach, e.g. black).
    pub fn fit_one(&self, rgb: [f64; 3], start: [f64; 3]) -> Fit {
        let target = self.lab(self.rgb_to_xyz(rgb));
        let mut slopes = vec![0.0; self.t.len()];
        let mut c = bound(start);
        let mut xyz = self.xyz_and_slopes(c, &mut slopes);
        let mut lab = self.lab(xyz);
        let mut err = dist(lab, target);
        for _ in 0..MAX_ITERATIONS {
            if err < TOLERANCE {
                break;
            }
            let jac = self.lab_jacobian(xyz, &slopes);
            let r = [0, 1, 2].map(|k| target[k] - lab[k]);
            let Some(step) = solve3(jac, r) else { break };
            let mut alpha = 1.0;
            let mut improved = false;
            for _ in 0..MAX_HALVINGS {
                let trial = bound([0, 1, 2].map(|j| c[j] + alpha * step[j]));
                let xyz_t = self.xyz_and_slopes(trial, &mut slopes);
                let lab_t = self.lab(xyz_t);
                let err_t = dist(lab_t, target);
                if err_t < err {
                    // Free Newton steps shrink ΔE by orders of magnitude; a tiny gain means the
                    // coefficient bound holds the iterate back, and more steps would not help.
                    improved = err_t < STALL * err;
                    (c, xyz, lab, err) = (trial, xyz_t, lab_t, err_t);
                    break;
                }
                alpha *= 0.5;
            }
            if !improved {
                break;
            }
        }
        Fit {
            coeffs: c,
            residual: err,
        }
    }

    /// Converts normalised coefficients (polynomial in t = (λ - 360) / 470) to coefficients of
    /// the polynomial in λ (nm).
    pub fn to_nm(c: [f64; 3]) -> [f64; 3] {
        let (a, w) = (LAMBDA_MIN, LAMBDA_MAX - LAMBDA_MIN);
        [
            c[0] / (w * w),
            c[1] / w - 2.0 * a * c[0] / (w * w),
            c[0] * a * a / (w * w) - c[1] * a / w + c[2],
        ]
    }
}

/// CIELAB's f(u) and its derivative.
fn lab_f(u: f64) -> (f64, f64) {
    const DELTA: f64 = 6.0 / 29.0;
    if u > DELTA * DELTA * DELTA {
        let f = portable::cbrt(u);
        (f, 1.0 / (3.0 * f * f))
    } else {
        let d = 1.0 / (3.0 * DELTA * DELTA);
        (u * d + 4.0 / 29.0, d)
    }
}

fn bound(c: [f64; 3]) -> [f64; 3] {
    // Scaling the whole vector (rather than clipping components) keeps the polynomial's roots,
    // i.e. where the spectrum crosses 1/2, and only limits how sharp the transitions get.
    let m = c.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if m > C_MAX {
        c.map(|v| v * (C_MAX / m))
    } else {
        c
    }
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// `m · v` for a 3×3 matrix (colour-space conversions).
pub fn mat_vec(m: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    m.map(|row| row[0] * v[0] + row[1] * v[1] + row[2] * v[2])
}

/// Solves `a x = b` by Gaussian elimination with partial pivoting; `None` if singular.
fn solve3(mut a: [[f64; 3]; 3], mut b: [f64; 3]) -> Option<[f64; 3]> {
    for col in 0..3 {
        let p = (col..3).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
        if a[p][col].abs() < 1e-300 || !a[p][col].is_finite() {
            return None;
        }
        a.swap(col, p);
        b.swap(col, p);
        let pivot = a[col];
        for row in col + 1..3 {
            let f = a[row][col] / pivot[col];
            for (v, p) in a[row][col..].iter_mut().zip(&pivot[col..]) {
                *v -= f * p;
            }
            b[row] -= f * b[col];
        }
    }
    let mut x = [0.0; 3];
    for row in (0..3).rev() {
        let s: f64 = (row + 1..3).map(|k| a[row][k] * x[k]).sum();
        x[row] = (b[row] - s) / a[row][row];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}
