//! An environment map (Mitsuba 3's `envmap`): radiance at infinity read from a
//! latitude-longitude image.
//!
//! Conventions, as Mitsuba 3's (checked against it by `tests/emitters_mitsuba.rs`): in the map's
//! local frame +y is up. Texture coordinates (u, v) ∈ [0, 1]² map to θ = π v (from +y) and
//! φ = 2π u, with the direction (sin φ sin θ, cos θ, −cos φ sin θ): u = 0 looks along −z, u = ¼
//! along +x, u = ½ along +z. Columns are texel-centred in u (column i at u = (i + ½)/W, wrapping
//! around), rows are vertex-centred in v (row j at v = j/(H − 1): the first row is the north
//! pole, the last the south pole). `to_world` rotates the map.
//!
//! Each texel's linear RGB is uplifted once, at load, as an illuminant (Mitsuba's scheme: scale =
//! 2·max(rgb), the sigmoid of rgb/scale, and a shared D65 factor). RGB says nothing about the
//! near infrared, and the D65 table ends at 830 nm: past it the factor continues as a
//! `TAIL_KELVIN` blackbody scaled to meet D65 there, up to `TAIL_END` (a chosen extension, not
//! data; `prism render` warns when the range goes past 830 nm), rather than dropping to 0. A lookup interpolates the
//! sigmoid values and the scales bilinearly, each on its own, and multiplies them, as Mitsuba does.
//!
//! Sampling is piecewise constant in (u, v) over the cells between texel centres, each cell
//! weighted by its corners' mean luminance times the mean of sin θ over its rows: the pdf is then
//! non-zero wherever the interpolated map is. In solid angle, pdf = pdf_uv / (2π² sin θ).

use crate::math::distribution::Distribution1D;
use crate::math::float;
use crate::math::portable;
use crate::math::turns::{acos_half_turns, azimuth_turns, sin_cos_turns};
use crate::spectrum::curve::Dense;
use crate::spectrum::gamut::Gamut;
use crate::spectrum::rgb2spec::{self, Sigmoid};
use crate::spectrum::{Spectrum, Wavelengths};
use crate::texture::{ImageSource, RgbImage};
use glam::{Mat3, Vec2, Vec3};
use std::f32::consts::PI;

#[derive(Clone, Debug)]
pub struct EnvMap {
    width: usize,
    height: usize,
    /// Per texel, row-major from the top: the sigmoid and the scale of its uplifted RGB.
    sigmoids: Vec<Sigmoid>,
    scales: Vec<f32>,
    /// CIE D65 at unit luminance with its blackbody tail (`illuminant`), shared by every texel.
    d65: Dense,
    /// The user's `scale` factor.
    scale: f32,
    /// Map-to-world and world-to-map rotations.
    to_world: Mat3,
    to_local: Mat3,
    /// Rows of cells (v), then cells within each row (u).
    marginal: Distribution1D,
    conditional: Vec<Distribution1D>,
    /// The image file it was read from (for `prism export`), if any.
    source: Option<ImageSource>,
}

/// The temperature of the tail past D65's table: D65's correlated colour temperature (K).
pub const TAIL_KELVIN: f32 = 6504.0;
/// Where the tail ends (nm); the map is 0 past it.
pub const TAIL_END: f32 = 2500.0;

/// CIE D65 at unit luminance, continued past its table's last sample by a `TAIL_KELVIN`
/// blackbody scaled to equal it there (module docs).
pub fn illuminant() -> Dense {
    let d65 = match crate::spectrum::data::named_illuminant("D65") {
        Some(crate::spectrum::Curve::Dense(d)) => d,
        _ => unreachable!("the embedded D65 table is evenly spaced"),
    };
    let last = d65.range().1;
    let k = d65.eval(last) / crate::spectrum::curve::planck(last, TAIL_KELVIN);
    d65.continued(TAIL_END, |l| {
        k * crate::spectrum::curve::planck(l, TAIL_KELVIN)
    })
}

/// Rec. 709 luminance of linear RGB.
fn luminance(c: [f32; 3]) -> f32 {
    0.212_672_9 * c[0] + 0.715_152_2 * c[1] + 0.072_175 * c[2]
}

impl EnvMap {
    /// The smallest map Mitsuba accepts (and which keeps both interpolation axes defined).
    pub const MIN_SIZE: (usize, usize) = (2, 3);

    /// Builds the map from linear RGB texels, which must be finite and ≥ 0, at least
    /// `MIN_SIZE`; `to_world` must be a rotation (orthonormal). The config checks all three.
    pub fn new(image: &RgbImage, scale: f32, to_world: Mat3) -> EnvMap {
        EnvMap::new_in(Gamut::Srgb, image, scale, to_world)
    }

    /// [`EnvMap::new`] for texels in the RGB space `gamut` (uplifted with its table, times D65
    /// as every input space is D65-adapted; sampling still weights cells by Rec. 709
    /// luminance, which only shapes the pdf).
    pub fn new_in(gamut: Gamut, image: &RgbImage, scale: f32, to_world: Mat3) -> EnvMap {
        let (w, h) = (image.width, image.height);
        assert!(w >= Self::MIN_SIZE.0 && h >= Self::MIN_SIZE.1);
        let mut sigmoids = Vec::with_capacity(w * h);
        let mut scales = Vec::with_capacity(w * h);
        for p in &image.pixels {
            let m = p[0].max(p[1]).max(p[2]);
            if m > 0.0 {
                let s = 2.0 * m;
                sigmoids.push(rgb2spec::fetch_in(
                    gamut,
                    p.map(|c| (c / s).clamp(0.0, 1.0)),
                ));
                scales.push(s);
            } else {
                sigmoids.push(Sigmoid::BLACK);
                scales.push(0.0);
            }
        }
        let d65 = illuminant();

        // Cell (i, j) lies between columns i, i+1 (wrapping) and rows j, j+1.
        let lum: Vec<f32> = image.pixels.iter().map(|&p| luminance(p)).collect();
        let dtheta = PI / (h - 1) as f32;
        let mut row_weights = Vec::with_capacity(h - 1);
        let mut conditional = Vec::with_capacity(h - 1);
        for j in 0..h - 1 {
            // Mean of sin θ over the cell's rows: (cos θ_j − cos θ_{j+1}) / Δθ.
            let (t0, t1) = (j as f64 * dtheta as f64, (j + 1) as f64 * dtheta as f64);
            let mean_sin = ((portable::cos(t0) - portable::cos(t1)) / (t1 - t0)) as f32;
            let cells: Vec<f32> = (0..w)
                .map(|i| {
                    let i1 = (i + 1) % w;
                    let corners = lum[j * w + i]
                        + lum[j * w + i1]
                        + lum[(j + 1) * w + i]
                        + lum[(j + 1) * w + i1];
                    0.25 * corners * mean_sin
                })
                .collect();
            row_weights.push(cells.iter().sum::<f32>());
            conditional.push(Distribution1D::new(&cells));
        }
        EnvMap {
            width: w,
            height: h,
            sigmoids,
            scales,
            d65,
            scale,
            to_world,
            to_local: to_world.transpose(),
            marginal: Distribution1D::new(&row_weights),
            conditional,
            source: image.source.clone(),
        }
    }

    /// The image file the map was read from, if any.
    pub fn source(&self) -> Option<&ImageSource> {
        self.source.as_ref()
    }

    /// The user's `scale` factor.
    pub fn scale(&self) -> f32 {
        self.scale
    }

    /// The map-to-world rotation.
    pub fn to_world(&self) -> Mat3 {
        self.to_world
    }

    /// Local direction → (u, v) in [0, 1)×[0, 1].
    #[inline]
    fn uv(d: Vec3) -> Vec2 {
        // Angles in turns straight away (no libm atan2, acos or floor: 3% of an env-lit frame).
        Vec2::new(azimuth_turns(d.x, -d.z), acos_half_turns(d.y))
    }

    /// Radiance arriving from world direction `d` (pointing away from the scene).
    #[inline]
    pub fn eval<const N: usize>(&self, d: Vec3, wl: &Wavelengths<N>) -> Spectrum<N> {
        self.eval_uv(Self::uv((self.to_local * d).normalize()), wl)
    }

    /// `eval` and `pdf` of one world direction, its local direction and (u, v) computed once
    /// (an escaping ray's MIS needs both: the two calls took two `atan2`s and `acos`es). The
    /// same bits as the two calls.
    #[inline]
    pub fn eval_and_pdf<const N: usize>(&self, d: Vec3, wl: &Wavelengths<N>) -> (Spectrum<N>, f32) {
        let l = (self.to_local * d).normalize();
        let uv = Self::uv(l);
        (self.eval_uv(uv, wl), self.pdf_local(l, uv))
    }

    /// Radiance at map coordinates `uv`.
    #[inline]
    fn eval_uv<const N: usize>(&self, uv: Vec2, wl: &Wavelengths<N>) -> Spectrum<N> {
        let (w, h) = (self.width, self.height);
        // Column centres at (i + ½)/W; rows at j/(H − 1).
        let x = uv.x * w as f32 - 0.5;
        let x0 = float::floor(x);
        let fx = x - x0;
        let i0 = float::wrap_index(x0 as i64, w);
        let i1 = if i0 + 1 == w { 0 } else { i0 + 1 };
        let y = uv.y * (h - 1) as f32;
        let j0 = (y.max(0.0) as usize).min(h - 2);
        let fy = y - j0 as f32;
        let idx = [
            j0 * w + i0,
            j0 * w + i1,
            (j0 + 1) * w + i0,
            (j0 + 1) * w + i1,
        ];
        let wt = [
            (1.0 - fx) * (1.0 - fy),
            fx * (1.0 - fy),
            (1.0 - fx) * fy,
            fx * fy,
        ];
        let f: f32 = idx.iter().zip(wt).map(|(&k, t)| t * self.scales[k]).sum();
        if f <= 0.0 {
            return Spectrum::zero();
        }
        let f = f * self.scale;
        // All lanes at once, texel by texel (SIMD sigmoids and D65 lookups, the same bits as one
        // lane at a time): per lane this was 4 scalar square roots and divisions and a table
        // lookup, 12% of the materials benchmark.
        // (Four calls rather than `idx.map`: the array map kept its closure out of line.)
        let s0 = self.sigmoids[idx[0]].eval_lanes(&wl.lambda);
        let s1 = self.sigmoids[idx[1]].eval_lanes(&wl.lambda);
        let s2 = self.sigmoids[idx[2]].eval_lanes(&wl.lambda);
        let s3 = self.sigmoids[idx[3]].eval_lanes(&wl.lambda);
        let d65 = self.d65.eval_lanes(&wl.lambda);
        Spectrum::from_fn(|l| {
            let s = wt[0] * s0[l] + wt[1] * s1[l] + wt[2] * s2[l] + wt[3] * s3[l];
            s * f * d65[l]
        })
    }

    /// Samples a world direction towards the map; returns it with its solid-angle pdf.
    #[inline]
    pub fn sample(&self, u: Vec2) -> Option<(Vec3, f32)> {
        let (v, pdf_v, j) = self.marginal.sample_continuous(u.y);
        let (x, pdf_x, _) = self.conditional[j].sample_continuous(u.x);
        // Cells start at the first column's centre.
        let uu = x + 0.5 / self.width as f32;
        let (sin_t, cos_t) = sin_cos_turns(0.5 * v);
        let (sin_p, cos_p) = sin_cos_turns(uu);
        if sin_t <= 0.0 {
            return None;
        }
        let local = Vec3::new(sin_p * sin_t, cos_t, -cos_p * sin_t);
        let pdf = pdf_v * pdf_x / (2.0 * PI * PI * sin_t);
        (pdf > 0.0 && pdf.is_finite()).then(|| ((self.to_world * local).normalize(), pdf))
    }

    /// Solid-angle density with which `sample` returns world direction `d`.
    #[inline]
    pub fn pdf(&self, d: Vec3) -> f32 {
        let l = (self.to_local * d).normalize();
        self.pdf_local(l, Self::uv(l))
    }

    /// `pdf` of local direction `l` (unit), whose map coordinates are `uv`.
    #[inline]
    fn pdf_local(&self, l: Vec3, uv: Vec2) -> f32 {
        let sin_t = (l.x * l.x + l.z * l.z).sqrt();
        if sin_t <= 0.0 {
            return 0.0;
        }
        let (v, x, j) = self.cell_coords(uv);
        self.marginal.pdf_continuous(v) * self.conditional[j].pdf_continuous(x)
            / (2.0 * PI * PI * sin_t)
    }

    /// Where map coordinates `uv` fall among the sampling cells: v, the position x in [0, 1)
    /// along its row of cells (which starts at the first column's centre), and the row.
    #[inline]
    fn cell_coords(&self, uv: Vec2) -> (f32, f32, usize) {
        let x = uv.x - 0.5 / self.width as f32;
        let x = x - float::floor(x);
        let rows = self.height - 1;
        let j = ((uv.y * rows as f32) as usize).min(rows - 1);
        (uv.y, x, j)
    }

    /// The sampling cell (row-major over rows of cells, then cells) that world direction `d`
    /// falls in.
    #[inline]
    pub fn cell(&self, d: Vec3) -> usize {
        let (_, x, j) = self.cell_coords(Self::uv((self.to_local * d).normalize()));
        let i = ((x * self.width as f32) as usize).min(self.width - 1);
        j * self.width + i
    }

    /// Probability with which `sample` picks cell `cell`.
    fn cell_probability(&self, cell: usize) -> f32 {
        let (i, j) = (cell % self.width, cell / self.width);
        self.marginal.pmf(j) * self.conditional[j].pmf(i)
    }

    /// The cells whose mean luminance is at least `ratio` times the map's (solid-angle) mean:
    /// a sun, a small window; None if no cell is that bright.
    pub fn bright_cells(&self, ratio: f32) -> Option<BrightCells> {
        let (w, rows) = (self.width, self.height - 1);
        let dtheta = PI as f64 / rows as f64;
        let mut mask = vec![false; w * rows];
        let (mut ids, mut weights) = (Vec::new(), Vec::new());
        for j in 0..rows {
            let p_row = self.marginal.pmf(j);
            if p_row <= 0.0 {
                continue;
            }
            // The cell's solid angle over the sphere's: its probability over that is its
            // luminance over the mean.
            let (t0, t1) = (j as f64 * dtheta, (j + 1) as f64 * dtheta);
            let share = ((portable::cos(t0) - portable::cos(t1)) / (2.0 * w as f64)) as f32;
            for i in 0..w {
                let p = self.cell_probability(j * w + i);
                if p > 0.0 && p >= ratio * share {
                    mask[j * w + i] = true;
                    ids.push((j * w + i) as u32);
                    weights.push(p);
                }
            }
        }
        (!ids.is_empty()).then(|| BrightCells {
            mask,
            dist: Distribution1D::new(&weights),
            ids,
        })
    }

    /// A world direction drawn from the bright cells alone (each by its share of the map's
    /// energy, uniform in (u, v) within it), with its solid-angle density.
    #[inline]
    pub fn sample_bright(&self, b: &BrightCells, u: Vec2) -> Option<(Vec3, f32)> {
        let (k, p, ux) = b.dist.sample_discrete(u.x);
        let cell = b.ids[k] as usize;
        let (w, rows) = (self.width, self.height - 1);
        let (i, j) = (cell % w, cell / w);
        // Cells start at the first column's centre, as in `sample`.
        let uu = (i as f32 + ux + 0.5) / w as f32;
        let v = (j as f32 + u.y) / rows as f32;
        let (sin_t, cos_t) = sin_cos_turns(0.5 * v);
        let (sin_p, cos_p) = sin_cos_turns(uu);
        if sin_t <= 0.0 {
            return None;
        }
        let local = Vec3::new(sin_p * sin_t, cos_t, -cos_p * sin_t);
        let pdf = p * (w * rows) as f32 / (2.0 * PI * PI * sin_t);
        (pdf > 0.0 && pdf.is_finite()).then(|| ((self.to_world * local).normalize(), pdf))
    }
}

/// A set of an environment map's sampling cells (`EnvMap::bright_cells`), with a distribution
/// over them by energy.
#[derive(Clone, Debug)]
pub struct BrightCells {
    mask: Vec<bool>,
    ids: Vec<u32>,
    dist: Distribution1D,
}

impl BrightCells {
    /// True if cell `cell` (`EnvMap::cell`) is in the set.
    #[inline]
    pub fn contains(&self, cell: usize) -> bool {
        self.mask[cell]
    }

    /// Number of cells in the set.
    pub fn len(&self) -> usize {
        self.ids.len()
    }

    pub fn is_empty(&self) -> bool {
        self.ids.is_empty()
    }
}

#[cfg(test)]
#[path = "envmap_tests.rs"]
mod tests;
