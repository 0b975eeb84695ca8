//! `prism dataset`'s contact sheet with layers and frame numbers (`outputs.sheet_layers`,
//! src/dataset/sheet_layers.rs): each tile is the frame's preview numbered with its frame index,
//! then its layers in false colour, read back here pixel for pixel against the frame's EXR.

mod dataset_util;
use dataset_util::*;

/// An edit of the config text.
type Edit = Box<dyn Fn(String) -> String>;

use prism::dataset::{digits, sheet_layers};

/// smoke.ron with the AOVs `aovs` and the sheet layers `layers`.
fn with_layers(aovs: &'static str, layers: &'static str) -> impl Fn(String) -> String {
    move |t: String| {
        t.replace(
            "outputs: (preview: true,",
            &format!("outputs: (aovs: [{aovs}], sheet_layers: [{layers}], preview: true,"),
        )
    }
}

/// Frames 0..3, tiles of preview + depth + normal + label (64×48 panels, 1 column): the sheet
/// is 1·(4·64 + 2) + 2 wide and 3·(48 + 2) + 2 high; tile k carries the number k (the 3×5 font,
/// white on black, exactly); the label panel is each pixel's id colour, the normal panel
/// (n + 1)/2 and the depth panel black exactly where no surface was hit (all exact: the sheet
/// is 8-bit and the paint is a fixed function of the EXR's values).
#[test]
fn the_sheet_shows_numbered_frames_and_their_layers() {
    let dir = workdir("sheet-layers");
    let cfg = config(
        &dir,
        with_layers(
            "\"depth\", \"normal\", \"label\"",
            "\"depth\", \"normal\", \"label\"",
        ),
    );
    let out = dir.join("out");
    ok(&dataset(&cfg, &out, &["--frames", "0..3"]));
    let sheet = image::open(out.join("contact_sheet.png"))
        .unwrap()
        .to_rgb8();
    let (w, h, gap) = (64u32, 48u32, 2u32);
    assert_eq!(sheet.dimensions(), (4 * w + 2 * gap, 3 * (h + gap) + gap));
    for k in 0..3u32 {
        let (x0, y0) = (gap, gap + k * (h + gap));
        // The number: a black box 5×7 with the glyph of digit k inside.
        for y in 0..7 {
            for x in 0..5 {
                let lit = (1..4).contains(&x)
                    && (1..6).contains(&y)
                    && digits::lit(k as u8, x - 1, y - 1);
                let want = if lit { [255; 3] } else { [0; 3] };
                assert_eq!(
                    sheet.get_pixel(x0 + x, y0 + y).0,
                    want,
                    "tile {k} number at ({x}, {y})"
                );
            }
        }
        let px = exr_pixels(&out.join(format!("frames/{k:06}.exr")));
        let (mut hits, mut misses) = (0u32, 0u32);
        for y in 0..h {
            for x in 0..w {
                let i = (y * w + x) as usize;
                let at = |panel: u32| sheet.get_pixel(x0 + panel * w + x, y0 + y).0;
                let label = px["label.ID"][i] as u32;
                assert_eq!(
                    at(3),
                    sheet_layers::id_colour(label).0,
                    "tile {k} label ({x}, {y})"
                );
                let n = [px["normal.X"][i], px["normal.Y"][i], px["normal.Z"][i]];
                let want = if n == [0.0; 3] {
                    [0; 3]
                } else {
                    n.map(|c| ((0.5 * (c + 1.0)).clamp(0.0, 1.0) * 255.0 + 0.5) as u8)
                };
                assert_eq!(at(2), want, "tile {k} normal ({x}, {y})");
                let d = px["depth.Z"][i];
                if d.is_finite() {
                    hits += 1;
                    assert!(
                        at(1)[0] >= 50,
                        "tile {k} depth ({x}, {y}) {d} painted {:?}",
                        at(1)
                    );
                } else {
                    misses += 1;
                    assert_eq!(at(1), [0; 3], "tile {k} depth ({x}, {y}) has no surface");
                }
            }
        }
        // The room encloses the camera: every pixel hits (the no-surface branch is checked
        // where a frame has one).
        assert!(
            hits > 0 && hits + misses == w * h,
            "tile {k}: {hits} hits, {misses} misses"
        );
    }
    // Frame 10's number reads "10" (two glyphs, four font pixels apart).
    let ten = dir.join("ten");
    std::fs::create_dir_all(&ten).unwrap();
    let cfg10 = config(&ten, |t| {
        with_layers("\"label\"", "\"label\"")(t).replace("frames: 8,", "frames: 12,")
    });
    ok(&dataset(&cfg10, &ten.join("out"), &["--frames", "10..11"]));
    let s = image::open(ten.join("out/contact_sheet.png"))
        .unwrap()
        .to_rgb8();
    for (g, d) in [(0u32, 1u8), (1, 0)] {
        for y in 0..5 {
            for x in 0..3 {
                let want = if digits::lit(d, x, y) {
                    [255; 3]
                } else {
                    [0; 3]
                };
                assert_eq!(
                    s.get_pixel(gap + 1 + 4 * g + x, gap + 1 + y).0,
                    want,
                    "glyph {g}"
                );
            }
        }
    }
}

/// A layer the frames lack, one the sheet cannot paint, and layers without previews are
/// refused at `--check` naming the field and the fix.
#[test]
fn bad_sheet_layers_are_refused() {
    let dir = workdir("sheet-bad");
    let cases: [(Edit, &[&str]); 3] = [
        (
            Box::new(with_layers("\"label\"", "\"depth\"")),
            &[
                "outputs.sheet_layers[0]",
                "no \"depth\" layer",
                "outputs.aovs",
            ],
        ),
        (
            Box::new(with_layers("\"position\"", "\"position\"")),
            &[
                "outputs.sheet_layers[0]",
                "cannot show \"position\"",
                "normal",
            ],
        ),
        (
            Box::new(|t: String| {
                with_layers("\"depth\"", "\"depth\"")(t)
                    .replace("preview: true,", "preview: false,")
            }),
            &["outputs.sheet_layers", "preview: true"],
        ),
    ];
    for (k, (edit, needles)) in cases.into_iter().enumerate() {
        let cfg = config(&dir, edit);
        let out = dir.join(format!("out{k}"));
        refused(&dataset(&cfg, &out, &["--check"]), needles);
        assert!(!out.exists(), "case {k}: the output folder was made");
    }
}
