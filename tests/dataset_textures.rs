//! `prism dataset` textures drawn per frame from a folder of images (src/dataset/textures.rs):
//! the frame names its image, its scene holds it as the material's bitmap, `dataset.json`
//! hashes every image; a missing or empty folder, a broken image or an unknown material is
//! refused at `--check`.

mod dataset_util;
use dataset_util::*;

/// Three 4×4 single-colour PNGs in `dir/tex` (and a text file the folder scan skips).
fn folder(dir: &std::path::Path) {
    let tex = dir.join("tex");
    std::fs::create_dir_all(&tex).unwrap();
    for (name, c) in [
        ("red", [200, 20, 20]),
        ("green", [20, 200, 20]),
        ("blue", [20, 20, 200]),
    ] {
        image::RgbImage::from_pixel(4, 4, image::Rgb(c))
            .save(tex.join(format!("{name}.png")))
            .unwrap();
    }
    std::fs::write(tex.join("README.txt"), "not an image").unwrap();
}

fn textured(t: String) -> String {
    t.replace(
        "    swaps: [",
        "    textures: [(target: \"paint\", folder: \"tex\")],\n    swaps: [",
    )
}

/// 8 frames draw more than one of the three images (all alike: p = 3·(1/3)^8 ≈ 5e-4, and the
/// seed is fixed); each frame's JSON names one relative to the config, `dataset.json` hashes
/// the three (not the text file), and frame 2's export holds it as a `Bitmap` of its absolute path and
/// renders the frame's pixels bit for bit.
#[test]
fn a_material_takes_a_texture_from_a_folder_per_frame() {
    let dir = workdir("textures");
    folder(&dir);
    let cfg = config(&dir, textured);
    let out = dir.join("out");
    ok(&dataset(&cfg, &out, &[]));
    let ds = json_file(&out.join("dataset.json"));
    for n in ["red", "green", "blue"] {
        let key = format!("tex/{n}.png");
        assert!(
            ds["inputs"][&key].is_string(),
            "{key} not hashed: {}",
            ds["inputs"]
        );
    }
    assert!(ds["inputs"]["tex/README.txt"].is_null());
    let mut seen = std::collections::BTreeSet::new();
    for i in 0..8 {
        let f = json_file(&out.join(format!("frames/{i:06}.json")));
        let t = &f["frame"]["textures"][0];
        assert_eq!(t["target"], "paint", "frame {i}");
        seen.insert(t["file"].as_str().unwrap().to_string());
    }
    assert!(seen.len() >= 2, "{seen:?}");
    assert!(
        seen.iter()
            .all(|s| s.starts_with("tex/") && s.ends_with(".png")),
        "{seen:?}"
    );
    let f = json_file(&out.join("frames/000002.json"));
    let file = f["frame"]["textures"][0]["file"]
        .as_str()
        .unwrap()
        .to_string();
    let exp = dir.join("exp");
    ok(&dataset(&cfg, &exp, &["--export-frame", "2"]));
    let ron = std::fs::read_to_string(exp.join("frames/000002.ron")).unwrap();
    assert!(
        ron.contains("Bitmap(") && ron.contains(&format!("path: {:?}", dir.join(&file))),
        "{ron}"
    );
    let exr = dir.join("r2.exr");
    ok(&prism()
        .arg("render")
        .arg(exp.join("frames/000002.ron"))
        .arg("-o")
        .arg(&exr)
        .arg("--quiet")
        .output()
        .unwrap());
    let (want, got) = (exr_pixels(&out.join("frames/000002.exr")), exr_pixels(&exr));
    for (k, v) in &want {
        assert!(got[k] == *v, "channel {k} differs from the export's render");
    }
}

#[test]
fn bad_texture_folders_are_refused_at_check() {
    let dir = workdir("textures-bad");
    folder(&dir);
    std::fs::create_dir_all(dir.join("empty")).unwrap();
    std::fs::create_dir_all(dir.join("broken")).unwrap();
    std::fs::write(dir.join("broken/a.png"), b"\x89PNG\r\n").unwrap();
    let cases: [(&str, &[&str]); 4] = [
        (
            "(target: \"paint\", folder: \"gone\")",
            &[
                "textures[0].folder",
                "cannot list",
                "relative to the dataset config",
            ],
        ),
        (
            "(target: \"paint\", folder: \"empty\")",
            &["textures[0].folder", "no PNG, JPEG, EXR or HDR image file"],
        ),
        (
            "(target: \"paint\", folder: \"broken\")",
            &["textures[0].folder", "a.png", "re-export"],
        ),
        (
            "(target: \"pant\", folder: \"tex\")",
            &["textures[0].target", "no material \"pant\""],
        ),
    ];
    for (k, (v, needles)) in cases.into_iter().enumerate() {
        let cfg = config(&dir, |t| {
            t.replace(
                "    swaps: [",
                &format!("    textures: [{v}],\n    swaps: ["),
            )
        });
        let out = dir.join(format!("out{k}"));
        refused(&dataset(&cfg, &out, &["--check"]), needles);
        assert!(!out.exists(), "case {k}: the output folder was made");
    }
}
