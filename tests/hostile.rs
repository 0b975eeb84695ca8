//! Hostile inputs of issue 27 item 7, each through the binary as a user would give it: output
//! paths that are inputs or not plain files, full output devices, FIFOs and devices as dataset
//! files, output folders of the wrong shape, forged manifest lines, widths and ranges that made
//! tables without bound. Every case must end with exit 0 or 2 (never a panic, a hang or exit 1)
//! and leave what the user owns as it was.

mod hostile_util;

use hostile_util::*;
use std::process::Stdio;

/// The sidecar `OUT.json` is an output like the EXR: checked against every input and for its
/// file type before anything renders (issue 27 item 7, data loss).
#[test]
fn the_sidecar_never_replaces_an_input_or_a_special_file() {
    let d = workdir("sidecar");
    // The scene itself named s.json: `-o s.exr` made its sidecar s.json.
    std::fs::write(d.join("s.json"), SCENE).unwrap();
    let o = render(&d, "s.json", "s.exr", &[]);
    refused(
        &o,
        "scene s.json",
        &["s.json", "the scene file being rendered"],
    );
    assert_eq!(std::fs::read_to_string(d.join("s.json")).unwrap(), SCENE);
    assert!(
        !d.join("s.exr").exists(),
        "the EXR was written before the refusal"
    );
    // A sensor file cam.json and `-o cam.exr`.
    std::fs::write(d.join("s.ron"), SCENE).unwrap();
    let sensor = "(observer: Cie1931, rgb: [Srgb], bands: [])";
    std::fs::write(d.join("cam.json"), sensor).unwrap();
    let o = render(&d, "s.ron", "cam.exr", &["--sensor", "cam.json"]);
    refused(
        &o,
        "sensor cam.json",
        &["cam.json", "a file this scene reads"],
    );
    assert_eq!(std::fs::read_to_string(d.join("cam.json")).unwrap(), sensor);
    // A symbolic link (and a dangling one) at OUT.json: the link is left as it is.
    std::fs::write(d.join("target.txt"), "mine").unwrap();
    std::os::unix::fs::symlink("target.txt", d.join("l.json")).unwrap();
    std::os::unix::fs::symlink("nowhere.txt", d.join("n.json")).unwrap();
    for out in ["l", "n"] {
        let o = render(&d, "s.ron", &format!("{out}.exr"), &[]);
        refused(&o, "link", &[&format!("{out}.json"), "symbolic link"]);
        assert!(std::fs::symlink_metadata(d.join(format!("{out}.json")))
            .unwrap()
            .file_type()
            .is_symlink());
        assert!(!d.join(format!("{out}.exr")).exists());
    }
    // A FIFO, a directory at OUT.json: refused before the EXR is written.
    mkfifo(&d.join("f.json"));
    std::fs::create_dir(d.join("dir.json")).unwrap();
    for out in ["f", "dir"] {
        let o = render(&d, "s.ron", &format!("{out}.exr"), &[]);
        refused(&o, out, &[&format!("{out}.json")]);
        assert!(!d.join(format!("{out}.exr")).exists(), "{out}: EXR written");
    }
    // The plain case still renders and writes both.
    let o = render(&d, "s.ron", "ok.exr", &[]);
    assert_eq!(code(&o), Some(0), "{}", stderr(&o));
    assert!(d.join("ok.exr").is_file() && d.join("ok.json").is_file());
    let _ = std::fs::remove_dir_all(&d);
}

/// `2>/dev/full` and `>/dev/full`: messages that cannot be written do not panic (exit 101);
/// a result that cannot be written (`--check`'s JSON) is an error, exit 2.
#[test]
fn a_full_output_device_is_not_a_panic() {
    let d = workdir("full");
    std::fs::write(d.join("s.ron"), SCENE).unwrap();
    let full = || {
        std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap()
    };
    let mut c = prism();
    c.current_dir(&d)
        .args(["render", "s.ron", "-o", "a.exr"])
        .stderr(full());
    let st = c.status().unwrap();
    assert_eq!(st.code(), Some(0), "render 2>/dev/full");
    let mut c = prism();
    c.current_dir(&d)
        .args(["render", "missing.ron", "-o", "b.exr"])
        .stderr(full());
    assert_eq!(c.status().unwrap().code(), Some(2), "refusal 2>/dev/full");
    std::fs::write(
        d.join("ds.ron"),
        "(scene: \"s.ron\", frames: 2, seed: 1, outputs: (spp: 1, resolution: (8, 6)))",
    )
    .unwrap();
    let mut c = prism();
    c.current_dir(&d)
        .args(["dataset", "ds.ron", "-o", "out", "--check"])
        .stdout(full())
        .stderr(Stdio::piped());
    let o = c.output().unwrap();
    refused(&o, "--check >/dev/full", &["standard output"]);
    let _ = std::fs::remove_dir_all(&d);
}

/// A Gaussian filter of any width makes a bounded table (a fwhm of 1e30 wrapped its sample
/// count to 0 and indexed an empty table: a panic); a spectral range is bounded.
#[test]
fn widths_and_ranges_make_bounded_tables() {
    let d = workdir("tables");
    let with = |extra: &str| SCENE.replacen("(film:", &format!("({extra} film:"), 1);
    let wide = with(
        "sensor: (observer: Cie1931, bands: [Filter(name: \"nir\", curve: Gaussian(centre: 850, fwhm: 1e30))]),",
    );
    std::fs::write(d.join("wide.ron"), wide).unwrap();
    let o = render(&d, "wide.ron", "wide.exr", &[]);
    assert_eq!(code(&o), Some(0), "{}", stderr(&o));
    let narrow = with(
        "sensor: (observer: Cie1931, bands: [Filter(name: \"n\", curve: Gaussian(centre: 550, fwhm: 1e-30))]),",
    );
    std::fs::write(d.join("narrow.ron"), narrow).unwrap();
    let o = render(&d, "narrow.ron", "narrow.exr", &[]);
    refused(&o, "fwhm 1e-30", &["fwhm", "0.001"]);
    let far = with("spectral: (range: (360, 1e9), sampling: Sensor),");
    std::fs::write(d.join("far.ron"), far).unwrap();
    let o = render(&d, "far.ron", "far.exr", &[]);
    refused(&o, "range to 1e9 nm", &["spectral.range", "100000"]);
    let _ = std::fs::remove_dir_all(&d);
}
