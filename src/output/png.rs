//! 8-bit sRGB PNG previews of the linear RGB image.

use crate::error::Error;
use crate::film::Film;
use crate::math::portable;
use crate::spectrum::color::{srgb_encode, XYZ_TO_SRGB};
use glam::Vec3;
use rayon::prelude::*;
use std::path::Path;

/// Writes an sRGB preview scaled by 2^`exposure` (atomically). Uses R, G, B if the film has
/// them, else converts X, Y, Z.
pub fn write(film: &Film, path: &Path, exposure: f32) -> Result<(), Error> {
    let n = (film.width * film.height) as usize;
    let rgb: Vec<Vec3> = match (film.channel("R"), film.channel("G"), film.channel("B")) {
        (Some(r), Some(g), Some(b)) => (0..n).map(|i| Vec3::new(r[i], g[i], b[i])).collect(),
        _ => match (film.channel("X"), film.channel("Y"), film.channel("Z")) {
            (Some(x), Some(y), Some(z)) => (0..n)
                .map(|i| XYZ_TO_SRGB * Vec3::new(x[i], y[i], z[i]))
                .collect(),
            _ => {
                return Err(Error::Other(
                    "a PNG preview needs the rgb or xyz output".into(),
                ))
            }
        },
    };
    let scale = portable::exp2(exposure);
    let encode = |v: f32| (srgb_encode(v * scale).clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
    // Over the threads: a `powf` per value, one thread's alone was 2% of a dataset frame.
    let bytes: Vec<u8> = rgb
        .par_iter()
        .with_min_len(1024)
        .flat_map_iter(|c| c.to_array().map(encode))
        .collect();
    let img = image::RgbImage::from_raw(film.width, film.height, bytes)
        .expect("buffer matches the film size");
    super::write_atomic(path, |tmp| {
        img.save_with_format(tmp, image::ImageFormat::Png)
            .map_err(|e| e.to_string())
    })
}
