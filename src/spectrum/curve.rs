//! `Curve`: a spectrum as a function of wavelength, ready to evaluate at a path's lanes.
//!
//! Every form a scene can write (constant, tabulated, file, named, blackbody, RGB) resolves to
//! one of these variants when the scene loads, so evaluation is one `match` and a few flops.

pub use super::blackbody::{planck, Blackbody};
use super::color::cie1931;
use super::gamut::Gamut;
use super::knots::Knots;
use super::rgb2spec::{self, Sigmoid};
use super::sampled::Spectrum;
use super::wavelengths::Wavelengths;

/// Samples on an even grid, linearly interpolated; 0 outside [start, start + (n-1)·step].
#[derive(Clone, Debug, PartialEq)]
pub struct Dense {
    start: f32,
    inv_step: f32,
    values: Vec<f32>,
}

impl Dense {
    /// Samples `values` from `start` nm, `per_nm` of them per nm.
    pub(super) fn new(start: f32, per_nm: f32, values: Vec<f32>) -> Dense {
        Dense {
            start,
            inv_step: per_nm,
            values,
        }
    }

    /// Every sample times `k`.
    pub(super) fn scale_values(&mut self, k: f32) {
        self.values.iter_mut().for_each(|v| *v *= k);
    }

    #[inline]
    pub fn eval(&self, lambda: f32) -> f32 {
        let x = (lambda - self.start) * self.inv_step;
        let last = (self.values.len() - 1) as f32;
        if !(0.0..=last).contains(&x) {
            return 0.0;
        }
        // Through i32: x is in range here, and f32 → i32 is a cheaper conversion than → usize.
        let i = (x as i32 as usize).min(self.values.len().saturating_sub(2));
        let t = x - i as f32;
        let a = self.values[i];
        match self.values.get(i + 1) {
            Some(&b) => a + t * (b - a),
            None => a,
        }
    }

    /// `eval` at every lane, four lanes at a time: the same IEEE operations, so the same bits
    /// (tested), with one SIMD float-to-index conversion per four lanes (the scalar `as usize`
    /// conversion was most of a lookup's cost in a Cornell-box profile).
    #[inline]
    pub fn eval_lanes<const N: usize>(&self, lambda: &[f32; N]) -> [f32; N] {
        use wide::{f32x4, i32x4, CmpGe, CmpLe};
        let mut out = [0.0; N];
        // `from_samples` makes a one-sample curve a `Constant`; guard anyway.
        if self.values.len() < 2 {
            for (o, &l) in out.iter_mut().zip(lambda) {
                *o = self.eval(l);
            }
            return out;
        }
        let last = (self.values.len() - 1) as f32;
        let (start, inv_step) = (f32x4::splat(self.start), f32x4::splat(self.inv_step));
        let (zero, lastv) = (f32x4::splat(0.0), f32x4::splat(last));
        let max_i = i32x4::splat(self.values.len() as i32 - 2);
        let mut chunks = out.chunks_exact_mut(4);
        for (o, l) in (&mut chunks).zip(lambda.chunks_exact(4)) {
            let x = (f32x4::from([l[0], l[1], l[2], l[3]]) - start) * inv_step;
            // NaN fails both comparisons, like the scalar range test.
            let inside = x.cmp_ge(zero) & x.cmp_le(lastv);
            let (k, t) = cells4(x, lastv, max_i);
            let a = f32x4::from(k.map(|k| self.values[k as usize]));
            let b = f32x4::from(k.map(|k| self.values[k as usize + 1]));
            let v = inside.blend(a + t * (b - a), zero);
            o.copy_from_slice(&v.to_array());
        }
        let done = N - chunks.into_remainder().len();
        for k in done..N {
            out[k] = self.eval(lambda[k]);
        }
        out
    }

    /// The table as (start, 1 / step, samples).
    pub fn grid(&self) -> (f32, f32, &[f32]) {
        (self.start, self.inv_step, &self.values)
    }

    /// The first and last sample's wavelengths (nm).
    pub fn range(&self) -> (f32, f32) {
        let n = self.values.len() as f32 - 1.0;
        (self.start, self.start + n / self.inv_step)
    }

    /// This table continued at its own step by `tail(λ)` up to `end` nm: the same start, step
    /// and samples, so it evaluates to the same bits inside its old range.
    pub fn continued(&self, end: f32, tail: impl Fn(f32) -> f32) -> Dense {
        let mut values = self.values.clone();
        let step = 1.0 / self.inv_step as f64;
        loop {
            let l = self.start as f64 + values.len() as f64 * step;
            if l > end as f64 + 1e-3 {
                break;
            }
            values.push(tail(l as f32));
        }
        Dense { values, ..*self }
    }
}

/// The table cells of four grid positions `x` (in samples from the table's first) and the
/// weights of their upper samples: each lane's `i` and `t` of a scalar lookup where x is in
/// [0, last]; elsewhere clamped there first, so every index is valid (the caller masks those
/// lanes). `max_i` is the last cell (samples − 2).
#[inline(always)]
pub(crate) fn cells4(
    x: wide::f32x4,
    last: wide::f32x4,
    max_i: wide::i32x4,
) -> ([i32; 4], wide::f32x4) {
    let zero = wide::f32x4::splat(0.0);
    let i = x
        .max(zero)
        .min(last)
        .fast_trunc_int()
        .max(wide::i32x4::splat(0))
        .min(max_i);
    (i.to_array(), x - i.round_float())
}

/// `repr(u8)`: a plain tag byte. Without it rustc may keep the variant in a niche of a field
/// (a `Vec` capacity in `Irregular`), which cost every `eval` five instructions to decode.
#[derive(Clone, Debug, PartialEq)]
#[repr(u8)]
pub enum Curve {
    Constant(f32),
    Dense(Dense),
    /// Unevenly spaced samples, linearly interpolated; 0 outside their range.
    Irregular {
        nm: Knots,
        values: Vec<f32>,
    },
    /// Planck's law in W m⁻² sr⁻¹ nm⁻¹, times a scale (tabulated: `blackbody.rs`).
    Blackbody(Blackbody),
    /// A Jakob–Hanika sigmoid spectrum (bounded to [0, 1]) times `scale`.
    Rgb {
        sigmoid: Sigmoid,
        scale: f32,
    },
    /// An emitter RGB: `scale` × sigmoid × the colour space's white (D65, unit luminance).
    RgbIlluminant {
        sigmoid: Sigmoid,
        scale: f32,
        illuminant: Dense,
    },
}

/// An `Irregular` curve at `lambda`: 0 outside the knots, else linear between the two around it.
#[inline]
fn irregular(knots: &Knots, values: &[f32], lambda: f32) -> f32 {
    let nm = knots.nm();
    if lambda < nm[0] || lambda > nm[nm.len() - 1] {
        return 0.0;
    }
    let i = knots.upper(lambda).clamp(1, nm.len() - 1);
    let t = (lambda - nm[i - 1]) / (nm[i] - nm[i - 1]);
    values[i - 1] + t * (values[i] - values[i - 1])
}

impl Curve {
    /// Planck's law at `kelvin`, of unit scale.
    pub fn blackbody(kelvin: f32) -> Curve {
        Curve::Blackbody(Blackbody::new(kelvin, 1.0))
    }

    /// A curve through (nm, value) samples: `Dense` when the spacing is even or the knots lie on
    /// an even grid (`knots::on_common_grid`), else `Irregular`.
    /// `nm` must be strictly increasing with at least one sample (the config checks).
    pub fn from_samples(nm: &[f64], values: &[f64]) -> Curve {
        assert_eq!(nm.len(), values.len());
        if nm.len() == 1 {
            return Curve::Constant(values[0] as f32);
        }
        let step = (nm[nm.len() - 1] - nm[0]) / (nm.len() - 1) as f64;
        let even = nm
            .iter()
            .enumerate()
            .all(|(i, &w)| (w - (nm[0] + i as f64 * step)).abs() < 1e-6 * step.max(1.0));
        let grid = if even {
            Some((step, values.to_vec()))
        } else {
            super::knots::on_common_grid(nm, values)
        };
        match grid {
            Some((step, grid)) => Curve::Dense(Dense {
                start: nm[0] as f32,
                inv_step: (1.0 / step) as f32,
                values: grid.iter().map(|&v| v as f32).collect(),
            }),
            None => Curve::Irregular {
                nm: Knots::new(nm.iter().map(|&v| v as f32).collect()),
                values: values.iter().map(|&v| v as f32).collect(),
            },
        }
    }

    /// A bounded reflectance from linear sRGB in [0, 1]³.
    pub fn rgb_reflectance(rgb: [f32; 3]) -> Curve {
        Curve::rgb_reflectance_in(Gamut::Srgb, rgb)
    }

    /// [`Curve::rgb_reflectance`] for a colour of the RGB space `gamut`.
    pub fn rgb_reflectance_in(gamut: Gamut, rgb: [f32; 3]) -> Curve {
        Curve::Rgb {
            sigmoid: rgb2spec::fetch_in(gamut, rgb),
            scale: 1.0,
        }
    }

    /// An unbounded emitter RGB, as Mitsuba 3 and pbrt-v4 do: scale = 2·max(rgb), the sigmoid of
    /// rgb/scale (so its peak is 0.5, well inside the bounded gamut), times D65 at unit luminance.
    pub fn rgb_illuminant(rgb: [f32; 3]) -> Curve {
        Curve::rgb_illuminant_in(Gamut::Srgb, rgb)
    }

    /// [`Curve::rgb_illuminant`] for a colour of the RGB space `gamut`. Every input space's
    /// XYZ is D65-adapted (`gamut.rs`), so the illuminant is D65 for each.
    pub fn rgb_illuminant_in(gamut: Gamut, rgb: [f32; 3]) -> Curve {
        let m = rgb[0].max(rgb[1]).max(rgb[2]);
        if m <= 0.0 {
            return Curve::Constant(0.0);
        }
        let scale = 2.0 * m;
        let d65 = match super::data::named_illuminant("D65") {
            Some(Curve::Dense(d)) => d,
            _ => unreachable!("the embedded D65 table is evenly spaced"),
        };
        Curve::RgbIlluminant {
            sigmoid: rgb2spec::fetch_in(gamut, rgb.map(|c| c / scale)),
            scale,
            illuminant: d65,
        }
    }

    /// The curve times `k`.
    pub fn scaled(self, k: f32) -> Curve {
        match self {
            Curve::Constant(v) => Curve::Constant(v * k),
            Curve::Dense(mut d) => {
                d.scale_values(k);
                Curve::Dense(d)
            }
            Curve::Irregular { nm, mut values } => {
                values.iter_mut().for_each(|v| *v *= k);
                Curve::Irregular { nm, values }
            }
            Curve::Blackbody(b) => Curve::Blackbody(b.scaled(k)),
            Curve::Rgb { sigmoid, scale } => Curve::Rgb {
                sigmoid,
                scale: scale * k,
            },
            Curve::RgbIlluminant {
                sigmoid,
                scale,
                illuminant,
            } => Curve::RgbIlluminant {
                sigmoid,
                scale: scale * k,
                illuminant,
            },
        }
    }

    #[inline]
    pub fn eval_one(&self, lambda: f32) -> f32 {
        match self {
            Curve::Constant(v) => *v,
            Curve::Dense(d) => d.eval(lambda),
            Curve::Irregular { nm, values } => irregular(nm, values, lambda),
            Curve::Blackbody(b) => b.eval_one(lambda),
            Curve::Rgb { sigmoid, scale } => scale * sigmoid.eval(lambda),
            Curve::RgbIlluminant {
                sigmoid,
                scale,
                illuminant,
            } => scale * sigmoid.eval(lambda) * illuminant.eval(lambda),
        }
    }

    /// The curve at every lane. One `match`, then a loop the compiler unrolls.
    #[inline]
    pub fn eval<const N: usize>(&self, wl: &Wavelengths<N>) -> Spectrum<N> {
        match self {
            Curve::Constant(v) => Spectrum::splat(*v),
            Curve::Dense(d) => {
                let v = d.eval_lanes(&wl.lambda);
                Spectrum::from_fn(|i| v[i])
            }
            Curve::Rgb { sigmoid, scale } => {
                let s = sigmoid.eval_lanes(&wl.lambda);
                Spectrum::from_fn(|i| scale * s[i])
            }
            Curve::RgbIlluminant {
                sigmoid,
                scale,
                illuminant,
            } => {
                let s = sigmoid.eval_lanes(&wl.lambda);
                let d = illuminant.eval_lanes(&wl.lambda);
                Spectrum::from_fn(|i| scale * s[i] * d[i])
            }
            Curve::Blackbody(b) => {
                let v = b.eval_lanes(&wl.lambda);
                Spectrum::from_fn(|i| v[i])
            }
            _ => Spectrum::from_fn(|i| self.eval_one(wl.lambda[i])),
        }
    }

    /// Samples that reproduce the curve over [lo, hi] for a piecewise-linear consumer: the
    /// knots of tabulated data (exact), or a 1 nm grid for smooth curves (sigmoids, Planck,
    /// whose curvature makes 1 nm linear interpolation accurate to ~1e-5 relative). None for a
    /// constant.
    pub fn tabulate(&self, lo: f32, hi: f32) -> Option<(Vec<f32>, Vec<f32>)> {
        let knots: Vec<f32> = match self {
            Curve::Constant(_) => return None,
            Curve::Dense(d) => {
                let (a, b) = d.range();
                let n = d.values.len();
                (0..n)
                    .map(|i| a + (b - a) * i as f32 / (n - 1).max(1) as f32)
                    .collect()
            }
            Curve::Irregular { nm, .. } => nm.nm().to_vec(),
            _ => {
                let n = (hi - lo).ceil() as usize;
                (0..=n).map(|i| (lo + i as f32).min(hi)).collect()
            }
        };
        let values = knots.iter().map(|&l| self.eval_one(l)).collect();
        Some((knots, values))
    }

    /// True if the value does not depend on wavelength.
    pub fn is_constant(&self) -> bool {
        matches!(self, Curve::Constant(_))
    }

    /// The wavelength range outside of which the curve is 0 (None: defined everywhere).
    pub fn support(&self) -> Option<(f32, f32)> {
        match self {
            Curve::Dense(d) => Some(d.range()),
            Curve::Irregular { nm, .. } => {
                let nm = nm.nm();
                Some((nm[0], nm[nm.len() - 1]))
            }
            Curve::RgbIlluminant { illuminant, .. } => Some(illuminant.range()),
            _ => None,
        }
    }

    /// Mean over [lo, hi] nm (midpoint rule, 0.25 nm cells: far finer than any data we hold).
    pub fn average(&self, lo: f32, hi: f32) -> f32 {
        let n = (((hi - lo) * 4.0).ceil() as usize).max(1);
        let h = (hi - lo) / n as f32;
        let sum: f64 = (0..n)
            .map(|i| self.eval_one(lo + (i as f32 + 0.5) * h) as f64)
            .sum();
        (sum / n as f64) as f32
    }

    /// Smallest value over [lo, hi] nm, sampled every 0.25 nm (for validating reflectances).
    pub fn min_max(&self, lo: f32, hi: f32) -> (f32, f32) {
        let n = (((hi - lo) * 4.0).ceil() as usize).max(1);
        (0..=n)
            .map(|i| self.eval_one(lo + (hi - lo) * i as f32 / n as f32))
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), v| {
                (a.min(v), b.max(v))
            })
    }

    /// Luminance relative to a constant spectrum of 1: ∫ S ȳ dλ / ∫ ȳ dλ over the CIE range.
    pub fn luminance(&self) -> f32 {
        let cmf = cie1931();
        let (lo, hi) = cmf.range();
        let n = ((hi - lo) * 4.0) as usize;
        let h = (hi - lo) / n as f32;
        let (mut num, mut den) = (0.0f64, 0.0f64);
        for i in 0..n {
            let l = lo + (i as f32 + 0.5) * h;
            let y = cmf.eval(l)[1] as f64;
            num += y * self.eval_one(l) as f64;
            den += y;
        }
        (num / den) as f32
    }
}

#[cfg(test)]
#[path = "curve_tests.rs"]
mod tests;
