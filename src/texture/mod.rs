//! Textures: material parameters that vary over a surface. A spectral texture yields a
//! spectrum at the path's wavelengths for a uv; RGB bitmaps are uplifted to Jakob–Hanika sigmoid
//! coefficients once, at load, so a lookup costs a few flops per texel and lane.
//!
//! Texture space as Mitsuba 3: (u, v) = (0, 0) is the image's first (top) row and first column;
//! `uv_scale` and `uv_offset` map surface uv to texture space (uv · scale + offset).

use crate::config::input_file;
use crate::spectrum::gamut::Gamut;
use crate::spectrum::rgb2spec::{self, Sigmoid};
use crate::spectrum::{Curve, Spectrum, Wavelengths};
use glam::Vec2;
use serde::{Deserialize, Serialize};

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
    pub wrap: Wrap,
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
                let (x0, y0) = (x.floor(), y.floor());
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
        let wrap = |v: f32, n: usize| -> usize {
            let i = if v.is_finite() { v.floor() as i64 } else { 0 };
            match self.wrap {
                Wrap::Repeat => i.rem_euclid(n as i64) as usize,
                Wrap::Clamp => i.clamp(0, n as i64 - 1) as usize,
            }
        };
        wrap(y, self.height) * self.width + wrap(x, self.width)
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
}

impl SpectralTexture {
    /// The value at `uv` and the path's wavelengths. A uniform spectrum (most parameters of
    /// most scenes) is looked up inline; textures go through `eval_varying`, out of line, so a
    /// scene without textures pays nothing for them.
    #[inline]
    pub fn eval<const N: usize>(&self, uv: Vec2, wl: &Wavelengths<N>) -> Spectrum<N> {
        match self {
            SpectralTexture::Uniform(c) => c.eval(wl),
            _ => self.eval_varying(uv, wl),
        }
    }

    #[inline(never)]
    fn eval_varying<const N: usize>(&self, uv: Vec2, wl: &Wavelengths<N>) -> Spectrum<N> {
        match self {
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
}

impl FloatTexture {
    #[inline]
    pub fn eval(&self, uv: Vec2) -> f32 {
        match self {
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
    (p.x - p.x.floor() > 0.5) == (p.y - p.y.floor() > 0.5)
}

/// A decoded image: linear RGB, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct RgbImage {
    pub width: usize,
    pub height: usize,
    pub pixels: Vec<[f32; 3]>,
    pub source: Option<ImageSource>,
}

/// Reads a PNG/JPEG (8/16-bit; sRGB-decoded unless `raw`), OpenEXR (linear) or Radiance HDR
/// (linear) image. Errors are plain messages naming the file.
pub fn load_rgb(path: &std::path::Path, raw: bool) -> Result<RgbImage, String> {
    crate::scene::inputs::record(path);
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let name = path.display();
    if !path.exists() {
        return Err(format!("image `{name}` does not exist"));
    }
    if ext.as_deref() == Some("exr") {
        // (width, pixels): the reader hands us the size first, then every pixel.
        // (width, pixels): the reader hands us the size first, then every pixel. A size over
        // the texel limit gets no storage (and the image is refused below).
        type Store = (usize, usize, Vec<[f32; 3]>);
        let file = input_file::open(path, input_file::Kind::Texture)?;
        use exr::prelude::{ReadChannels, ReadLayers};
        let img = exr::prelude::read()
            .no_deep_data()
            .largest_resolution_level()
            .rgba_channels(
                |res, _| -> Store {
                    let n = res.0 as u64 * res.1 as u64;
                    let keep = n <= input_file::MAX_TEXELS;
                    let store = if keep {
                        vec![[0.0; 3]; n as usize]
                    } else {
                        Vec::new()
                    };
                    (res.0, res.1, store)
                },
                |s: &mut Store, pos, (r, g, b, _a): (f32, f32, f32, f32)| {
                    if let Some(p) = s.2.get_mut(pos.1 * s.0 + pos.0) {
                        *p = [r, g, b]
                    }
                },
            )
            .first_valid_layer()
            .all_attributes()
            .from_buffered(std::io::BufReader::new(file))
            .map_err(|e| format!("`{name}`: cannot read OpenEXR: {e}"))?;
        let (width, height, pixels) = img.layer_data.channel_data.pixels;
        check_texels(path, width, height)?;
        let source = Some(ImageSource {
            path: path.to_path_buf(),
            raw,
        });
        return Ok(RgbImage {
            width,
            height,
            pixels,
            source,
        });
    }
    let file = input_file::open(path, input_file::Kind::Texture)?;
    let mut reader = image::ImageReader::new(std::io::BufReader::new(file));
    match image::ImageFormat::from_path(path) {
        Ok(f) => reader.set_format(f),
        Err(_) => {
            reader = reader
                .with_guessed_format()
                .map_err(|e| format!("`{name}`: cannot read image: {e}"))?
        }
    }
    let img = reader
        .decode()
        .map_err(|e| format!("`{name}`: cannot read image: {e}"))?;
    check_texels(path, img.width() as usize, img.height() as usize)?;
    let linear = ext.as_deref() == Some("hdr");
    let rgb = img.to_rgb32f();
    let (width, height) = (rgb.width() as usize, rgb.height() as usize);
    let decode = |v: f32| if raw || linear { v } else { srgb_decode(v) };
    let pixels = rgb
        .pixels()
        .map(|p| [decode(p[0]), decode(p[1]), decode(p[2])])
        .collect();
    let source = Some(ImageSource {
        path: path.to_path_buf(),
        raw,
    });
    Ok(RgbImage {
        width,
        height,
        pixels,
        source,
    })
}

fn check_texels(path: &std::path::Path, width: usize, height: usize) -> Result<(), String> {
    if width as u64 * height as u64 > input_file::MAX_TEXELS {
        return Err(format!(
            "`{}` is {width}×{height} pixels, more than the {} (16384 × 8192) prism reads for \
             one image (scenes/README.md, \"Input files\"); downsample it",
            path.display(),
            input_file::MAX_TEXELS
        ));
    }
    Ok(())
}

/// Rec. 709 luminance of linear RGB.
#[inline]
fn luminance(p: [f32; 3]) -> f32 {
    0.212_672_9 * p[0] + 0.715_152_2 * p[1] + 0.072_175 * p[2]
}

/// The sRGB transfer function's inverse.
#[inline]
pub fn srgb_decode(v: f32) -> f32 {
    if v <= 0.040_45 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

/// What an image's texels must be for the parameter it gives, checked at load.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TexelRange {
    /// A reflectance: every component finite and in [0, 1].
    Reflectance,
    /// An opacity or a blend weight: the luminance finite and in [0, 1].
    Fraction,
    /// The luminance finite (a roughness, clamped where it is used).
    Finite,
}

/// Rounding of an 8-bit white's sRGB decode and luminance weights may pass 1 by an ulp or two.
const RANGE_SLACK: f32 = 1e-4;

impl RgbImage {
    /// Refuses the first texel outside `range`, naming the file, the texel (x, y, from the top
    /// left) and its value, with the fix.
    pub fn validate(&self, range: TexelRange) -> Result<(), String> {
        let in01 = |v: f32| (0.0..=1.0 + RANGE_SLACK).contains(&v);
        for (i, p) in self.pixels.iter().enumerate() {
            let y = luminance(*p);
            let problem = match range {
                TexelRange::Reflectance => (0..3).find(|&c| !in01(p[c])).map(|c| {
                    (
                        format!("{} = {}", ["R", "G", "B"][c], p[c]),
                        "a reflectance",
                    )
                }),
                TexelRange::Fraction => {
                    (!in01(y)).then(|| (format!("luminance {y}"), "an opacity or blend weight"))
                }
                TexelRange::Finite => {
                    (!y.is_finite()).then(|| (format!("luminance {y}"), "a roughness"))
                }
            };
            if let Some((value, what)) = problem {
                let name = self
                    .source
                    .as_ref()
                    .map_or("the image".into(), |s| format!("`{}`", s.path.display()));
                let bound = if range == TexelRange::Finite {
                    "finite"
                } else {
                    "in [0, 1]"
                };
                return Err(format!(
                    "{name}: texel ({}, {}) has {value}, but {what} must be {bound}; fix or \
                     rescale the image (an 8-bit PNG always is in range)",
                    i % self.width.max(1),
                    i / self.width.max(1)
                ));
            }
        }
        Ok(())
    }

    /// Uplifts every texel to a bounded reflectance spectrum (components clamped to [0, 1]).
    pub fn to_reflectance(&self, wrap: Wrap, filter: TexFilter, map: UvMap) -> Grid<Sigmoid> {
        self.to_reflectance_in(Gamut::Srgb, wrap, filter, map)
    }

    /// [`RgbImage::to_reflectance`] for texels in the RGB space `gamut`.
    pub fn to_reflectance_in(
        &self,
        gamut: Gamut,
        wrap: Wrap,
        filter: TexFilter,
        map: UvMap,
    ) -> Grid<Sigmoid> {
        let texels = self
            .pixels
            .iter()
            .map(|p| rgb2spec::fetch_in(gamut, p.map(|c| c.clamp(0.0, 1.0))))
            .collect();
        Grid {
            width: self.width,
            height: self.height,
            texels,
            wrap,
            filter,
            map,
            source: self.source.clone(),
        }
    }

    /// Luminance (Rec. 709 weights) of every texel, for scalar parameters.
    pub fn to_luminance(&self, wrap: Wrap, filter: TexFilter, map: UvMap) -> Grid<f32> {
        let texels = self.pixels.iter().map(|p| luminance(*p)).collect();
        Grid {
            width: self.width,
            height: self.height,
            texels,
            wrap,
            filter,
            map,
            source: self.source.clone(),
        }
    }
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
            ..g
        }));
        assert!((clamp.eval(Vec2::new(1.0, 0.5)) - 1.0).abs() < 1e-6);
    }
}

#[cfg(test)]
mod bitmap_tests {
    use super::*;
    use crate::spectrum::{WavelengthSampler, WavelengthSampling};

    /// A 2×1 PNG (sRGB 8-bit) read back: values are sRGB-decoded (or not, when `raw`), and the
    /// uplifted spectra reproduce the texels' luminance under D65 within 1e-3 (the uplifting
    /// table's accuracy).
    #[test]
    fn png_round_trip() {
        let dir = std::env::temp_dir().join(format!("prism-tex-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("t.png");
        let img = image::RgbImage::from_raw(2, 1, vec![255, 128, 0, 10, 200, 30]).unwrap();
        img.save(&path).unwrap();
        let rgb = load_rgb(&path, false).unwrap();
        assert_eq!((rgb.width, rgb.height), (2, 1));
        assert!((rgb.pixels[0][1] - srgb_decode(128.0 / 255.0)).abs() < 1e-6);
        let raw = load_rgb(&path, true).unwrap();
        assert!((raw.pixels[0][1] - 128.0 / 255.0).abs() < 1e-6);
        let map = UvMap::IDENTITY;
        let tex = SpectralTexture::Bitmap(Box::new(rgb.to_reflectance(
            Wrap::Clamp,
            TexFilter::Nearest,
            map,
        )));
        let cmf = crate::spectrum::color::cie1931();
        let d65 = crate::spectrum::data::named_illuminant("D65").unwrap();
        let ws = WavelengthSampler::new(WavelengthSampling::Uniform, 360.0, 830.0);
        for (texel, u) in [(0usize, 0.25f32), (1, 0.75)] {
            // The reflectance's luminance under D65 is the texel's sRGB Y.
            let (mut y, mut norm) = (0.0f64, 0.0f64);
            for i in 0..2000 {
                let wl = ws.sample::<1>((i as f32 + 0.5) / 2000.0);
                let l = wl.lambda[0];
                let w = cmf.eval(l)[1] as f64 * d65.eval_one(l) as f64;
                y += tex.eval(Vec2::new(u, 0.5), &wl)[0] as f64 * w;
                norm += w;
            }
            let p = rgb.pixels[texel];
            let y_srgb = 0.212_672_9 * p[0] + 0.715_152_2 * p[1] + 0.072_175 * p[2];
            assert!(
                (y / norm - y_srgb as f64).abs() < 1e-3,
                "texel {texel}: {} vs {y_srgb}",
                y / norm
            );
        }
        assert!(load_rgb(&dir.join("missing.png"), false)
            .unwrap_err()
            .contains("does not exist"));
        std::fs::write(dir.join("bad.png"), b"not a png").unwrap();
        assert!(load_rgb(&dir.join("bad.png"), false)
            .unwrap_err()
            .contains("cannot read image"));
    }
}
