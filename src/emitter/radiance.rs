//! What an area light emits: one spectrum all over it (`Uniform`: a RON `emitter: (radiance:
//! ..)`, a glTF emissiveFactor), or a texture over the shape's uv (`Textured`: a glTF
//! emissiveTexture, a RON `Bitmap` radiance).
//!
//! Each texel's linear RGB (times the emitter's RGB factor) is uplifted once, at load, as an
//! illuminant exactly as a uniform RGB radiance is (`Curve::rgb_illuminant`: scale = 2·max(rgb),
//! the sigmoid of rgb/scale, times D65 at unit luminance), so a 1×1 texture emits what the same
//! RGB as a uniform radiance emits. A lookup interpolates the texels' radiance spectra (nearest
//! or bilinear), as Mitsuba 3's `bitmap` interpolates its texels' spectra; a black texel
//! (scale 0) contributes nothing.

use crate::spectrum::curve::Dense;
use crate::spectrum::gamut::Gamut;
use crate::spectrum::rgb2spec::{self, Sigmoid};
use crate::spectrum::{Curve, Spectrum, Wavelengths};
use crate::texture::{Grid, ImageSource, RgbImage, TexFilter, UvMap, Wrap};
use glam::Vec2;

/// An area light's radiance. A closed set: the path loop handles `Uniform` as before textured
/// emission existed (evaluated once per path, `path::LeMemo`), and only `Textured` per point.
#[derive(Clone, Debug)]
pub enum AreaRadiance {
    Uniform(Curve),
    Textured(Box<EmissionTexture>),
}

impl AreaRadiance {
    /// The radiance at surface coordinates `uv` (ignored when uniform).
    #[inline]
    pub fn eval<const N: usize>(&self, uv: Vec2, wl: &Wavelengths<N>) -> Spectrum<N> {
        match self {
            AreaRadiance::Uniform(c) => c.eval(wl),
            AreaRadiance::Textured(t) => t.eval(uv, wl),
        }
    }
}

/// One texel's uplifted RGB: radiance = `scale` × `sigmoid` × D65.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EmissionTexel {
    pub sigmoid: Sigmoid,
    pub scale: f32,
}

/// A radiance texture (see the module docs).
#[derive(Clone, Debug)]
pub struct EmissionTexture {
    grid: Grid<EmissionTexel>,
    /// Rec. 709 luminance of each texel's RGB (times the factor), placed like `grid`: the
    /// weights emitter sampling steers by.
    luminance: Grid<f32>,
    /// CIE D65 at unit luminance, shared by every texel.
    d65: Dense,
    /// The RGB factor the image's texels were multiplied by (for `prism export`).
    pub factor: [f32; 3],
}

/// Rec. 709 luminance of linear RGB.
fn luminance(c: [f32; 3]) -> f32 {
    0.212_672_9 * c[0] + 0.715_152_2 * c[1] + 0.072_175 * c[2]
}

impl EmissionTexture {
    /// Uplifts `image` (linear RGB in `gamut`, finite and ≥ 0: the loaders check) times
    /// `factor`, placed on the surface by `map`.
    pub fn new(
        gamut: Gamut,
        image: &RgbImage,
        factor: [f32; 3],
        wrap: [Wrap; 2],
        filter: TexFilter,
        map: UvMap,
    ) -> EmissionTexture {
        let rgb: Vec<[f32; 3]> = image
            .pixels
            .iter()
            .map(|p| [0, 1, 2].map(|k| (p[k] * factor[k]).max(0.0)))
            .collect();
        let texels = rgb
            .iter()
            .map(|c| {
                let m = c[0].max(c[1]).max(c[2]);
                if m > 0.0 {
                    // As `Curve::rgb_illuminant_in`.
                    let scale = 2.0 * m;
                    EmissionTexel {
                        sigmoid: rgb2spec::fetch_in(gamut, c.map(|v| v / scale)),
                        scale,
                    }
                } else {
                    EmissionTexel {
                        sigmoid: Sigmoid::BLACK,
                        scale: 0.0,
                    }
                }
            })
            .collect();
        let d65 = match crate::spectrum::data::named_illuminant("D65") {
            Some(Curve::Dense(d)) => d,
            _ => unreachable!("the embedded D65 table is evenly spaced"),
        };
        fn grid<T>(
            image: &RgbImage,
            texels: Vec<T>,
            w: [Wrap; 2],
            f: TexFilter,
            m: UvMap,
        ) -> Grid<T> {
            Grid {
                width: image.width,
                height: image.height,
                texels,
                wrap: w[0],
                wrap_v: w[1],
                filter: f,
                map: m,
                source: image.source.clone(),
            }
        }
        let lum = rgb.iter().map(|&c| luminance(c)).collect();
        EmissionTexture {
            grid: grid(image, texels, wrap, filter, map),
            luminance: grid(image, lum, wrap, filter, map),
            d65,
            factor,
        }
    }

    /// The image file, wrap, filter and uv map (for `prism export`).
    pub fn source(&self) -> Option<&ImageSource> {
        self.grid.source.as_ref()
    }

    pub fn placement(&self) -> (Wrap, TexFilter, UvMap) {
        (self.grid.wrap, self.grid.filter, self.grid.map)
    }

    /// (width, height) in texels.
    pub fn size(&self) -> (usize, usize) {
        (self.grid.width, self.grid.height)
    }

    /// The radiance at `uv`. Out of line: only textured lights call it.
    #[inline(never)]
    pub fn eval<const N: usize>(&self, uv: Vec2, wl: &Wavelengths<N>) -> Spectrum<N> {
        let mut acc = [0.0f32; N];
        let mut any = false;
        for (t, w) in self.grid.taps(uv) {
            let k = w * t.scale;
            if k > 0.0 {
                any = true;
                let s = t.sigmoid.eval_lanes(&wl.lambda);
                for (a, v) in acc.iter_mut().zip(s) {
                    *a += k * v;
                }
            }
        }
        if !any {
            return Spectrum::zero();
        }
        let d = self.d65.eval_lanes(&wl.lambda);
        Spectrum::from_fn(|i| acc[i] * d[i])
    }

    /// The luminance of the RGB radiance at `uv` (interpolated as `eval` interpolates).
    pub fn luminance_at(&self, uv: Vec2) -> f32 {
        self.luminance.taps(uv).iter().map(|(v, w)| v * w).sum()
    }

    /// The mean luminance over the triangle with corner uvs `uv` (at least 16 stratified
    /// points, about four per texel it covers, at most 4096): what emitter sampling weights
    /// the triangle by, times its area.
    pub fn mean_over_triangle(&self, uv: [Vec2; 3]) -> f32 {
        let (e1, e2) = (uv[1] - uv[0], uv[2] - uv[0]);
        let s = self.grid.map.scale;
        let texels = 0.5
            * (e1.x * e2.y - e1.y * e2.x).abs()
            * (s.x * s.y).abs()
            * (self.grid.width * self.grid.height) as f32;
        let n = ((4.0 * texels).sqrt().ceil() as usize).clamp(4, 64);
        let mut sum = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                let b = crate::math::sampling::square_to_triangle(u);
                let p = uv[0] * (1.0 - b.x - b.y) + uv[1] * b.x + uv[2] * b.y;
                sum += self.luminance_at(p) as f64;
            }
        }
        (sum / (n * n) as f64) as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 1×1 texture emits what the same RGB as a uniform radiance emits (the same uplift), at
    /// any uv and wavelength (f32 rounding of the four bilinear taps: 1e-6 relative); a black
    /// texel emits exactly nothing.
    #[test]
    fn one_texel_is_the_uniform_radiance() {
        let rgb = [3.0, 1.2, 0.4];
        let img = RgbImage {
            width: 1,
            height: 1,
            pixels: vec![rgb],
            source: None,
        };
        let factor = [2.0, 0.5, 1.0];
        let want = Curve::rgb_illuminant([6.0, 0.6, 0.4]);
        for filter in [TexFilter::Nearest, TexFilter::Bilinear] {
            let t = EmissionTexture::new(
                Gamut::Srgb,
                &img,
                factor,
                [Wrap::Repeat; 2],
                filter,
                UvMap::IDENTITY,
            );
            for (k, lambda) in [380.0f32, 455.5, 532.0, 611.25, 700.0, 829.0]
                .iter()
                .enumerate()
            {
                let wl = Wavelengths::<1> {
                    lambda: [*lambda],
                    pdf: [1.0],
                };
                let uv = Vec2::new(0.13 * k as f32, 0.71 - 0.2 * k as f32);
                let (got, exp) = (t.eval(uv, &wl)[0], want.eval(&wl)[0]);
                assert!(
                    (got - exp).abs() <= 1e-6 * exp,
                    "{filter:?} {lambda}: {got} vs {exp}"
                );
            }
        }
        let black = EmissionTexture::new(
            Gamut::Srgb,
            &RgbImage {
                pixels: vec![[0.0; 3]],
                ..img
            },
            factor,
            [Wrap::Repeat; 2],
            TexFilter::Bilinear,
            UvMap::IDENTITY,
        );
        let wl = Wavelengths::<4> {
            lambda: [400.0, 500.0, 600.0, 700.0],
            pdf: [1.0; 4],
        };
        assert!(black.eval(Vec2::splat(0.3), &wl).is_zero());
        assert_eq!(
            black.mean_over_triangle([Vec2::ZERO, Vec2::X, Vec2::Y]),
            0.0
        );
    }
}
