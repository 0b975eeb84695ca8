//! Hero-wavelength sampling (Wilkie et al. 2014): one uniform number picks the hero; the other
//! N-1 wavelengths are the hero rotated by j/N in the sampling CDF, so every lane has the same
//! marginal pdf and the N lanes stratify the range.
//!
//! Two distributions over any range [lo, hi] chosen at run time:
//! - `Visible`: p(λ) ∝ cosh⁻²(0.0072 (λ − 538)), truncated to the range. Its CDF is a tanh, so
//!   sampling is closed-form. Over 360–830 nm this is exactly Mitsuba 3's visible sampling.
//! - `Uniform`: p(λ) = 1 / (hi − lo). With it the rotation is Wilkie's λ_j = lo + ((λ_h − lo) + jΛ/N) mod Λ.

use crate::math::portable;
use serde::{Deserialize, Serialize};
use wide::f32x4;

/// How wavelengths are drawn for each camera path.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default, clap::ValueEnum)]
pub enum WavelengthSampling {
    /// Importance sampling of the visible range (the CIE curves' mass), as Mitsuba 3 does.
    #[default]
    Visible,
    /// Uniform over the range: equal noise in every spectral band.
    Uniform,
    /// From the sensor's own curves (Mitsuba 3's `specfilm`): see `sensor::sampling`.
    Sensor,
}

// Constants of the visible distribution (Mitsuba 3 / Radziszewski et al. 2009).
const VIS_CENTER: f32 = 538.0;
const VIS_K: f32 = 0.0072;

/// Samples wavelengths over a fixed range with a fixed distribution.
#[derive(Clone, Copy, Debug)]
pub struct WavelengthSampler {
    kind: WavelengthSampling,
    lo: f32,
    hi: f32,
    // Visible: tanh(k (lo − 538)) and tanh(k (hi − 538)) − tanh(k (lo − 538)).
    t_lo: f32,
    t_span: f32,
    /// `Sensor`: the tabulated density (leaked once per scene load: a few kB, and it keeps the
    /// sampler `Copy`).
    table: Option<&'static Tabulated>,
}

/// A piecewise-constant density on equal cells over [lo, hi], sampled by its inverse CDF.
#[derive(Debug)]
pub struct Tabulated {
    lo: f32,
    cell: f32,
    /// Density per cell (1/nm), normalised.
    pdf: Vec<f32>,
    /// CDF at the cell edges (len = cells + 1, from 0 to 1).
    cdf: Vec<f32>,
}

impl Tabulated {
    /// From non-negative cell values (any scale; at least one positive).
    fn new(lo: f32, hi: f32, values: &[f32]) -> Self {
        let cell = (hi - lo) / values.len() as f32;
        let total: f64 = values.iter().map(|&v| v as f64).sum::<f64>() * cell as f64;
        let pdf: Vec<f32> = values.iter().map(|&v| (v as f64 / total) as f32).collect();
        let mut cdf = Vec::with_capacity(values.len() + 1);
        let mut acc = 0.0f64;
        cdf.push(0.0);
        for &v in values {
            acc += v as f64 * cell as f64 / total;
            cdf.push(acc as f32);
        }
        *cdf.last_mut().unwrap() = 1.0;
        Self { lo, cell, pdf, cdf }
    }

    #[inline]
    fn sample(&self, u: f32) -> (f32, f32) {
        // The last edge with cdf ≤ u; empty cells (pdf 0) are never chosen for u < 1.
        let i = (self.cdf.partition_point(|&c| c <= u).max(1) - 1).min(self.pdf.len() - 1);
        let p = self.pdf[i];
        let t = if p > 0.0 {
            ((u - self.cdf[i]) / (p * self.cell)).clamp(0.0, 1.0)
        } else {
            0.5
        };
        let lambda = self.lo + (i as f32 + t) * self.cell;
        // The density at the wavelength returned, so a λ rounded onto a cell edge carries the
        // pdf that `pdf` reports for it.
        (lambda, self.pdf(lambda))
    }

    #[inline]
    fn pdf(&self, lambda: f32) -> f32 {
        let i = ((lambda - self.lo) / self.cell) as i64;
        self.pdf[i.clamp(0, self.pdf.len() as i64 - 1) as usize]
    }

    fn cdf(&self, lambda: f32) -> f32 {
        let x = (lambda - self.lo) / self.cell;
        let i = (x as i64).clamp(0, self.pdf.len() as i64 - 1) as usize;
        (self.cdf[i] + (x - i as f32).clamp(0.0, 1.0) * self.pdf[i] * self.cell).min(1.0)
    }
}

/// The wavelengths (nm) of one path and each lane's marginal pdf (1/nm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wavelengths<const N: usize> {
    pub lambda: [f32; N],
    pub pdf: [f32; N],
}

impl<const N: usize> Wavelengths<N> {
    /// Each lane's weight in the hero-wavelength estimator, 1 / (N p_j); 0 for a lane of zero
    /// density, which carries nothing.
    #[inline]
    pub fn estimator_weights(&self) -> crate::spectrum::Spectrum<N> {
        crate::spectrum::Spectrum::from_fn(|j| {
            if self.pdf[j] > 0.0 {
                1.0 / (N as f32 * self.pdf[j])
            } else {
                0.0
            }
        })
    }

    /// The hero wavelength, which drives every wavelength-dependent sampling decision.
    #[inline]
    pub fn hero(&self) -> f32 {
        self.lambda[0]
    }
}

impl WavelengthSampler {
    /// `lo < hi` in nm (validated by the config).
    pub fn new(kind: WavelengthSampling, lo: f32, hi: f32) -> Self {
        let t_lo = portable::tanh(VIS_K * (lo - VIS_CENTER));
        let t_span = portable::tanh(VIS_K * (hi - VIS_CENTER)) - t_lo;
        assert!(
            kind != WavelengthSampling::Sensor,
            "Sensor sampling needs its density: WavelengthSampler::tabulated"
        );
        Self {
            kind,
            lo,
            hi,
            t_lo,
            t_span,
            table: None,
        }
    }

    /// `Sensor` sampling from a density given as values on equal cells over [lo, hi].
    pub fn tabulated(lo: f32, hi: f32, values: &[f32]) -> Self {
        let table: &'static Tabulated = Box::leak(Box::new(Tabulated::new(lo, hi, values)));
        Self {
            kind: WavelengthSampling::Sensor,
            lo,
            hi,
            t_lo: 0.0,
            t_span: 1.0,
            table: Some(table),
        }
    }

    pub fn kind(&self) -> WavelengthSampling {
        self.kind
    }

    pub fn range(&self) -> (f32, f32) {
        (self.lo, self.hi)
    }

    /// Inverse CDF: maps u in [0,1) to a wavelength in [lo, hi].
    #[inline]
    pub fn sample_one(&self, u: f32) -> f32 {
        let l = match self.kind {
            WavelengthSampling::Uniform => self.lo + u * (self.hi - self.lo),
            WavelengthSampling::Visible => {
                VIS_CENTER + portable::atanh(self.t_lo + u * self.t_span) * (1.0 / VIS_K)
            }
            WavelengthSampling::Sensor => self.table.expect("tabulated").sample(u).0,
        };
        l.clamp(self.lo, self.hi)
    }

    /// The pdf (1/nm) of `lambda` under this distribution; 0 outside the range.
    #[inline]
    pub fn pdf(&self, lambda: f32) -> f32 {
        if !(self.lo..=self.hi).contains(&lambda) {
            return 0.0;
        }
        match self.kind {
            WavelengthSampling::Uniform => 1.0 / (self.hi - self.lo),
            WavelengthSampling::Visible => {
                let c = portable::cosh(VIS_K * (lambda - VIS_CENTER));
                VIS_K / (c * c * self.t_span)
            }
            WavelengthSampling::Sensor => self.table.expect("tabulated").pdf(lambda),
        }
    }

    /// The CDF of `lambda` (used by tests and by band-probability estimates).
    pub fn cdf(&self, lambda: f32) -> f32 {
        let l = lambda.clamp(self.lo, self.hi);
        match self.kind {
            WavelengthSampling::Uniform => (l - self.lo) / (self.hi - self.lo),
            WavelengthSampling::Visible => {
                (portable::tanh(VIS_K * (l - VIS_CENTER)) - self.t_lo) / self.t_span
            }
            WavelengthSampling::Sensor => self.table.expect("tabulated").cdf(l),
        }
    }

    /// Hero at `u`, companions at u + j/N (mod 1).
    #[inline]
    pub fn sample<const N: usize>(&self, u: f32) -> Wavelengths<N> {
        let mut lambda = [0.0; N];
        let mut pdf = [0.0; N];
        let lane_u = |j: usize| {
            let uj = u + j as f32 / N as f32;
            if uj >= 1.0 {
                uj - 1.0
            } else {
                uj
            }
        };
        match self.kind {
            WavelengthSampling::Uniform => {
                for j in 0..N {
                    lambda[j] = self.sample_one(lane_u(j));
                    pdf[j] = 1.0 / (self.hi - self.lo);
                }
            }
            WavelengthSampling::Sensor => {
                let t = self.table.expect("tabulated");
                for j in 0..N {
                    (lambda[j], pdf[j]) = t.sample(lane_u(j));
                }
            }
            WavelengthSampling::Visible => {
                // With t = tanh(k (λ − 538)), cosh⁻² = 1 − t², so the pdf needs no cosh. The
                // inverse, atanh(t) = ½ ln((1 + t) / (1 − t)), runs four lanes at a time: libm's
                // scalar atanh per lane was 5% of a Cornell box render.
                for j0 in (0..N).step_by(4) {
                    let mut t = [0.0f32; 4];
                    for (k, t) in t.iter_mut().enumerate().take(N - j0) {
                        *t = self.t_lo + lane_u(j0 + k) * self.t_span;
                    }
                    let tv = f32x4::from(t);
                    let atanh = ((f32x4::ONE + tv) / (f32x4::ONE - tv)).ln() * 0.5;
                    for (k, a) in atanh.to_array().into_iter().enumerate().take(N - j0) {
                        lambda[j0 + k] = (VIS_CENTER + a * (1.0 / VIS_K)).clamp(self.lo, self.hi);
                        pdf[j0 + k] = VIS_K * (1.0 - t[k] * t[k]) / self.t_span;
                    }
                }
            }
        }
        Wavelengths { lambda, pdf }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The SIMD inverse CDF of `sample` against the scalar one of `sample_one` (libm's atanh):
    /// within 1e-3 nm over ranges from narrow to 300-1100 nm (whose ends are where 1 − t loses
    /// digits, in both). Far below any spectral feature; the pdf comes from t in both.
    #[test]
    fn simd_inverse_cdf_matches_scalar() {
        for (lo, hi) in [
            (360.0, 830.0),
            (300.0, 1100.0),
            (500.0, 510.0),
            (380.0, 780.0),
        ] {
            let s = WavelengthSampler::new(WavelengthSampling::Visible, lo, hi);
            for i in 0..4000 {
                let u = i as f32 / 4000.0;
                let w = s.sample::<8>(u);
                for j in 0..8 {
                    let uj = (u + j as f32 / 8.0) % 1.0;
                    let want = s.sample_one(uj);
                    assert!(
                        (w.lambda[j] - want).abs() < 1e-3,
                        "{lo}-{hi} nm, u {uj}: {} vs {want}",
                        w.lambda[j]
                    );
                }
                let w1 = s.sample::<1>(u);
                assert!((w1.lambda[0] - s.sample_one(u)).abs() < 1e-3);
            }
        }
    }

    #[test]
    fn visible_matches_mitsuba_constants_over_360_830() {
        // Mitsuba 3: λ = 538 − 138.888·atanh(0.85691 − 1.82750·u).
        let s = WavelengthSampler::new(WavelengthSampling::Visible, 360.0, 830.0);
        for &u in &[0.01f32, 0.25, 0.5, 0.75, 0.99] {
            let mitsuba = 538.0 - 138.888_89 * portable::atanh(0.856_910_6 - 1.827_502 * u);
            assert!((s.sample_one(u) - mitsuba).abs() < 0.02, "u={u}");
        }
    }

    #[test]
    fn cdf_inverts_sampling_and_pdf_integrates_to_one() {
        for kind in [WavelengthSampling::Visible, WavelengthSampling::Uniform] {
            for (lo, hi) in [(360.0, 830.0), (300.0, 1100.0), (500.0, 510.0)] {
                let s = WavelengthSampler::new(kind, lo, hi);
                for i in 1..100 {
                    let u = i as f32 / 100.0;
                    assert!(
                        (s.cdf(s.sample_one(u)) - u).abs() < 2e-3,
                        "{kind:?} {lo}-{hi} u={u}"
                    );
                }
                // Midpoint rule with 1e4 cells: error far below the tolerance.
                let n = 10_000;
                let h = (hi - lo) / n as f32;
                let total: f32 = (0..n).map(|i| s.pdf(lo + (i as f32 + 0.5) * h) * h).sum();
                assert!((total - 1.0).abs() < 1e-3, "{kind:?} {lo}-{hi}: {total}");
            }
        }
    }

    #[test]
    fn lane_pdfs_equal_the_pdf_function() {
        for kind in [WavelengthSampling::Visible, WavelengthSampling::Uniform] {
            let s = WavelengthSampler::new(kind, 360.0, 830.0);
            for i in 0..100 {
                let w = s.sample::<4>(i as f32 / 100.0);
                for j in 0..4 {
                    let p = s.pdf(w.lambda[j]);
                    assert!(
                        (w.pdf[j] - p).abs() <= 2e-4 * p,
                        "{kind:?}: {} vs {p}",
                        w.pdf[j]
                    );
                }
            }
        }
    }

    #[test]
    fn lanes_are_rotated_hero() {
        let s = WavelengthSampler::new(WavelengthSampling::Uniform, 400.0, 800.0);
        let w = s.sample::<4>(0.9);
        let expect = [760.0, 460.0, 560.0, 660.0];
        for (j, e) in expect.iter().enumerate() {
            assert!((w.lambda[j] - e).abs() < 1e-3);
            assert!((w.pdf[j] - 1.0 / 400.0).abs() < 1e-9);
        }
    }
}
