//! Textures: material parameters that vary over a surface. A spectral texture yields a
//! spectrum at the path's wavelengths for a uv; RGB bitmaps are uplifted to Jakob–Hanika sigmoid
//! coefficients once, at load, so a lookup costs a few flops per texel and lane.
//!
//! Texture space as Mitsuba 3: (u, v) = (0, 0) is the image's first (top) row and first column;
//! `uv_scale` and `uv_offset` map surface uv to texture space (uv · scale + offset).

use crate::math::float;
use crate::spectrum::rgb2spec::Sigmoid;
use crate::spectrum::{Curve, Spectrum, Wavelengths};
use glam::Vec2;
use serde::{Deserialize, Serialize};

mod rgb_image;
mod vertex;
pub use rgb_image::{load_rgb, srgb_decode, RgbImage, TexelRange};
pub use vertex::{TexPoint, VertexAlpha, VertexColors};

/// How texture coordinates outside [0, 1) are treated.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Wrap {
    #[default]
    Repeat,
    Clamp,
}

/// How texels are interpolated.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum TexFilter {
    #[default]
    Bilinear,
    Nearest,
}

/// Where a texture sits on the surface: uv ↦ R(θ) · (uv · scale) + offset, with R(θ) =
/// [[cos θ, sin θ], [−sin θ, cos θ]] (KHR_texture_transform's order and sense; θ = 0 from RON).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UvMap {
    pub scale: Vec2,
    pub offset: Vec2,
    /// (cos θ, sin θ); `Vec2::X` for none.
    pub rotation: Vec2,
}

impl UvMap {
    /// No scale, offset or rotation.
    pub const IDENTITY: UvMap = UvMap {
        scale: Vec2::ONE,
        offset: Vec2::ZERO,
        rotation: Vec2::X,
    };

    #[inline]
    fn apply(&self, uv: Vec2) -> Vec2 {
        let s = uv * self.scale;
        let (c, r) = (self.rotation.x, self.rotation.y);
        Vec2::new(c * s.x + r * s.y, c * s.y - r * s.x) + self.offset
    }
}

/// A grid of values addressed by texture coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid<T> {
    pub width: usize,
    pub height: usize,
    pub texels: Vec<T>,
    /// Along u (and v unless `wrap_v` says otherwise).
    pub wrap: Wrap,
    /// Along v: glTF's samplers set wrapS and wrapT apart; RON textures use `wrap` for both.
    pub wrap_v: Wrap,
    pub filter: TexFilter,
    pub map: UvMap,
    /// The image file it came from (for exporting the scene to other renderers).
    pub source: Option<ImageSource>,
}

/// Where an image came from and how it was read.
#[derive(Clone, Debug, PartialEq)]
pub struct ImageSource {
    pub path: std::path::PathBuf,
    /// 8-bit values taken as they are (not sRGB-decoded).
    pub raw: bool,
}

impl<T: Copy> Grid<T> {
    /// The (up to) four texels around `uv` with their bilinear weights.
    #[inline]
    pub(crate) fn taps(&self, uv: Vec2) -> [(T, f32); 4] {
        let p = self.map.apply(uv);
        let (w, h) = (self.width as f32, self.height as f32);
        match self.filter {
            TexFilter::Nearest => {
                let t = self.texels[self.index(p.x * w, p.y * h)];
                [(t, 1.0), (t, 0.0), (t, 0.0), (t, 0.0)]
            }
            TexFilter::Bilinear => {
                let (x, y) = (p.x * w - 0.5, p.y * h - 0.5);
                let (x0, y0) = (float::floor(x), float::floor(y));
                let (fx, fy) = (x - x0, y - y0);
                [
                    (self.texels[self.index(x0, y0)], (1.0 - fx) * (1.0 - fy)),
                    (self.texels[self.index(x0 + 1.0, y0)], fx * (1.0 - fy)),
                    (self.texels[self.index(x0, y0 + 1.0)], (1.0 - fx) * fy),
                    (self.texels[self.index(x0 + 1.0, y0 + 1.0)], fx * fy),
                ]
            }
        }
    }

    #[inline]
    fn index(&self, x: f32, y: f32) -> usize {
        let wrap = |v: f32, n: usize, mode: Wrap| -> usize {
            let i = if v.is_finite() {
                float::floor(v) as i64
            } else {
                0
            };
            match mode {
                Wrap::Repeat => float::wrap_index(i, n),
                Wrap::Clamp => i.clamp(0, n as i64 - 1) as usize,
            }
        };
        wrap(y, self.height, self.wrap_v) * self.width + wrap(x, self.width, self.wrap)
    }
}

impl Grid<glam::Vec3> {
    /// The interpolated vector at `uv` (normal maps).
    #[inline]
    pub fn eval_vec3(&self, uv: Vec2) -> glam::Vec3 {
        self.taps(uv).iter().map(|(v, w)| *v * *w).sum()
    }
}

/// A spectral parameter: uniform, checkerboard, or an RGB bitmap (bounded reflectance).
#[derive(Clone, Debug, PartialEq)]
pub enum SpectralTexture {
    Uniform(Curve),
    /// `color0` where frac(u) and frac(v) fall in the same half, `color1` elsewhere (Mitsuba's).
    Checkerboard {
        color0: Curve,
        color1: Curve,
        map: UvMap,
    },
    Bitmap(Box<Grid<Sigmoid>>),
    /// A texture times per-vertex colours (glTF `COLOR_0`).
    Vertex(Box<VertexColors>),
}

impl SpectralTexture {
    /// The value at `at` (a uv, or a hit's `TexPoint` for per-vertex data) and the path's
    /// wavelengths. A uniform spectrum (most parameters of most scenes) is looked up inline;
    /// textures go through `eval_varying`, out of line, so a scene without textures pays
    /// nothing for them.
    #[inline]
    pub fn eval<const N: usize>(
        &self,
        at: impl Into<TexPoint>,
        wl: &Wavelengths<N>,
    ) -> Spectrum<N> {
        match self {
            SpectralTexture::Uniform(c) => c.eval(wl),
            _ => self.eval_varying(at.into(), wl),
        }
    }

    #[inline(never)]
    fn eval_varying<const N: usize>(&self, at: TexPoint, wl: &Wavelengths<N>) -> Spectrum<N> {
        let uv = at.uv;
        match self {
            SpectralTexture::Vertex(v) => v.eval(at, wl),
            SpectralTexture::Uniform(c) => c.eval(wl),
            SpectralTexture::Checkerboard {
                color0,
                color1,
                map,
            } => {
                if checker(map.apply(uv)) {
                    color0.eval(wl)
                } else {
                    color1.eval(wl)
                }
            }
            SpectralTexture::Bitmap(g) => {
                let taps = g.taps(uv);
                Spectrum::from_fn(|i| {
                    taps.iter()
                        .map(|(s, w)| {
                            if *w > 0.0 {
                                w * s.eval(wl.lambda[i])
                            } else {
                                0.0
                            }
                        })
                        .sum()
                })
            }
        }
    }

    /// The mean value over the surface and over [lo, hi] nm (steers sampling between lobes;
    /// bitmaps are averaged over at most ~4096 evenly spread texels).
    pub fn mean(&self, lo: f32, hi: f32) -> f32 {
        match self {
            SpectralTexture::Uniform(c) => c.average(lo, hi),
            SpectralTexture::Checkerboard { color0, color1, .. } => {
                0.5 * (color0.average(lo, hi) + color1.average(lo, hi))
            }
            SpectralTexture::Bitmap(g) => {
                let step = (g.texels.len() / 4096).max(1);
                let picked: Vec<&Sigmoid> = g.texels.iter().step_by(step).collect();
                let n = 16;
                let sum: f32 = picked
                    .iter()
                    .map(|s| {
                        (0..n)
                            .map(|i| s.eval(lo + (i as f32 + 0.5) * (hi - lo) / n as f32))
                            .sum::<f32>()
                            / n as f32
                    })
                    .sum();
                sum / picked.len() as f32
            }
            SpectralTexture::Vertex(v) => v.mean(lo, hi),
        }
    }

    /// The largest value the texture takes at any point and wavelength in [lo, hi] (for checks).
    pub fn max_value(&self, lo: f32, hi: f32) -> f32 {
        match self {
            SpectralTexture::Uniform(c) => c.min_max(lo, hi).1,
            SpectralTexture::Checkerboard { color0, color1, .. } => {
                color0.min_max(lo, hi).1.max(color1.min_max(lo, hi).1)
            }
            // Bounded sigmoids never exceed 1.
            SpectralTexture::Bitmap(_) => 1.0,
            SpectralTexture::Vertex(v) => v.base.max_value(lo, hi),
        }
    }
}

/// A scalar parameter (a blend weight, an opacity).
#[derive(Clone, Debug, PartialEq)]
pub enum FloatTexture {
    Constant(f32),
    Checkerboard {
        value0: f32,
        value1: f32,
        map: UvMap,
    },
    Bitmap(Box<Grid<f32>>),
    /// An opacity times per-vertex alphas (glTF `COLOR_0`'s alpha).
    Vertex(Box<VertexAlpha>),
}

impl FloatTexture {
    /// The value at `at` (a uv, or a hit's `TexPoint` for per-vertex data).
    #[inline]
    pub fn eval(&self, at: impl Into<TexPoint>) -> f32 {
        let at = at.into();
        let uv = at.uv;
        match self {
            FloatTexture::Vertex(v) => v.eval(at),
            FloatTexture::Constant(v) => *v,
            FloatTexture::Checkerboard {
                value0,
                value1,
                map,
            } => {
                if checker(map.apply(uv)) {
                    *value0
                } else {
                    *value1
                }
            }
            FloatTexture::Bitmap(g) => g.taps(uv).iter().map(|(v, w)| v * w).sum(),
        }
    }
}

#[inline]
fn checker(p: Vec2) -> bool {
    (p.x - float::floor(p.x) > 0.5) == (p.y - float::floor(p.y) > 0.5)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checkerboard_and_wrap() {
        let map = UvMap::IDENTITY;
        let t = FloatTexture::Checkerboard {
            value0: 1.0,
            value1: 0.0,
            map,
        };
        assert_eq!(t.eval(Vec2::new(0.25, 0.25)), 1.0);
        assert_eq!(t.eval(Vec2::new(0.75, 0.25)), 0.0);
        assert_eq!(t.eval(Vec2::new(1.75, 0.75)), 1.0);
        let g = Grid {
            source: None,
            width: 2,
            height: 1,
            texels: vec![0.0f32, 1.0],
            wrap: Wrap::Repeat,
            wrap_v: Wrap::Repeat,
            filter: TexFilter::Bilinear,
            map,
        };
        let b = FloatTexture::Bitmap(Box::new(g.clone()));
        // Texel centres at u = 0.25 and 0.75; halfway between them is 0.5.
        assert!((b.eval(Vec2::new(0.25, 0.5)) - 0.0).abs() < 1e-6);
        assert!((b.eval(Vec2::new(0.5, 0.5)) - 0.5).abs() < 1e-6);
        // Repeat wraps u = 1.0 back to the first texel's neighbourhood.
        assert!((b.eval(Vec2::new(1.0, 0.5)) - 0.5).abs() < 1e-6);
        let clamp = FloatTexture::Bitmap(Box::new(Grid {
            wrap: Wrap::Clamp,
            wrap_v: Wrap::Clamp,
            ..g
        }));
        assert!((clamp.eval(Vec2::new(1.0, 0.5)) - 1.0).abs() < 1e-6);
    }
}
