//! The contact sheet: finished frames' preview PNGs on one grid (`OUT/contact_sheet.png`), so
//! the first look at a dataset needs no other tool. Written atomically after each run.
//!
//! At most [`MAX_TILES`] frames, evenly spaced over the selection (all of them when there are
//! fewer), read one at a time into the sheet: its memory is bounded whatever the dataset's size
//! (holding every preview of a 1,000-frame run of 128² frames made the run's peak RSS 5.6× that
//! of a 10-frame run).

use crate::error::Error;
use image::{imageops, RgbImage};
use std::path::{Path, PathBuf};

/// Grey between tiles, so frames with dark edges stay apart.
const GAP: u32 = 2;
const GAP_GREY: u8 = 40;
/// At most this many columns; tiles keep their size (frames are small by design).
const MAX_COLUMNS: u32 = 8;
/// At most this many tiles (8 rows of 8).
pub const MAX_TILES: usize = 64;

/// The previews the sheet shows: all of `pngs` up to [`MAX_TILES`], else that many evenly
/// spaced ones, first and last included, in frame order.
pub fn pick(pngs: &[PathBuf]) -> Vec<&PathBuf> {
    let n = pngs.len();
    if n <= MAX_TILES {
        return pngs.iter().collect();
    }
    (0..MAX_TILES)
        .map(|k| &pngs[k * (n - 1) / (MAX_TILES - 1)])
        .collect()
}

/// Tiles the previews in `pngs` (frame order; see [`pick`]) into `path`; does nothing without
/// previews.
pub fn write(pngs: &[PathBuf], path: &Path) -> Result<Option<PathBuf>, Error> {
    let chosen = pick(pngs);
    let open = |p: &Path| {
        image::open(p)
            .map(|img| img.to_rgb8())
            .map_err(|e| Error::Other(format!("contact sheet: reading {}: {e}", p.display())))
    };
    let Some(first) = chosen.first() else {
        return Ok(None);
    };
    let first = open(first)?;
    let (tw, th) = first.dimensions();
    let n = chosen.len() as u32;
    let cols = (n as f64).sqrt().ceil().clamp(1.0, MAX_COLUMNS as f64) as u32;
    let rows = n.div_ceil(cols);
    let mut sheet = RgbImage::from_pixel(
        cols * (tw + GAP) + GAP,
        rows * (th + GAP) + GAP,
        image::Rgb([GAP_GREY; 3]),
    );
    let mut place = |k: usize, t: &RgbImage| {
        let (c, r) = (k as u32 % cols, k as u32 / cols);
        // Frames of another size (a resolution variation) are placed as they are, clipped.
        imageops::replace(
            &mut sheet,
            t,
            (GAP + c * (tw + GAP)) as i64,
            (GAP + r * (th + GAP)) as i64,
        );
    };
    place(0, &first);
    drop(first);
    for (k, p) in chosen.iter().enumerate().skip(1) {
        place(k, &open(p)?);
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

    /// Past MAX_TILES frames the sheet shows MAX_TILES of them, evenly spaced, first and last
    /// included, each once and in order.
    #[test]
    fn long_runs_show_evenly_spaced_frames() {
        let pngs: Vec<PathBuf> = (0..1000)
            .map(|k| PathBuf::from(format!("{k}.png")))
            .collect();
        let chosen: Vec<usize> = pick(&pngs)
            .iter()
            .map(|p| p.file_stem().unwrap().to_str().unwrap().parse().unwrap())
            .collect();
        assert_eq!(chosen.len(), MAX_TILES);
        assert_eq!((chosen[0], chosen[MAX_TILES - 1]), (0, 999));
        let steps: Vec<usize> = chosen.windows(2).map(|w| w[1] - w[0]).collect();
        assert!(steps.iter().all(|&d| d == 15 || d == 16), "{steps:?}");
        assert_eq!(pick(&pngs[..MAX_TILES]).len(), MAX_TILES);
    }
}
