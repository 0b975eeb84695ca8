//! The contact sheet: finished frames' preview PNGs on one grid (`OUT/contact_sheet.png`), so
//! the first look at a dataset needs no other tool. Written atomically after each run.
//!
//! At most [`MAX_TILES`] frames, evenly spaced over the selection (all of them when there are
//! fewer). The sheet is encoded as a stream, one row of tiles at a time, each tile read when its
//! row is built: its memory is one row of tiles whatever the dataset's size (holding every
//! preview of a 1,000-frame run of 128² frames made the run's peak RSS 5.6× that of a 10-frame
//! run, and holding the 64-tile raster still added 3 MB to the peak).

use crate::error::Error;
use image::{imageops, RgbImage};
use std::io::Write;
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
pub fn pick<T>(pngs: &[T]) -> Vec<&T> {
    let n = pngs.len();
    if n <= MAX_TILES {
        return pngs.iter().collect();
    }
    (0..MAX_TILES)
        .map(|k| &pngs[k * (n - 1) / (MAX_TILES - 1)])
        .collect()
}

fn open(p: &Path) -> Result<RgbImage, Error> {
    image::open(p)
        .map(|img| img.to_rgb8())
        .map_err(|e| Error::Other(format!("contact sheet: reading {}: {e}", p.display())))
}

/// Tiles the previews in `pngs` (frame order; see [`pick`]) into `path`; does nothing without
/// previews. The first preview sets the tile size; frames of another size (a resolution
/// variation) are placed at their tile's corner as they are, clipped to the tile.
pub fn write(pngs: &[PathBuf], path: &Path) -> Result<Option<PathBuf>, Error> {
    let frames: Vec<(Option<u32>, PathBuf)> = pngs.iter().map(|p| (None, p.clone())).collect();
    write_tiles(&frames, &[], path)
}

/// [`write`] of a dataset's frames `(index, preview)`: each tile numbered, with `layers` of the
/// frame's EXR (the preview's path with `.exr`) beside its preview (src/dataset/sheet_layers.rs).
pub fn write_frames(
    frames: &[(u32, PathBuf)],
    layers: &[crate::film::Aov],
    path: &Path,
) -> Result<Option<PathBuf>, Error> {
    let frames: Vec<(Option<u32>, PathBuf)> =
        frames.iter().map(|(i, p)| (Some(*i), p.clone())).collect();
    write_tiles(&frames, layers, path)
}

fn write_tiles(
    frames: &[(Option<u32>, PathBuf)],
    layers: &[crate::film::Aov],
    path: &Path,
) -> Result<Option<PathBuf>, Error> {
    let chosen = pick(frames);
    let Some(first) = chosen.first() else {
        return Ok(None);
    };
    let mut first = Some(open(&first.1)?);
    let (pw, th) = first.as_ref().map_or((0, 0), |f| f.dimensions());
    // A tile: the preview, then one panel of its size per layer.
    let panels = 1 + layers.len() as u32;
    let tw = pw * panels;
    let n = chosen.len() as u32;
    let cols = (n as f64 / panels as f64)
        .sqrt()
        .ceil()
        .clamp(1.0, MAX_COLUMNS as f64) as u32;
    let rows = n.div_ceil(cols);
    let (width, height) = (cols * (tw + GAP) + GAP, rows * (th + GAP) + GAP);
    let grey = image::Rgb([GAP_GREY; 3]);
    // A preview that cannot be read is reported as such, not as a failed write.
    let mut unread: Option<Error> = None;
    let mut encode = |tmp: &Path| -> Result<(), String> {
        let file = std::fs::File::create(tmp).map_err(|e| e.to_string())?;
        let mut enc = png::Encoder::new(std::io::BufWriter::new(file), width, height);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let mut writer = enc.write_header().map_err(|e| e.to_string())?;
        let mut stream = writer.stream_writer().map_err(|e| e.to_string())?;
        let io = |e: std::io::Error| e.to_string();
        stream
            .write_all(RgbImage::from_pixel(width, GAP, grey).as_raw())
            .map_err(io)?;
        // One strip per row of tiles: the tiles' rows, then the gap below them.
        let mut strip = RgbImage::new(width, th + GAP);
        for r in 0..rows {
            strip.pixels_mut().for_each(|p| *p = grey);
            for c in 0..cols {
                let k = (r * cols + c) as usize;
                let Some((number, p)) = chosen.get(k).copied() else {
                    break;
                };
                let mut failed = |e: Error| {
                    let m = e.to_string();
                    unread = Some(e);
                    m
                };
                let preview = match first.take() {
                    Some(t) => t,
                    None => open(p).map_err(&mut failed)?,
                };
                let x = GAP + c * (tw + GAP);
                if number.is_none() && layers.is_empty() {
                    let fit = imageops::crop_imm(&preview, 0, 0, tw.min(preview.width()), th);
                    imageops::replace(&mut strip, &*fit, x as i64, 0);
                } else {
                    let exr = p.with_extension("exr");
                    let tile = super::sheet_layers::tile(&preview, *number, &exr, layers, (pw, th))
                        .map_err(&mut failed)?;
                    imageops::replace(&mut strip, &tile, x as i64, 0);
                }
            }
            stream.write_all(strip.as_raw()).map_err(io)?;
        }
        stream.finish().map_err(|e| e.to_string())?;
        writer.finish().map_err(|e| e.to_string())
    };
    let written = crate::output::write_atomic(path, |tmp| encode(tmp));
    if let Some(e) = unread {
        return Err(e);
    }
    written?;
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

    /// A larger frame (a resolution variation) is clipped to its tile and leaves the next row
    /// alone; a preview that cannot be decoded is an error naming it, and no sheet is left.
    #[test]
    fn odd_sizes_are_clipped_and_bad_previews_named() {
        let dir = std::env::temp_dir().join(format!("prism-sheet-odd-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let save = |k: u8, w: u32, h: u32| {
            let p = dir.join(format!("{k}.png"));
            RgbImage::from_pixel(w, h, image::Rgb([k * 60, 10, 0]))
                .save(&p)
                .unwrap();
            p
        };
        // Tiles 4×3; frame 1 is 9×7; 2×2 grid.
        let pngs = vec![save(0, 4, 3), save(1, 9, 7), save(2, 4, 3), save(3, 4, 3)];
        let out = dir.join("sheet.png");
        write(&pngs, &out).unwrap();
        let s = image::open(&out).unwrap().to_rgb8();
        assert_eq!(s.dimensions(), (2 * 6 + 2, 2 * 5 + 2));
        // Frame 1 fills its 4×3 tile and stops there: the gap and frame 3 below are intact.
        assert_eq!(s.get_pixel(8 + 3, 2 + 2).0, [60, 10, 0]);
        assert_eq!(s.get_pixel(8 + 3, 2 + 3).0, [GAP_GREY; 3]);
        assert_eq!(s.get_pixel(8, 7).0, [180, 10, 0]);
        assert_eq!(s.get_pixel(2, 7).0, [120, 10, 0]);
        // A truncated preview.
        std::fs::write(&pngs[2], b"\x89PNG\r\n").unwrap();
        std::fs::remove_file(&out).unwrap();
        let e = write(&pngs, &out).unwrap_err().to_string();
        assert!(
            e.contains("contact sheet: reading") && e.contains("2.png"),
            "{e}"
        );
        assert!(!out.exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
