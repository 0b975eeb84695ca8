//! Decoded images: reading PNG, JPEG, OpenEXR and Radiance HDR files into linear RGB, checking
//! their texels' range, and uplifting them into the textures of `super`.

use super::*;
use crate::io::input_file;
use crate::math::portable;
use crate::spectrum::gamut::Gamut;
use crate::spectrum::rgb2spec::{self, Sigmoid};

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
    crate::io::inputs::record(path);
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let name = path.display();
    if !path.exists() {
        return Err(format!("image `{name}` does not exist"));
    }
    if ext.as_deref() == Some("exr") {
        // The size is checked on the header before any pixel is decoded: the decoder allocates
        // each block from the data window, so a window of 570425472 × 64 asked for 54 GB and
        // aborted the process (fuzz run 9, corpus case exr_huge_data_window).
        let header = input_file::open(path, input_file::Kind::Texture)?;
        let meta = exr::meta::MetaData::read_from_buffered(std::io::BufReader::new(header), false)
            .map_err(|e| format!("`{name}`: cannot read OpenEXR: {e}"))?;
        for h in meta.headers.iter() {
            check_texels(path, h.layer_size.0, h.layer_size.1)?;
        }
        // (width, height, pixels): the reader hands us the size first, then every pixel.
        type Store = (usize, usize, Vec<[f32; 3]>);
        let file = input_file::open(path, input_file::Kind::Texture)?;
        use exr::prelude::{ReadChannels, ReadLayers};
        let img = exr::prelude::read()
            .no_deep_data()
            .largest_resolution_level()
            .rgba_channels(
                |res, _| -> Store { (res.0, res.1, vec![[0.0; 3]; res.0 * res.1]) },
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
        portable::powf((v + 0.055) / 1.055, 2.4)
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
    /// An emitted radiance: every component finite and ≥ 0 (unbounded above).
    Radiance,
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
            let component = |ok: &dyn Fn(f32) -> bool| {
                (0..3)
                    .find(|&c| !ok(p[c]))
                    .map(|c| format!("{} = {}", ["R", "G", "B"][c], p[c]))
            };
            let (problem, what, bound) = match range {
                TexelRange::Reflectance => (component(&in01), "a reflectance", "in [0, 1]"),
                TexelRange::Fraction => (
                    (!in01(y)).then(|| format!("luminance {y}")),
                    "an opacity or blend weight",
                    "in [0, 1]",
                ),
                TexelRange::Finite => (
                    (!y.is_finite()).then(|| format!("luminance {y}")),
                    "a roughness",
                    "finite",
                ),
                TexelRange::Radiance => (
                    component(&|v: f32| v.is_finite() && v >= 0.0),
                    "an emitted radiance",
                    "finite and ≥ 0",
                ),
            };
            if let Some(value) = problem {
                let name = self
                    .source
                    .as_ref()
                    .map_or("the image".into(), |s| format!("`{}`", s.path.display()));
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
            wrap_v: wrap,
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
            wrap_v: wrap,
            filter,
            map,
            source: self.source.clone(),
        }
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
