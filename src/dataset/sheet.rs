//! The contact sheet: every finished frame's preview PNG on one grid (`OUT/contact_sheet.png`),
//! so the first look at a dataset needs no other tool. Written atomically after each run.

use crate::error::Error;
use image::{imageops, RgbImage};
use std::path::{Path, PathBuf};

/// Grey between tiles, so frames with dark edges stay apart.
const GAP: u32 = 2;
const GAP_GREY: u8 = 40;
/// At most this many columns; tiles keep their size (frames are small by design).
const MAX_COLUMNS: u32 = 8;

/// Tiles the previews in `pngs` (frame order) into `path`; does nothing without previews.
pub fn write(pngs: &[PathBuf], path: &Path) -> Result<Option<PathBuf>, Error> {
    let mut tiles = Vec::with_capacity(pngs.len());
    for p in pngs {
        let img = image::open(p)
            .map_err(|e| Error::Other(format!("contact sheet: reading {}: {e}", p.display())))?;
        tiles.push(img.to_rgb8());
    }
    let Some(first) = tiles.first() else {
        return Ok(None);
    };
    let (tw, th) = first.dimensions();
    let n = tiles.len() as u32;
    let cols = (n as f64).sqrt().ceil().clamp(1.0, MAX_COLUMNS as f64) as u32;
    let rows = n.div_ceil(cols);
    let mut sheet = RgbImage::from_pixel(
        cols * (tw + GAP) + GAP,
        rows * (th + GAP) + GAP,
        image::Rgb([GAP_GREY; 3]),
    );
    for (k, t) in tiles.iter().enumerate() {
        let (c, r) = (k as u32 % cols, k as u32 / cols);
        // Frames of another size (a resolution variation) are placed as they are, clipped.
        imageops::replace(
            &mut sheet,
            t,
            (GAP + c * (tw + GAP)) as i64,
            (GAP + r * (th + GAP)) as i64,
        );
    }
    crate::output::write_atomic(path, |tmp| {
        sheet
            .save_with_format(tmp, image::ImageFormat::Png)
            .map_err(|e| e.to_string())
    })?;
    Ok(Some(path.to_path_buf()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Five 3×2 tiles go on a 3-column grid, each at its place with the gap around it.
    #[test]
    fn tiles_land_in_frame_order() {
        let dir = std::env::temp_dir().join(format!("prism-sheet-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let pngs: Vec<PathBuf> = (0..5u8)
            .map(|k| {
                let p = dir.join(format!("{k}.png"));
                RgbImage::from_pixel(3, 2, image::Rgb([k * 50, 0, 0]))
                    .save(&p)
                    .unwrap();
                p
            })
            .collect();
        let out = dir.join("sheet.png");
        write(&pngs, &out).unwrap();
        let s = image::open(&out).unwrap().to_rgb8();
        assert_eq!(s.dimensions(), (3 * 5 + 2, 2 * 4 + 2));
        for k in 0..5u32 {
            let (x, y) = (GAP + (k % 3) * 5, GAP + (k / 3) * 4);
            assert_eq!(
                s.get_pixel(x + 2, y + 1).0,
                [k as u8 * 50, 0, 0],
                "tile {k}"
            );
        }
        assert_eq!(s.get_pixel(0, 0).0, [GAP_GREY; 3]);
        assert_eq!(write(&[], &out).unwrap(), None);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
