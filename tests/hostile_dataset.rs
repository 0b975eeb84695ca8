//! Hostile dataset inputs of issue 27 item 7, each through the binary as a user would give
//! it: FIFOs and devices as dataset files, output folders of the wrong shape, forged manifest
//! lines, signals, unbounded draws. Every case must end with exit 0 or 2 (never a panic, a
//! hang or exit 1) and leave what the user owns as it was.

mod hostile_util;

use hostile_util::*;
use std::path::Path;
use std::process::Stdio;
use std::time::{Duration, Instant};

/// FIFOs and devices where a dataset reads a file: refused at once naming the file, not read
/// forever (the config, the sensor file, the base scene, a hashed envmap file).
#[test]
fn dataset_files_that_are_fifos_or_devices_are_refused() {
    let d = workdir("dsfifo");
    std::fs::write(d.join("s.ron"), SCENE).unwrap();
    mkfifo(&d.join("pipe.ron"));
    let o = dataset(&d, "pipe.ron", "o1", &[]);
    refused(&o, "config FIFO", &["pipe.ron", "FIFO"]);
    let o = dataset(&d, "/dev/zero", "o2", &[]);
    refused(&o, "config /dev/zero", &["/dev/zero", "device"]);
    for (name, scene) in [("dir", "d"), ("fifo", "pipe.ron"), ("dev", "/dev/zero")] {
        std::fs::create_dir_all(d.join("d")).unwrap();
        let cfg = format!("{name}.ron");
        std::fs::write(d.join(&cfg), DATASET.replace("s.ron", scene)).unwrap();
        let o = dataset(&d, &cfg, &format!("o-{name}"), &[]);
        let what = ["a directory", "a FIFO", "a device"][["dir", "fifo", "dev"]
            .iter()
            .position(|n| *n == name)
            .unwrap()];
        refused(&o, name, &["base scene", what]);
    }
    // A sensor file that is a FIFO, through `--sensor` of render.
    std::fs::write(d.join("s2.ron"), SCENE).unwrap();
    let o = render(&d, "s2.ron", "x.exr", &["--sensor", "pipe.ron"]);
    refused(&o, "--sensor FIFO", &["pipe.ron", "FIFO"]);
    let _ = std::fs::remove_dir_all(&d);
}

/// Output folders of the wrong shape are the user's to fix: exit 2 with a hint, not exit 1
/// with a raw OS error (OUT a file or /dev/null, a dangling link, manifest.jsonl, frames/ or
/// the lock of the wrong file type); `frames` is bounded.
#[test]
fn dataset_output_folders_of_the_wrong_shape_are_refused() {
    let d = workdir("dsout");
    std::fs::write(d.join("s.ron"), SCENE).unwrap();
    std::fs::write(d.join("ds.ron"), DATASET).unwrap();
    std::fs::write(d.join("afile"), "x").unwrap();
    std::os::unix::fs::symlink("nowhere/at/all", d.join("dangling")).unwrap();
    for out in ["afile", "/dev/null", "dangling"] {
        let o = dataset(&d, "ds.ron", out, &[]);
        refused(&o, out, &[out]);
    }
    // A claimed folder whose parts are then replaced by the wrong kinds of file.
    let o = dataset(&d, "ds.ron", "good", &["--frames", "0"]);
    assert_eq!(code(&o), Some(0), "{}", stderr(&o));
    let g = d.join("good");
    let swap = |name: &str, make: &dyn Fn(&Path)| {
        let p = g.join(name);
        let keep = g.join(format!("{name}.keep"));
        std::fs::rename(&p, &keep).unwrap();
        make(&p);
        let o = dataset(&d, "ds.ron", "good", &[]);
        refused(&o, name, &[name]);
        if p.is_dir() {
            std::fs::remove_dir(&p).unwrap();
        } else {
            std::fs::remove_file(&p).unwrap();
        }
        std::fs::rename(&keep, &p).unwrap();
    };
    swap("manifest.jsonl", &|p| std::fs::create_dir(p).unwrap());
    swap("manifest.jsonl", &|p| mkfifo(p));
    swap("frames", &|p| std::fs::write(p, "x").unwrap());
    swap(".prism-dataset.lock", &|p| mkfifo(p));
    swap(".prism-dataset.lock", &|p| std::fs::create_dir(p).unwrap());
    // frames: 2^32 - 1 planned every frame before the first: refused at once.
    std::fs::write(
        d.join("many.ron"),
        DATASET.replace("frames: 2", "frames: 4294967295"),
    )
    .unwrap();
    let o = dataset(&d, "many.ron", "many", &["--check"]);
    refused(&o, "frames 2^32-1", &["frames", "1000000"]);
    let _ = std::fs::remove_dir_all(&d);
}

/// A manifest line counts a frame as done only if it lists that frame's own files, the EXR
/// among them, intact; a line that is not UTF-8 is skipped as a torn line is.
#[test]
fn forged_manifest_lines_do_not_count_as_done() {
    let d = workdir("dsforge");
    std::fs::write(d.join("s.ron"), SCENE).unwrap();
    std::fs::write(d.join("ds.ron"), DATASET).unwrap();
    let o = dataset(&d, "ds.ron", "out", &["--frames", "0"]);
    assert_eq!(code(&o), Some(0), "{}", stderr(&o));
    let m = d.join("out/manifest.jsonl");
    let line0 = std::fs::read_to_string(&m).unwrap();
    let check = |what: &str| -> String {
        let o = dataset(&d, "ds.ron", "out", &["--check"]);
        assert_eq!(code(&o), Some(0), "{what}: {}", stderr(&o));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    assert!(check("as written").contains("\"done\":[0]"));
    // Frame 1 claiming frame 0's files; frame 1 with no files.
    let as1 = line0.replacen("\"frame\":0", "\"frame\":1", 1);
    let empty = as1
        .split("\"files\":[")
        .next()
        .map(|head| {
            let tail = &as1[as1.find("],\"seconds\"").unwrap() + 1..];
            format!("{head}\"files\":[]{tail}")
        })
        .unwrap();
    for (what, line) in [
        ("another frame's files", as1.as_str()),
        ("no files", &empty),
    ] {
        std::fs::write(&m, format!("{line0}{line}")).unwrap();
        let out = check(what);
        assert!(
            out.contains("\"done\":[0]") && out.contains("\"todo\":[1]"),
            "{what}: {out}"
        );
    }
    // Frame 99 of 2, its files copies of frame 0's: not a frame of this dataset, so not done,
    // and a resume drops its line (a reader of the manifest would count it).
    for e in ["exr", "json"] {
        std::fs::copy(
            d.join(format!("out/frames/000000.{e}")),
            d.join(format!("out/frames/000099.{e}")),
        )
        .unwrap();
    }
    let past = line0
        .replacen("\"frame\":0", "\"frame\":99", 1)
        .replace("frames/000000.", "frames/000099.");
    std::fs::write(&m, format!("{line0}{past}")).unwrap();
    let out = check("frame 99 of 2");
    assert!(out.contains("\"done\":[0]"), "{out}");
    let o = dataset(&d, "ds.ron", "out", &["--frames", "0"]);
    assert_eq!(code(&o), Some(0), "{}", stderr(&o));
    let kept = std::fs::read_to_string(&m).unwrap();
    assert!(!kept.contains("\"frame\":99"), "frame 99 of 2 kept: {kept}");
    // An invalid-UTF-8 line is skipped, frame 0 stays done.
    let mut bytes = line0.clone().into_bytes();
    bytes.extend_from_slice(b"{\"frame\":1,\xff\xfe}\n");
    std::fs::write(&m, bytes).unwrap();
    let out = check("invalid UTF-8 line");
    assert!(out.contains("\"done\":[0]"), "{out}");
    let _ = std::fs::remove_dir_all(&d);
}

/// SIGTERM ends `prism dataset` with exit 143 (SIGINT: 130) and no temporary left behind.
#[test]
fn a_dataset_run_ended_by_sigterm_exits_143_and_leaves_no_temporaries() {
    let d = workdir("dssig");
    // Frames slow enough to be interrupted mid-run (about a second each).
    std::fs::write(
        d.join("s.ron"),
        SCENE
            .replace("spp: 1", "spp: 4096")
            .replace("width: 8, height: 6", "width: 128, height: 96"),
    )
    .unwrap();
    std::fs::write(
        d.join("ds.ron"),
        "(scene: \"s.ron\", frames: 50, seed: 1, outputs: (spp: 256, resolution: (128, 96)))",
    )
    .unwrap();
    let mut child = prism()
        .current_dir(&d)
        .args([
            "dataset",
            "ds.ron",
            "-o",
            "out",
            "--quiet",
            "--threads",
            "1",
        ])
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Wait until the run is rendering (the frames folder exists), then a little more.
    let t = Instant::now();
    while !d.join("out/frames").exists() && t.elapsed() < Duration::from_secs(60) {
        std::thread::sleep(Duration::from_millis(20));
    }
    std::thread::sleep(Duration::from_millis(300));
    // SAFETY: signals our own child by its pid.
    unsafe { libc::kill(child.id() as i32, libc::SIGTERM) };
    let st = child.wait().unwrap();
    assert_eq!(st.code(), Some(143), "{st:?}");
    let temps: Vec<_> = walk(&d.join("out"))
        .into_iter()
        .filter(|p| p.file_name().unwrap().to_string_lossy().contains(".tmp."))
        .collect();
    assert!(temps.is_empty(), "temporaries left: {temps:?}");
    let _ = std::fs::remove_dir_all(&d);
}

/// Bounds that keep a run from spinning before its first frame, and configs that would record
/// what is not so: `max_attempts` of 2^32 − 1, a shape placed twice, 20,000 listed bands.
#[test]
fn unbounded_draws_duplicate_placements_and_band_lists_are_refused() {
    let d = workdir("dsbounds");
    std::fs::write(d.join("s.ron"), SCENE).unwrap();
    let cfg = |name: &str, extra: &str| {
        let text = DATASET.replacen("outputs:", &format!("{extra} outputs:"), 1);
        std::fs::write(d.join(name), text).unwrap();
    };
    cfg(
        "attempts.ron",
        "camera: (look_at: Shell(target: (0, 0, 0), radius: (5, 5), elevation: (15, 45), azimuth: (-60, 60)), keep_in_view: [\"ball\"], max_attempts: 4294967295),",
    );
    let o = dataset(&d, "attempts.ron", "o1", &["--check"]);
    refused(&o, "max_attempts", &["camera.max_attempts", "10000"]);
    cfg(
        "twice.ron",
        "objects: (place: (support: \"ball\", shapes: [\"ball\", \"ball\"])),",
    );
    let o = dataset(&d, "twice.ron", "o2", &["--check"]);
    refused(
        &o,
        "place twice",
        &["objects.place.shapes[1]", "listed twice"],
    );
    let boxes: Vec<String> = (0..20_000)
        .map(|i| {
            format!(
                "({}, {})",
                400.0 + i as f64 * 0.01,
                400.0 + i as f64 * 0.01 + 0.005
            )
        })
        .collect();
    let scene = SCENE.replacen(
        "(film:",
        &format!(
            "(sensor: (observer: Cie1931, bands: [Boxes([{}])]), film:",
            boxes.join(", ")
        ),
        1,
    );
    std::fs::write(d.join("boxes.ron"), scene).unwrap();
    let t = Instant::now();
    let o = render(&d, "boxes.ron", "boxes.exr", &[]);
    refused(&o, "20,000 boxes", &["bands", "1024"]);
    assert!(t.elapsed() < Duration::from_secs(20), "{:?}", t.elapsed());
    // A dataset.json that is not prism's: said so, not `changed: : null → …`.
    std::fs::create_dir_all(d.join("o3")).unwrap();
    std::fs::write(d.join("o3/dataset.json"), "garbage").unwrap();
    std::fs::write(d.join("ok.ron"), DATASET).unwrap();
    let o2 = dataset(&d, "ok.ron", "o3", &["--check"]);
    refused(
        &o2,
        "garbage dataset.json",
        &["dataset.json", "not prism's"],
    );
    assert!(!stderr(&o2).contains(": null →"), "{}", stderr(&o2));
    let _ = std::fs::remove_dir_all(&d);
}

/// Every variation's whole range is checked against the scene at load (so at `--check`) and
/// before any frame: each value some frame could draw that the scene refuses is exit 2 naming
/// the dataset config's field, and the output folder is not made (before: OUT claimed, then
/// every frame exit 1 blaming the base scene).
#[test]
fn variation_extremes_the_scene_refuses_are_refused_before_any_frame() {
    let d = workdir("dsextremes");
    let scene = SCENE
        .replace(
            "materials: {\"m\": Diffuse()}",
            "materials: {\"m\": Diffuse(), \"glass\": Dielectric(int_ior: 1.5)}",
        )
        .replace(
            "emitters: [Constant(radiance: Named(\"D65\"))]",
            "emitters: [Constant(radiance: Named(\"D65\")), Envmap(filename: \"sky.exr\")]",
        );
    std::fs::write(d.join("s.ron"), scene).unwrap();
    std::fs::copy(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/textures/sky.exr"),
        d.join("sky.exr"),
    )
    .unwrap();
    let shell = |target: &str, radius: &str, up: &str, el: &str, az: &str| {
        format!("camera: (look_at: Shell(target: {target}, radius: {radius}, elevation: {el}, azimuth: {az}), up: {up}),")
    };
    let cases = [
        (
            "degenerate pose",
            "camera: (look_at: Poses([(origin: (0, 1, 4), target: (0, 1, 4))])),".to_string(),
            "camera.look_at[0]",
        ),
        (
            "up along the view",
            shell("(0, 0, 0)", "(5, 5)", "(0, 0, 1)", "(-10, 10)", "(-10, 10)"),
            "camera.up",
        ),
        (
            "NaN target",
            shell("(NaN, 0, 0)", "(5, 5)", "(0, 1, 0)", "(10, 20)", "(0, 90)"),
            "camera.look_at.target",
        ),
        (
            "radius 1e30",
            shell("(0, 0, 0)", "(5, 1e30)", "(0, 1, 0)", "(10, 20)", "(0, 90)"),
            "camera.look_at.radius",
        ),
        (
            "intensity 3e38",
            "lights: [(target: \"emitters[0]\", intensity: (1, 3e38))],".into(),
            "lights[0].intensity",
        ),
        (
            "an envmap file that is not one",
            "envmap: (target: \"emitters[1]\", files: [\"s.ron\"]),".into(),
            "envmap.files[0]",
        ),
        (
            "IOR the scene refuses",
            "materials: [(target: \"glass\", ior: (0.001, 1.5))],".into(),
            "materials[0].ior",
        ),
        (
            "resolution 32768²",
            "outputs: (spp: 1, resolution: (32768, 32768)),".into(),
            "outputs.resolution",
        ),
    ];
    for (k, (what, extra, field)) in cases.iter().enumerate() {
        let text = if extra.starts_with("outputs:") {
            format!("(scene: \"s.ron\", frames: 2, seed: 1, {extra})")
        } else {
            DATASET.replacen("outputs:", &format!("{extra} outputs:"), 1)
        };
        let cfg = format!("x{k}.ron");
        std::fs::write(d.join(&cfg), text).unwrap();
        let out = format!("o{k}");
        let o = dataset(&d, &cfg, &out, &["--check"]);
        refused(&o, what, &[&cfg, field]);
        assert!(!d.join(&out).exists(), "{what}: the output folder was made");
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// `--force` of config Y into a folder config X is still writing is refused while X's run
/// holds it (before: Y started over and X's later frames were listed under Y); once X has
/// ended, `--force` starts over.
#[test]
fn force_into_a_folder_another_run_is_writing_is_refused() {
    let d = workdir("dsforce");
    std::fs::write(
        d.join("s.ron"),
        SCENE
            .replace("spp: 1", "spp: 4096")
            .replace("width: 8, height: 6", "width: 128, height: 96"),
    )
    .unwrap();
    std::fs::write(
        d.join("x.ron"),
        "(scene: \"s.ron\", frames: 50, seed: 1, outputs: (spp: 256, resolution: (128, 96)))",
    )
    .unwrap();
    std::fs::write(d.join("y.ron"), DATASET.replace("seed: 1", "seed: 2")).unwrap();
    let mut x = prism()
        .current_dir(&d)
        .args(["dataset", "x.ron", "-o", "out", "--quiet", "--threads", "1"])
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let t = Instant::now();
    while !d.join("out/frames").exists() && t.elapsed() < Duration::from_secs(60) {
        std::thread::sleep(Duration::from_millis(20));
    }
    let o = dataset(&d, "y.ron", "out", &["--force", "--check"]);
    // SAFETY: signals our own child by its pid.
    unsafe { libc::kill(x.id() as i32, libc::SIGTERM) };
    let _ = x.wait();
    refused(
        &o,
        "--force under a running run",
        &["--force", "another `prism dataset` run"],
    );
    let identity = std::fs::read_to_string(d.join("out/dataset.json")).unwrap();
    assert!(
        identity.contains("\"seed\": 1"),
        "X's identity replaced:\n{identity}"
    );
    // X has ended: --force starts Y over.
    let o = dataset(&d, "y.ron", "out", &["--force", "--check"]);
    assert_eq!(code(&o), Some(0), "{}", stderr(&o));
    let identity = std::fs::read_to_string(d.join("out/dataset.json")).unwrap();
    assert!(identity.contains("\"seed\": 2"), "{identity}");
    let _ = std::fs::remove_dir_all(&d);
}
