//! Per-vertex data on a texture: glTF's `COLOR_0`, which multiplies the base colour and its
//! alpha. A hit names its triangle and barycentrics (`TexPoint`); the three corners' values are
//! blended with them, as the vertex colour is interpolated in glTF (§3.7.2.1).
//!
//! Colours are uplifted per vertex (each corner a bounded Jakob–Hanika sigmoid) and the corner
//! spectra blended, so the result stays a reflectance in [0, 1]; a texture under the vertex
//! colour multiplies it (`VertexColors::base`).

use super::{FloatTexture, SpectralTexture};
use crate::spectrum::rgb2spec::Sigmoid;
use crate::spectrum::{Spectrum, Wavelengths};
use glam::Vec2;

/// Where a texture is read: texture coordinates, and the triangle and barycentrics (b1, b2) of
/// the hit for per-vertex data (`prim` = `u32::MAX` where there is no hit: such a lookup takes
/// the corners' mean, see `VertexColors::eval`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TexPoint {
    pub uv: Vec2,
    pub prim: u32,
    pub bary: Vec2,
}

impl From<Vec2> for TexPoint {
    #[inline(always)]
    fn from(uv: Vec2) -> Self {
        TexPoint {
            uv,
            prim: u32::MAX,
            bary: Vec2::splat(1.0 / 3.0),
        }
    }
}

impl TexPoint {
    /// The weights of corners 0, 1 and 2.
    #[inline]
    fn weights(&self) -> [f32; 3] {
        [1.0 - self.bary.x - self.bary.y, self.bary.x, self.bary.y]
    }
}

/// A base colour times per-vertex colours.
#[derive(Clone, Debug, PartialEq)]
pub struct VertexColors {
    /// Each triangle's corner colours, in the order of the shape's barycentrics.
    pub corners: Vec<[Sigmoid; 3]>,
    /// What the vertex colour multiplies: a bitmap (factor × texel, uplifted per texel), or
    /// `Uniform(1)` where the factor was folded into the corners.
    pub base: SpectralTexture,
}

impl VertexColors {
    #[inline(never)]
    pub fn eval<const N: usize>(&self, at: TexPoint, wl: &Wavelengths<N>) -> Spectrum<N> {
        let base = self.base.eval(at, wl);
        // No hit to read: the first triangle's mean (never reached by a render; every
        // material lookup passes its hit).
        let Some((w, corners)) = pick(&self.corners, at) else {
            return base;
        };
        Spectrum::from_fn(|i| {
            let l = wl.lambda[i];
            let c: f32 = (0..3).map(|k| w[k] * corners[k].eval(l)).sum();
            base[i] * c.clamp(0.0, 1.0)
        })
    }

    /// The mean over triangles (unweighted by area) and wavelengths in [lo, hi].
    pub fn mean(&self, lo: f32, hi: f32) -> f32 {
        let n = 16;
        let step = (self.corners.len() / 4096).max(1);
        let picked: Vec<&[Sigmoid; 3]> = self.corners.iter().step_by(step).collect();
        let sum: f32 = picked
            .iter()
            .flat_map(|c| c.iter())
            .map(|s| {
                (0..n)
                    .map(|i| s.eval(lo + (i as f32 + 0.5) * (hi - lo) / n as f32))
                    .sum::<f32>()
                    / n as f32
            })
            .sum();
        self.base.mean(lo, hi) * sum / (3 * picked.len()) as f32
    }
}

/// An opacity times per-vertex alphas, then cut at `cutoff` (glTF's MASK) if it has one.
#[derive(Clone, Debug, PartialEq)]
pub struct VertexAlpha {
    pub corners: Vec<[f32; 3]>,
    /// Texel alpha × factor alpha (uncut).
    pub base: FloatTexture,
    pub cutoff: Option<f32>,
}

impl VertexAlpha {
    #[inline(never)]
    pub fn eval(&self, at: TexPoint) -> f32 {
        let base = self.base.eval(at);
        let a = match pick(&self.corners, at) {
            Some((w, c)) => base * (w[0] * c[0] + w[1] * c[1] + w[2] * c[2]),
            None => base,
        };
        match self.cutoff {
            Some(cut) => {
                if a >= cut {
                    1.0
                } else {
                    0.0
                }
            }
            None => a,
        }
    }
}

/// The corners of the hit's triangle and their weights; without a hit, the first triangle's
/// with equal weights.
#[inline]
fn pick<T>(corners: &[T], at: TexPoint) -> Option<([f32; 3], &T)> {
    match corners.get(at.prim as usize) {
        Some(c) => Some((at.weights(), c)),
        None => corners.first().map(|c| ([1.0 / 3.0; 3], c)),
    }
}
