//! Hostile inputs of issue 27 item 7, each through the binary as a user would give it: output
//! paths that are inputs or not plain files, full output devices, FIFOs and devices as dataset
//! files, output folders of the wrong shape, forged manifest lines, widths and ranges that made
//! tables without bound. Every case must end with exit 0 or 2 (never a panic, a hang or exit 1)
//! and leave what the user owns as it was.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

fn prism() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_prism"));
    c.stdin(Stdio::null());
    c
}

fn workdir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("prism-hostile-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

const SCENE: &str = r#"(film: (width: 8, height: 6), sampler: (spp: 1),
 camera: (fov: 40, to_world: [LookAt(origin: (0, 0, 5), target: (0, 0, 0), up: (0, 1, 0))]),
 materials: {"m": Diffuse()}, shapes: [(shape: Sphere(radius: 1), material: "m", name: "ball")],
 emitters: [Constant(radiance: Named("D65"))])"#;

/// Runs with a wall bound (a FIFO read would block forever): the output, or a panic naming
/// the case if it ran past `secs`.
fn run(mut c: Command, secs: u64, what: &str) -> Output {
    let mut child = c
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let t = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if t.elapsed() > Duration::from_secs(secs) {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{what}: still running after {secs} s (a hang)");
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    child.wait_with_output().unwrap()
}

fn code(o: &Output) -> Option<i32> {
    o.status.code()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Exit 2 with each of `want` in the message.
fn refused(o: &Output, what: &str, want: &[&str]) {
    let e = stderr(o);
    assert_eq!(code(o), Some(2), "{what}: exit {:?}\n{e}", code(o));
    assert!(e.contains("hint:"), "{what}: no hint in\n{e}");
    for w in want {
        assert!(e.contains(w), "{what}: no `{w}` in\n{e}");
    }
}

fn render(dir: &Path, scene: &str, out: &str, extra: &[&str]) -> Output {
    let mut c = prism();
    c.current_dir(dir)
        .args(["render", scene, "-o", out, "-q"])
        .args(extra);
    run(c, 60, &format!("render {scene} -o {out}"))
}

fn mkfifo(p: &Path) {
    assert!(Command::new("mkfifo").arg(p).status().unwrap().success());
}

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

fn dataset(dir: &Path, cfg: &str, out: &str, extra: &[&str]) -> Output {
    let mut c = prism();
    c.current_dir(dir)
        .args(["dataset", cfg, "-o", out, "--quiet"])
        .args(extra)
        .env_remove("SLURM_ARRAY_TASK_ID")
        .env_remove("SLURM_ARRAY_TASK_COUNT")
        .env_remove("JOB_COMPLETION_INDEX");
    run(c, 120, &format!("dataset {cfg} -o {out}"))
}

const DATASET: &str =
    "(scene: \"s.ron\", frames: 2, seed: 1, outputs: (spp: 1, resolution: (8, 6)))";

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

fn walk(d: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(d).into_iter().flatten().flatten() {
        let p = e.path();
        if p.is_dir() {
            out.extend(walk(&p));
        } else {
            out.push(p);
        }
    }
    out
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
