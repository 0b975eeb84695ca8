//! The preview animation of a video dataset (`OUT/sequences.png`): an animated PNG (APNG,
//! which browsers and GitHub play) whose frame k shows frame k of every sequence side by side
//! (up to [`MAX_SEQUENCES`]), at the dataset's fps, looping. Written atomically after each run
//! that has sequences and previews, from the previews of the sequences the manifest lists whole.
//!
//! APNG through the `png` crate prism already uses, rather than GIF: a GIF encoder would be a
//! new dependency (`image`'s `gif` feature), and GIF's 256 colours band the smooth shading.

use crate::error::Error;
use image::{imageops, RgbImage};
use std::path::{Path, PathBuf};

/// At most this many sequences side by side (the first ones).
pub const MAX_SEQUENCES: usize = 8;
const GAP: u32 = 2;
const GAP_GREY: u8 = 40;

/// Writes the animation of `sequences` (each its frames' preview PNGs, in order; every one
/// the same length) at `fps` into `path`; None when there is nothing to show.
pub fn write(sequences: &[Vec<PathBuf>], fps: f32, path: &Path) -> Result<Option<PathBuf>, Error> {
    let seqs: Vec<&Vec<PathBuf>> = sequences.iter().take(MAX_SEQUENCES).collect();
    let Some(frames) = seqs.first().map(|s| s.len()).filter(|&n| n > 0) else {
        return Ok(None);
    };
    let open = |p: &Path| -> Result<RgbImage, Error> {
        image::open(p)
            .map(|img| img.to_rgb8())
            .map_err(|e| Error::Other(format!("preview animation: reading {}: {e}", p.display())))
    };
    let (tw, th) = open(&seqs[0][0])?.dimensions();
    let n = seqs.len() as u32;
    let (width, height) = (n * (tw + GAP) + GAP, th + 2 * GAP);
    // Every frame of the animation, read before the file is opened (a few small previews).
    let mut canvases = Vec::with_capacity(frames);
    for k in 0..frames {
        let mut c = RgbImage::from_pixel(width, height, image::Rgb([GAP_GREY; 3]));
        for (s, seq) in seqs.iter().enumerate() {
            let tile = open(&seq[k])?;
            let fit = imageops::crop_imm(&tile, 0, 0, tw.min(tile.width()), th.min(tile.height()));
            imageops::replace(
                &mut c,
                &*fit,
                (GAP + s as u32 * (tw + GAP)) as i64,
                GAP as i64,
            );
        }
        canvases.push(c);
    }
    // The frame delay as a fraction: 1000 / (1000·fps) seconds, fps to a thousandth.
    let den = (fps * 1000.0).round().clamp(1.0, u16::MAX as f32) as u16;
    crate::output::write_atomic(path, |tmp| {
        let file = std::fs::File::create(tmp).map_err(|e| e.to_string())?;
        let mut enc = png::Encoder::new(std::io::BufWriter::new(file), width, height);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let e = |e: png::EncodingError| e.to_string();
        enc.set_animated(frames as u32, 0).map_err(e)?;
        enc.set_frame_delay(1000, den).map_err(e)?;
        let mut w = enc.write_header().map_err(e)?;
        for c in &canvases {
            w.write_image_data(c.as_raw()).map_err(e)?;
        }
        w.finish().map_err(e)
    })?;
    Ok(Some(path.to_path_buf()))
}
