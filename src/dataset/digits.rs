//! Frame numbers on contact-sheet tiles: a 3×5 pixel font of the ten digits, scaled by whole
//! pixels, white on a black box in the tile's top-left corner.
//!
//! Hand-written rather than a font crate (font8x8, embedded-graphics): a frame number needs ten
//! glyphs of fifteen bits each, and a rasteriser crate would add a dependency for them.

use image::{Rgb, RgbImage};

/// Rows of each digit, top first; bit 2 is the left column.
const GLYPHS: [[u8; 5]; 10] = [
    [0b111, 0b101, 0b101, 0b101, 0b111],
    [0b010, 0b110, 0b010, 0b010, 0b111],
    [0b111, 0b001, 0b111, 0b100, 0b111],
    [0b111, 0b001, 0b111, 0b001, 0b111],
    [0b101, 0b101, 0b111, 0b001, 0b001],
    [0b111, 0b100, 0b111, 0b001, 0b111],
    [0b111, 0b100, 0b111, 0b101, 0b111],
    [0b111, 0b001, 0b001, 0b001, 0b001],
    [0b111, 0b101, 0b111, 0b101, 0b111],
    [0b111, 0b101, 0b111, 0b001, 0b111],
];

/// Whether pixel (x, y) of digit `d` (3×5) is lit.
pub fn lit(d: u8, x: u32, y: u32) -> bool {
    (GLYPHS[d as usize][y as usize] >> (2 - x)) & 1 == 1
}

/// Draws `n` in decimal at the top-left of `img`, each font pixel `scale`×`scale`, one font
/// pixel apart and with a one-pixel black margin; clipped to the image.
pub fn draw(img: &mut RgbImage, n: u32, scale: u32) {
    let text = n.to_string();
    let (w, h) = ((4 * text.len() as u32 + 1) * scale, 7 * scale);
    let mut put = |x: u32, y: u32, c: Rgb<u8>| {
        for (dx, dy) in (0..scale).flat_map(|a| (0..scale).map(move |b| (a, b))) {
            let (px, py) = (x * scale + dx, y * scale + dy);
            if px < img.width() && py < img.height() {
                img.put_pixel(px, py, c);
            }
        }
    };
    for y in 0..h / scale {
        for x in 0..w / scale {
            put(x, y, Rgb([0; 3]));
        }
    }
    for (k, d) in text.bytes().map(|b| b - b'0').enumerate() {
        for (x, y) in (0..3).flat_map(|x| (0..5).map(move |y| (x, y))) {
            if lit(d, x, y) {
                put(1 + 4 * k as u32 + x, 1 + y, Rgb([255; 3]));
            }
        }
    }
}
