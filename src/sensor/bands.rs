//! Spectral bands: evenly spaced box bands (the fast path: one index per lane), and response
//! channels, each a box [lo, hi) or a curve (a filter, a camera's colour channel).

use crate::spectrum::{Curve, Wavelengths};

/// Evenly spaced spectral bands over [lo, hi).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bands {
    pub lo: f32,
    pub hi: f32,
    pub count: u32,
}

impl Bands {
    pub fn width(&self) -> f32 {
        (self.hi - self.lo) / self.count as f32
    }

    /// Centre wavelength of band `i` (what the EXR channel is named after).
    pub fn center(&self, i: u32) -> f32 {
        self.lo + (i as f32 + 0.5) * self.width()
    }
}

/// The spectral shape of one response channel.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// 1 on [lo, hi), 0 elsewhere.
    Box { lo: f32, hi: f32 },
    /// A tabulated or analytic curve (0 outside its data).
    Curve(Curve),
    /// A curve times λ (nm): a photon count's weight (the raw sensor's electrons, raw.rs).
    Photons(Curve),
}

/// One response channel: it accumulates L(λ)·shape(λ)·scale.
#[derive(Clone, Debug, PartialEq)]
pub struct Response {
    pub shape: Shape,
    /// The normalisation: 1 / ∫ shape for a band or a filter (a constant spectrum of 1 reads
    /// 1), 1 / ∫ ḡ for a camera's three channels.
    pub scale: f32,
}

impl Response {
    #[inline]
    pub fn eval(&self, lambda: f32) -> f32 {
        match &self.shape {
            Shape::Box { lo, hi } => {
                if lambda >= *lo && lambda < *hi {
                    1.0
                } else {
                    0.0
                }
            }
            Shape::Curve(c) => c.eval_one(lambda),
            Shape::Photons(c) => c.eval_one(lambda) * lambda,
        }
    }

    /// `eval` at every wavelength of a path: a curve's table is read for all lanes at once
    /// (`Curve::eval`'s SIMD lookups), with the same bits as `eval` lane by lane.
    #[inline]
    pub fn eval_lanes<const N: usize>(&self, wl: &Wavelengths<N>) -> [f32; N] {
        match &self.shape {
            Shape::Box { .. } => std::array::from_fn(|j| self.eval(wl.lambda[j])),
            Shape::Curve(c) => c.eval(wl).0,
            Shape::Photons(c) => {
                let v = c.eval(wl).0;
                std::array::from_fn(|j| v[j] * wl.lambda[j])
            }
        }
    }

    /// Where the shape is non-zero (a box's interval; a curve's data, or `range` for a curve
    /// defined everywhere).
    pub fn support(&self, range: (f32, f32)) -> (f32, f32) {
        match &self.shape {
            Shape::Box { lo, hi } => (*lo, *hi),
            Shape::Curve(c) | Shape::Photons(c) => c.support().unwrap_or(range),
        }
    }

    /// ∫ shape dλ over [lo, hi] (midpoint rule on 0.05 nm cells: exact for a box whose edges
    /// fall on the grid, and far below data precision for tabulated curves).
    pub fn integral(&self, lo: f32, hi: f32) -> f64 {
        integrate(lo, hi, |l| self.eval(l) as f64)
    }

    /// The response-weighted mean wavelength ∫λ·shape / ∫shape (what a channel is named after).
    pub fn centre(&self, lo: f32, hi: f32) -> f32 {
        let num = integrate(lo, hi, |l| l as f64 * self.eval(l) as f64);
        (num / self.integral(lo, hi)) as f32
    }
}

/// ∫ f over [lo, hi], midpoint rule on cells of at most 0.05 nm.
pub fn integrate(lo: f32, hi: f32, f: impl Fn(f32) -> f64) -> f64 {
    let n = (((hi - lo) * 20.0).ceil() as usize).max(1);
    let h = (hi - lo) as f64 / n as f64;
    (0..n)
        .map(|i| f((lo as f64 + (i as f64 + 0.5) * h) as f32))
        .sum::<f64>()
        * h
}
