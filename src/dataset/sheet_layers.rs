//! The contact sheet's tile of one frame: its preview with the frame number drawn in the corner,
//! then the layers `outputs.sheet_layers` names, read from the frame's EXR and painted in false
//! colour, side by side (src/dataset/sheet.rs lays the tiles out).
//!
//! Paint: `depth`/`distance` grey, nearest white, farthest dark grey (per frame: the frame's
//! nearest and farthest surface), no surface black; normals as (n + 1)/2 in RGB; ids (`instance`,
//! `label`, `material`) a fixed colour per id (a hash, the same id the same colour in every frame
//! and dataset), 0 black; `alpha` grey; `albedo` its linear sRGB, sRGB-encoded.

use crate::error::{Error, InputError};
use crate::film::Aov;
use image::{Rgb, RgbImage};
use std::collections::BTreeMap;
use std::path::Path;

/// The layers a sheet can show.
pub const SHOWN: [&str; 11] = [
    "depth",
    "distance",
    "normal",
    "geo_normal",
    "normal_camera",
    "geo_normal_camera",
    "instance",
    "label",
    "material",
    "alpha",
    "albedo",
];

/// `outputs.sheet_layers` checked: each a layer the sheet can paint and every frame has.
pub fn check(
    file: &Path,
    names: &[String],
    aovs: &[String],
    preview: bool,
) -> Result<Vec<Aov>, InputError> {
    if !names.is_empty() && !preview {
        return Err(
            InputError::new(file, "a contact sheet's layers need the previews")
                .field("outputs.sheet_layers")
                .hint("set `outputs: (preview: true, ..)`, or drop sheet_layers"),
        );
    }
    let mut out = Vec::new();
    for (i, n) in names.iter().enumerate() {
        let field = format!("outputs.sheet_layers[{i}]");
        let aov = Aov::parse(n).filter(|_| SHOWN.contains(&n.as_str()));
        let Some(aov) = aov else {
            return Err(
                InputError::new(file, format!("the contact sheet cannot show \"{n}\""))
                    .field(field)
                    .hint(format!("it shows: {}", SHOWN.join(", "))),
            );
        };
        if !aovs.iter().any(|a| a.trim() == n) {
            return Err(
                InputError::new(file, format!("the frames have no \"{n}\" layer"))
                    .field(field)
                    .hint(format!(
                        "add \"{n}\" to `outputs.aovs` (the frames have: {})",
                        aovs.join(", ")
                    )),
            );
        }
        out.push(aov);
    }
    Ok(out)
}

/// The frame's tile: `preview` (`tw`×`th`, clipped or padded) numbered `frame`, then one panel
/// per layer of `exr`.
pub fn tile(
    preview: &RgbImage,
    frame: Option<u32>,
    exr: &Path,
    layers: &[Aov],
    (tw, th): (u32, u32),
) -> Result<RgbImage, Error> {
    let mut out = RgbImage::new(tw * (1 + layers.len() as u32), th);
    let fit = image::imageops::crop_imm(preview, 0, 0, tw.min(preview.width()), th);
    image::imageops::replace(&mut out, &*fit, 0, 0);
    if let Some(f) = frame {
        super::digits::draw(&mut out, f, (tw / 64).max(1));
    }
    if layers.is_empty() {
        return Ok(out);
    }
    let read = |e: String| Error::Other(format!("contact sheet: reading {}: {e}", exr.display()));
    let (channels, (w, h)) = read_channels(exr).map_err(read)?;
    for (k, &aov) in layers.iter().enumerate() {
        let get = |c: &str| {
            let name = format!("{}.{c}", aov.name());
            channels
                .get(&name)
                .ok_or_else(|| read(format!("no channel {name}")))
        };
        let ch: Vec<&Vec<f32>> = aov
            .channels()
            .iter()
            .map(|c| get(c))
            .collect::<Result<_, _>>()?;
        let x0 = tw * (1 + k as u32);
        let paint = paint(aov, &ch);
        for y in 0..th.min(h) {
            for x in 0..tw.min(w) {
                let i = (y * w + x) as usize;
                out.put_pixel(x0 + x, y, paint(i));
            }
        }
    }
    Ok(out)
}

/// Every channel of the EXR's first layer as f32 (ids are exact below 2^24), and its size.
#[allow(clippy::type_complexity)]
fn read_channels(p: &Path) -> Result<(BTreeMap<String, Vec<f32>>, (u32, u32)), String> {
    use exr::prelude::*;
    let img = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_file(p)
        .map_err(|e| e.to_string())?;
    let size = img.layer_data.size;
    let map = img.layer_data.channel_data.list.iter();
    let map = map.map(|c| (c.name.to_string(), c.sample_data.values_as_f32().collect()));
    Ok((map.collect(), (size.0 as u32, size.1 as u32)))
}

/// The false colour of pixel i of a layer with channels `ch`.
fn paint<'a>(aov: Aov, ch: &'a [&'a Vec<f32>]) -> Box<dyn Fn(usize) -> Rgb<u8> + 'a> {
    let byte = |v: f32| (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
    if aov.is_id() {
        return Box::new(move |i| id_colour(ch[0][i] as u32));
    }
    match ch.len() {
        // Depth or distance: the frame's nearest surface white, its farthest 20% grey.
        1 if aov.channels() == ["Z"] => {
            let hit = |v: &&f32| v.is_finite() && **v > 0.0;
            let lo = ch[0]
                .iter()
                .filter(hit)
                .fold(f32::INFINITY, |a, &b| a.min(b));
            let hi = ch[0].iter().filter(hit).fold(0.0f32, |a, &b| a.max(b));
            let span = (hi - lo).max(f32::MIN_POSITIVE);
            Box::new(move |i| {
                let d = ch[0][i];
                let g = if d.is_finite() && d > 0.0 {
                    byte(1.0 - 0.8 * (d - lo) / span)
                } else {
                    0
                };
                Rgb([g; 3])
            })
        }
        1 => Box::new(move |i| Rgb([byte(ch[0][i]); 3])),
        // Albedo: linear sRGB, encoded.
        3 if aov.channels() == ["R", "G", "B"] => Box::new(move |i| {
            let enc = |c: f32| byte(crate::spectrum::color::srgb_encode(c));
            Rgb([enc(ch[0][i]), enc(ch[1][i]), enc(ch[2][i])])
        }),
        // Normals: (n + 1) / 2; no surface (n = 0) black.
        _ => Box::new(move |i| {
            let n = [ch[0][i], ch[1][i], ch[2][i]];
            if n == [0.0; 3] {
                Rgb([0; 3])
            } else {
                Rgb(n.map(|c| byte(0.5 * (c + 1.0))))
            }
        }),
    }
}

/// A fixed, bright-enough colour per id (SplitMix64's finaliser of the id); 0 black.
pub fn id_colour(id: u32) -> Rgb<u8> {
    if id == 0 {
        return Rgb([0; 3]);
    }
    let mut z = (id as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^= z >> 31;
    // Each channel in 64..=255, so no id reads as the black of "none".
    Rgb([0, 8, 16].map(|s| 64 + ((z >> s) as u8 % 192)))
}
