//! `prism dataset`: frames reproducible alone, shards disjoint and complete, resume after
//! `kill -9`, `--export-frame` reproduced by `prism render`, and bad input refused (exit 2)
//! before any frame renders. All on configs/datasets/smoke.ron (8 frames of 64×48 at 8 spp).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

fn prism() -> Command {
    Command::new(env!("CARGO_BIN_EXE_prism"))
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn workdir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("prism-dataset-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// smoke.ron with its paths made absolute and `edit` applied, written into `dir`.
fn config(dir: &Path, edit: impl Fn(String) -> String) -> PathBuf {
    let ds = root().join("configs/datasets");
    let text = std::fs::read_to_string(ds.join("smoke.ron")).unwrap();
    let text = text
        .replace(
            "\"scenes/tabletop.ron\"",
            &format!("{:?}", ds.join("scenes/tabletop.ron")),
        )
        .replace(
            "\"../../scenes/textures/sky.exr\"",
            &format!("{:?}", root().join("scenes/textures/sky.exr")),
        );
    let p = dir.join("dataset.ron");
    std::fs::write(&p, edit(text)).unwrap();
    p
}

/// configs/datasets/scenes/tabletop.ron with its sky's path made absolute, so that an edited
/// copy of it loads from any folder.
fn tabletop() -> String {
    std::fs::read_to_string(root().join("configs/datasets/scenes/tabletop.ron"))
        .unwrap()
        .replace(
            "\"../../../scenes/textures/sky.exr\"",
            &format!("{:?}", root().join("scenes/textures/sky.exr")),
        )
}

/// `config(dir, edit)` with `dir`/base.ron (an edited `tabletop()`) as the frames' base scene.
fn config_on_base(dir: &Path, edit: impl Fn(String) -> String) -> PathBuf {
    let tabletop = format!("{:?}", root().join("configs/datasets/scenes/tabletop.ron"));
    let base = format!("{:?}", dir.join("base.ron"));
    config(dir, |t| edit(t).replace(&tabletop, &base))
}

fn dataset(cfg: &Path, out: &Path, extra: &[&str]) -> Output {
    prism()
        .arg("dataset")
        .arg(cfg)
        .arg("-o")
        .arg(out)
        .arg("--quiet")
        .args(extra)
        .env_remove("SLURM_ARRAY_TASK_ID")
        .env_remove("SLURM_ARRAY_TASK_COUNT")
        .env_remove("JOB_COMPLETION_INDEX")
        .output()
        .unwrap()
}

fn ok(o: &Output) {
    assert!(
        o.status.success(),
        "exit {:?}\n{}",
        o.status.code(),
        String::from_utf8_lossy(&o.stderr)
    );
}

/// Every file under OUT/frames (but temporary ones) with its bytes.
fn frames(out: &Path) -> BTreeMap<String, Vec<u8>> {
    let mut m = BTreeMap::new();
    let Ok(rd) = std::fs::read_dir(out.join("frames")) else {
        return m;
    };
    for e in rd {
        let p = e.unwrap().path();
        let name = p.file_name().unwrap().to_string_lossy().into_owned();
        if !name.starts_with('.') {
            m.insert(name, std::fs::read(&p).unwrap());
        }
    }
    m
}

/// The manifest's frame indices, in order, each line checked to parse.
fn manifest(out: &Path) -> Vec<u64> {
    let text = std::fs::read_to_string(out.join("manifest.jsonl")).unwrap_or_default();
    text.lines()
        .map(|l| {
            let v: serde_json::Value =
                serde_json::from_str(l).unwrap_or_else(|e| panic!("manifest line `{l}`: {e}"));
            v["frame"].as_u64().unwrap()
        })
        .collect()
}

/// The full run, made once per test process.
fn full_run() -> PathBuf {
    static FULL: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();
    FULL.get_or_init(|| {
        let dir = workdir("full");
        let cfg = config(&dir, |t| t);
        let out = dir.join("out");
        ok(&dataset(&cfg, &out, &[]));
        assert_eq!(manifest(&out), (0..8).collect::<Vec<_>>());
        out
    })
    .clone()
}

#[test]
fn a_frame_alone_is_bit_identical_to_the_full_run() {
    let full = frames(&full_run());
    assert_eq!(full.len(), 8 * 3, "exr, json and png per frame");
    let dir = workdir("alone");
    let cfg = config(&dir, |t| t);
    // One frame, on one thread; a range, on two.
    let one = dir.join("one");
    ok(&dataset(&cfg, &one, &["--frames", "5", "--threads", "1"]));
    let range = dir.join("range");
    ok(&dataset(
        &cfg,
        &range,
        &["--frames", "2..4", "--threads", "2"],
    ));
    let got: Vec<_> = frames(&one).into_iter().chain(frames(&range)).collect();
    assert_eq!(got.len(), 9);
    for (name, bytes) in got {
        assert!(full[&name] == bytes, "{name} differs from the full run");
    }
    assert_eq!(manifest(&one), vec![5]);
    assert_eq!(manifest(&range), vec![2, 3]);
}

#[test]
fn shards_are_disjoint_complete_and_their_union_is_one_run() {
    let full = frames(&full_run());
    let dir = workdir("shards");
    let cfg = config(&dir, |t| t);
    let mut seen = Vec::new();
    for s in 0..3 {
        let out = dir.join(format!("shard{s}"));
        let shard = s.to_string();
        ok(&dataset(
            &cfg,
            &out,
            &["--shard", &shard, "--num-shards", "3"],
        ));
        let m = manifest(&out);
        assert!(m.iter().all(|i| i % 3 == s as u64), "shard {s}: {m:?}");
        seen.extend(m);
        for (name, bytes) in frames(&out) {
            assert!(full[&name] == bytes, "shard {s}: {name} differs");
        }
    }
    seen.sort_unstable();
    assert_eq!(seen, (0..8).collect::<Vec<_>>());

    // Shards from the scheduler's environment, all into one folder: one line per frame.
    let shared = dir.join("shared");
    for (k, v) in [("SLURM_ARRAY_TASK_ID", "0"), ("SLURM_ARRAY_TASK_ID", "1")] {
        let o = prism()
            .args(["dataset", "--quiet", "-o"])
            .arg(&shared)
            .arg(&cfg)
            .env(k, v)
            .env("SLURM_ARRAY_TASK_COUNT", "2")
            .env_remove("JOB_COMPLETION_INDEX")
            .output()
            .unwrap();
        ok(&o);
    }
    // Temporaries a killed run left (its process gone) are removed at start; a live
    // process's are not.
    let mut child = Command::new("true").spawn().unwrap();
    let dead = child.id();
    child.wait().unwrap();
    let stale = shared.join(format!("frames/.000001.exr.{dead}.tmp.exr"));
    let live = shared.join("frames/.000002.exr.1.tmp.exr");
    std::fs::write(&stale, b"partial").unwrap();
    std::fs::write(&live, b"partial").unwrap();
    let o = prism()
        .args(["dataset", "--quiet", "--num-shards", "2", "-o"])
        .arg(&shared)
        .arg(&cfg)
        .env("JOB_COMPLETION_INDEX", "1")
        .env_remove("SLURM_ARRAY_TASK_ID")
        .output()
        .unwrap();
    ok(&o);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("0 rendered, 4 skipped"), "{err}");
    let mut m = manifest(&shared);
    m.sort_unstable();
    assert_eq!(m, (0..8).collect::<Vec<_>>());
    assert!(!stale.exists(), "a dead run's temporary was left");
    assert!(live.exists(), "a live process's temporary was removed");
    std::fs::remove_file(&live).unwrap();
    assert!(frames(&shared) == full);
    // The last shard's contact sheet shows every listed frame, as the single run's does.
    let sheet = |d: &Path| std::fs::read(d.join("contact_sheet.png")).unwrap();
    assert!(
        sheet(&shared) == sheet(&full_run()),
        "the sheet lacks other shards' frames"
    );
}

/// A small deterministic generator for the kill moments.
fn lcg(state: &mut u64) -> f64 {
    *state = state
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*state >> 11) as f64 / (1u64 << 53) as f64
}

/// Runs killed with SIGKILL at 5 seeded moments (tools/bench/dataset_kill.sh runs 20): after
/// each kill every listed frame is intact and still listed, none twice; the resumed run ends
/// byte-identical to the uninterrupted one.
#[test]
fn resume_after_kill_loses_nothing_and_ends_identical() {
    let full = frames(&full_run());
    let dir = workdir("kill");
    let cfg = config(&dir, |t| t);
    let out = dir.join("out");
    let t = Instant::now();
    ok(&dataset(&cfg, &dir.join("timing"), &[]));
    let whole = t.elapsed().as_secs_f64();
    let kills: u32 = std::env::var("PRISM_KILLS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(5);
    let mut rng = 20261201u64;
    let mut listed: Vec<u64> = Vec::new();
    for k in 0..kills {
        let mut child = prism()
            .arg("dataset")
            .arg(&cfg)
            .arg("-o")
            .arg(&out)
            .arg("--quiet")
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_secs_f64(lcg(&mut rng) * whole * 0.5));
        let _ = child.kill(); // SIGKILL on Unix
        let _ = child.wait();
        let now = manifest(&out);
        let mut sorted = now.clone();
        sorted.sort_unstable();
        sorted.dedup();
        assert_eq!(
            sorted.len(),
            now.len(),
            "kill {k}: a frame listed twice: {now:?}"
        );
        assert!(
            listed.iter().all(|i| now.contains(i)),
            "kill {k}: lost a frame: {listed:?} -> {now:?}"
        );
        let files = frames(&out);
        for i in &now {
            for ext in ["exr", "json", "png"] {
                let name = format!("{i:06}.{ext}");
                assert!(
                    files.get(&name) == full.get(&name),
                    "kill {k}: listed {name} is not the full run's"
                );
            }
        }
        listed = now;
    }
    ok(&dataset(&cfg, &out, &[]));
    let mut m = manifest(&out);
    m.sort_unstable();
    assert_eq!(m, (0..8).collect::<Vec<_>>());
    assert!(
        frames(&out) == full,
        "the resumed dataset differs from the uninterrupted one"
    );
}

/// The pixel data of an EXR, channel by channel.
fn exr_pixels(p: &Path) -> BTreeMap<String, Vec<f32>> {
    use exr::prelude::*;
    let img = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_file(p)
        .unwrap();
    img.layer_data
        .channel_data
        .list
        .iter()
        .map(|c| {
            (
                c.name.to_string(),
                c.sample_data.values_as_f32().collect::<Vec<f32>>(),
            )
        })
        .collect()
}

#[test]
fn an_exported_frame_renders_the_same_with_prism_render() {
    let full = full_run();
    let dir = workdir("export");
    let cfg = config(&dir, |t| t);
    let out = dir.join("out");
    ok(&dataset(&cfg, &out, &["--export-frame", "6"]));
    let scene = out.join("frames/000006.ron");
    assert!(scene.is_file());
    assert!(
        !out.join("frames/000006.exr").exists(),
        "export renders nothing"
    );
    // From another folder: the exported scene's paths are absolute.
    let exr = dir.join("render.exr");
    let png = dir.join("render.png");
    let o = prism()
        .current_dir(std::env::temp_dir())
        .arg("render")
        .arg(&scene)
        .arg("-o")
        .arg(&exr)
        .arg("--preview")
        .arg(&png)
        .arg("--quiet")
        .output()
        .unwrap();
    ok(&o);
    let want = exr_pixels(&full.join("frames/000006.exr"));
    let got = exr_pixels(&exr);
    assert_eq!(
        want.keys().collect::<Vec<_>>(),
        got.keys().collect::<Vec<_>>()
    );
    for (k, v) in &want {
        assert!(got[k] == *v, "channel {k} differs");
    }
    assert!(std::fs::read(&png).unwrap() == std::fs::read(full.join("frames/000006.png")).unwrap());
}

/// Exit 2 and an `error:` naming the file, the field and the fix (the callers check that
/// nothing was rendered).
fn refused(o: &Output, needles: &[&str]) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.starts_with("error: ") && !err.contains("panicked"),
        "{err}"
    );
    assert!(err.contains("hint:"), "no fix given: {err}");
    for n in needles {
        assert!(err.contains(n), "stderr lacks `{n}`:\n{err}");
    }
}

#[test]
fn bad_input_is_refused_before_any_frame_renders() {
    let dir = workdir("bad");
    // (case, text replaced in smoke.ron, its replacement, what stderr must name)
    let cases: [(&str, &str, &str, &[&str]); 7] = [
        (
            "missing shape",
            "keep_in_view: [\"ball\"]",
            "keep_in_view: [\"teapot\"]",
            &[
                "dataset.ron",
                "camera.keep_in_view[0]",
                "no shape named \"teapot\"",
                "\"ball\"",
            ],
        ),
        (
            "missing material",
            "[\"plastic\", \"paint\", \"metal\"]",
            "[\"plastic\", \"gold\"]",
            &["swaps[0].materials[1]", "no material \"gold\""],
        ),
        (
            "missing light",
            "target: \"emitters[0]\", intensity",
            "target: \"emitters[3]\", intensity",
            &["lights[1].target", "1 emitter(s)"],
        ),
        (
            "inverted range",
            "radius: (2.4, 3.2)",
            "radius: (3.2, 2.4)",
            &["camera.look_at.radius", "inverted", "(2.4, 3.2)"],
        ),
        (
            "inverted subset",
            "shown: (1, 3)",
            "shown: (3, 1)",
            &["objects.subsets[0].shown", "inverted"],
        ),
        (
            "unknown library",
            "Library(\"colorchecker\")",
            "Library(\"munsell\")",
            &["materials[0].reflectance", "munsell", "colorchecker"],
        ),
        (
            "keep in view impossible",
            "fov: (35, 50)",
            "fov: (0.5, 1)",
            &["camera.keep_in_view", "attempts"],
        ),
    ];
    for (name, from, to, needles) in cases {
        let cfg = config(&dir, |t| {
            assert!(t.contains(from), "{name}: smoke.ron has no `{from}`");
            t.replace(from, to)
        });
        let out = dir.join(name.replace(' ', "_"));
        let o = dataset(&cfg, &out, &[]);
        refused(&o, needles);
        assert!(!out.exists(), "{name}: the output folder was made");
    }

    // An output folder holding another dataset: refused naming the change, left as it was.
    let cfg = config(&dir, |t| t);
    let out = dir.join("taken");
    ok(&dataset(&cfg, &out, &["--frames", "0"]));
    let before = frames(&out);
    let cfg2 = config(&dir, |t| t.replace("seed: 1,", "seed: 2,"));
    let o = dataset(&cfg2, &out, &[]);
    refused(
        &o,
        &["holds another dataset", "config.seed: 1 → 2", "--force"],
    );
    assert!(frames(&out) == before);
    // A folder of someone else's files.
    let foreign = dir.join("foreign");
    std::fs::create_dir_all(&foreign).unwrap();
    std::fs::write(foreign.join("notes.txt"), "mine").unwrap();
    refused(&dataset(&cfg, &foreign, &[]), &["notes.txt", "not empty"]);
    assert_eq!(
        std::fs::read_to_string(foreign.join("notes.txt")).unwrap(),
        "mine"
    );
    // Frames outside the dataset, a shard past the count.
    refused(
        &dataset(&cfg, &dir.join("f"), &["--frames", "8"]),
        &["--frames", "0..8"],
    );
    assert!(!dir.join("f").exists());
    refused(
        &dataset(&cfg, &dir.join("s"), &["--shard", "3", "--num-shards", "3"]),
        &["--shard"],
    );
    assert!(!dir.join("s").exists());
    refused(
        &dataset(&cfg, &dir.join("t"), &["--threads", "0"]),
        &["dataset.ron: --threads", "at least 1"],
    );
    assert!(!dir.join("t").exists());
    // --force starts the dataset over.
    ok(&dataset(&cfg2, &out, &["--force", "--frames", "0"]));
    assert_eq!(manifest(&out), vec![0]);
}

/// Frames that change only camera, lights and materials reuse the first frame's geometry (a
/// mesh among it): one build for the run, and each frame byte-identical to a fresh build of it.
#[test]
fn frames_that_keep_their_geometry_build_it_once_and_match_fresh_builds() {
    let dir = workdir("geometry");
    let base = tabletop().replace(
            "    shapes: [\n",
            &format!(
                "    shapes: [\n        (name: \"prism\", shape: Mesh(path: {:?}), material: \"plastic\", to_world: [Scale((0.15, 0.15, 0.15)), Translate((0.5, 0.9, -0.4))]),\n",
                root().join("scenes/meshes/prism.obj")
            ),
        );
    std::fs::write(dir.join("base.ron"), base).unwrap();
    let cfg = config_on_base(&dir, |t| {
        let a = t.find("    objects: (").unwrap();
        let b = a + t[a..].find("\n    ),\n").unwrap() + "\n    ),\n".len();
        format!("{}{}", &t[..a], &t[b..])
    });
    let full = dir.join("full");
    let o = dataset(&cfg, &full, &[]);
    ok(&o);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("8 rendered") && err.contains("geometry built 1 time(s)"),
        "{err}"
    );
    let want = frames(&full);
    let alone = dir.join("alone");
    for i in ["3", "6"] {
        ok(&dataset(&cfg, &alone, &["--frames", i]));
    }
    let got = frames(&alone);
    assert_eq!(got.len(), 6);
    for (name, bytes) in got {
        assert!(
            want[&name] == bytes,
            "{name}: reused geometry differs from a fresh build"
        );
    }
}

/// smoke.ron with `seed` and `sensor: <variation>` (NIKON, CIE: those sensor files).
fn sensor_config(dir: &Path, seed: u64, variation: &str) -> PathBuf {
    let s = root().join("configs/sensors");
    let v = variation
        .replace("NIKON", &format!("{:?}", s.join("nikon_d810.ron")))
        .replace("CIE", &format!("{:?}", s.join("cie1931.ron")));
    config(dir, |t| {
        t.replace("seed: 1,", &format!("seed: {seed},\n    sensor: {v},"))
    })
}

/// A sensor from a list per frame: each frame's EXR has its own sensor's channels (camera.R and
/// corrected.R only for the camera sensor), its JSON names the file and exposure, and a
/// frame rendered alone equals the full run byte for byte.
#[test]
fn frames_take_their_sensor_from_the_list_and_render_alone_identically() {
    let dir = workdir("sensor");
    let cfg = sensor_config(&dir, 2, "(files: [CIE, NIKON], exposure: (-1, 1))");
    let out = dir.join("full");
    ok(&dataset(&cfg, &out, &[]));
    let mut seen = [false; 2];
    for i in 0..8 {
        let stem = out.join(format!("frames/{i:06}"));
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(stem.with_extension("json")).unwrap())
                .unwrap();
        let s = &json["frame"]["sensor"];
        let file = s["file"].as_str().unwrap();
        let e = s["exposure"].as_f64().unwrap();
        assert!((-1.0..=1.0).contains(&e), "frame {i}: exposure {e}");
        let px = exr_pixels(&stem.with_extension("exr"));
        let camera = file.ends_with("nikon_d810.ron");
        assert!(camera || file.ends_with("cie1931.ron"), "{file}");
        seen[camera as usize] = true;
        assert_eq!(px.contains_key("camera.R"), camera, "frame {i} ({file})");
        assert_eq!(px.contains_key("corrected.R"), camera, "frame {i} ({file})");
        assert!(
            px.contains_key("R") && px.contains_key("X"),
            "frame {i}: both write sRGB, XYZ"
        );
    }
    assert_eq!(
        seen,
        [true, true],
        "seed 2 draws both sensors in 8 frames (seed 1 draws CIE alone: p = 1/128)"
    );
    let full = frames(&out);
    let one = dir.join("one");
    ok(&dataset(
        &cfg,
        &one,
        &["--frames", "3..5", "--threads", "1"],
    ));
    let got = frames(&one);
    assert_eq!(got.len(), 2 * 3);
    for (name, bytes) in got {
        assert!(full[&name] == bytes, "{name} differs from the full run");
    }
}

/// Exposure e multiplies every sensor channel by 2^e: the same frames with `exposure: (e, e)`
/// and without the variation draw the same scene and render seed, so each channel's ratio is
/// 2^e up to the rounding of one f32 multiply (relative 2⁻²³ on the value and the factor; the
/// tolerance 1e-6 is ~4 of those); the AOV channels stay as they were.
#[test]
fn exposure_scales_the_sensor_channels_by_two_to_the_stops() {
    let base = full_run();
    let dir = workdir("exposure");
    let e = 1.5f64;
    let cfg = sensor_config(&dir, 1, &format!("(exposure: ({e}, {e}))"));
    let out = dir.join("out");
    ok(&dataset(&cfg, &out, &["--frames", "0..2"]));
    let k = 2f64.powf(e);
    for i in 0..2 {
        let stem = format!("frames/{i:06}.exr");
        let a = exr_pixels(&base.join(&stem));
        let b = exr_pixels(&out.join(&stem));
        assert_eq!(a.keys().collect::<Vec<_>>(), b.keys().collect::<Vec<_>>());
        let mut checked = 0;
        for (name, va) in &a {
            let vb = &b[name];
            // Colour and spectral channels are the sensor's; the rest are AOVs.
            let sensor =
                ["R", "G", "B", "X", "Y", "Z"].contains(&name.as_str()) || name.starts_with("S0.");
            for (x, y) in va.iter().zip(vb) {
                let want = if sensor { *x as f64 * k } else { *x as f64 };
                assert!(
                    (*y as f64 - want).abs() <= 1e-6 * want.abs(),
                    "frame {i} {name}: {y} vs {want}"
                );
            }
            checked += sensor as usize;
        }
        assert!(checked >= 6, "frame {i}: sensor channels {:?}", a.keys());
    }
}

#[test]
fn bad_sensor_variations_are_refused_before_any_frame_renders() {
    let dir = workdir("badsensor");
    let cases: [(&str, &str, &[&str]); 3] = [
        (
            "missing file",
            "(files: [CIE, \"nope.ron\"])",
            &[
                "sensor.files[1]",
                "nope.ron",
                "does not exist",
                "relative to the dataset config",
            ],
        ),
        (
            "inverted exposure",
            "(exposure: (1, -1))",
            &["sensor.exposure", "inverted", "(-1, 1)"],
        ),
        ("empty list", "(files: [])", &["sensor.files", "empty"]),
    ];
    for (name, v, needles) in cases {
        let cfg = sensor_config(&dir, 1, v);
        let out = dir.join(name.replace(' ', "_"));
        refused(&dataset(&cfg, &out, &[]), needles);
        assert!(!out.exists(), "{name}: the output folder was made");
    }
}

/// `dataset.json` holds the SHA-256 of every file the dataset reads: a resume after a texture
/// changed is refused naming the texture (exit 2, nothing rendered or removed), `--force`
/// starts over, and unchanged files resume.
#[test]
fn a_changed_texture_refuses_the_resume_naming_the_file() {
    let dir = workdir("assets");
    let base = tabletop().replace(
        "Diffuse(reflectance: Rgb(0.45, 0.28, 0.15))",
        "Diffuse(reflectance: Bitmap(path: \"wood.png\"))",
    );
    assert!(base.contains("wood.png"));
    std::fs::write(dir.join("base.ron"), base).unwrap();
    let textures = root().join("scenes/textures");
    std::fs::copy(textures.join("grid.png"), dir.join("wood.png")).unwrap();
    let cfg = config_on_base(&dir, |t| t);
    let out = dir.join("out");
    ok(&dataset(&cfg, &out, &["--frames", "0"]));
    let identity: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("dataset.json")).unwrap()).unwrap();
    let inputs = identity["inputs"].as_object().unwrap();
    assert!(
        inputs.contains_key("wood.png") && inputs.keys().any(|k| k.ends_with("sky.exr")),
        "{inputs:?}"
    );
    // Unchanged: the rerun resumes.
    let o = dataset(&cfg, &out, &["--frames", "0..2"]);
    ok(&o);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("1 rendered, 1 skipped"), "{err}");
    // Changed: refused, naming the file, the folder as it was.
    std::fs::copy(textures.join("leaf_alpha.png"), dir.join("wood.png")).unwrap();
    let before = frames(&out);
    refused(
        &dataset(&cfg, &out, &[]),
        &[
            "holds another dataset",
            "the contents of the input file `wood.png`",
            "--force",
        ],
    );
    assert!(frames(&out) == before);
    assert_eq!(manifest(&out), vec![0, 1]);
    // --force starts over with the new texture.
    ok(&dataset(&cfg, &out, &["--force", "--frames", "0"]));
    assert_eq!(manifest(&out), vec![0]);
    assert!(frames(&out)["000000.exr"] != before["000000.exr"]);
}

/// tabletop() with class labels and the id layers: the ball and box are "toy", the marble
/// "marble", the bead "bead", the table "furniture" (sorted: bead 1, furniture 2, marble 3,
/// toy 4 while every shape shows).
fn labelled_tabletop() -> String {
    tabletop()
        .replace(
            "    integrator: (max_depth: 6),\n",
            "    integrator: (max_depth: 6),\n    aovs: [\"instance\", \"label\", \"material\"],\n",
        )
        .replace(
            "(name: \"table\",",
            "(name: \"table\", label: \"furniture\",",
        )
        .replace("(name: \"ball\",", "(name: \"ball\", label: \"toy\",")
        .replace("(name: \"box\",", "(name: \"box\", label: \"toy\",")
        .replace(
            "(name: \"marble\",",
            "(name: \"marble\", label: \"marble\",",
        )
        .replace("(name: \"bead\",", "(name: \"bead\", label: \"bead\",")
}

fn json_file(p: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

/// Every frame of `out` (8 frames, config `cfg`) against `prism render` of its exported scene:
/// the EXR's pixels bit for bit (ids included) and the JSON's `labels`, `materials` and
/// `objects` (names, ids, labels, materials, transforms) equal; and every id a frame uses is the
/// one `dataset.json`'s tables give its class and instance.
fn check_against_exports(dir: &Path, cfg: &Path, out: &Path) {
    let ds = json_file(&out.join("dataset.json"));
    let classes: BTreeMap<String, u64> = ds["classes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            (
                c["name"].as_str().unwrap().into(),
                c["id"].as_u64().unwrap(),
            )
        })
        .collect();
    let names: Vec<&str> = classes.keys().map(|s| s.as_str()).collect();
    assert_eq!(names, ["bead", "furniture", "marble", "toy"]);
    let instances: BTreeMap<String, u64> = ds["instances"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            (
                c["name"].as_str().unwrap().into(),
                c["id"].as_u64().unwrap(),
            )
        })
        .collect();
    let exp = dir.join("exported");
    for i in 0..8u32 {
        let stem = out.join(format!("frames/{i:06}"));
        let frame = json_file(&stem.with_extension("json"));
        ok(&dataset(cfg, &exp, &["--export-frame", &i.to_string()]));
        let exr = dir.join(format!("render{i}.exr"));
        let o = prism()
            .current_dir(std::env::temp_dir())
            .arg("render")
            .arg(exp.join(format!("frames/{i:06}.ron")))
            .arg("-o")
            .arg(&exr)
            .arg("--quiet")
            .output()
            .unwrap();
        ok(&o);
        let fresh = json_file(&exr.with_extension("json"));
        for key in ["labels", "materials", "objects"] {
            assert_eq!(frame[key], fresh[key], "frame {i}: `{key}` differs");
        }
        let (want, got) = (exr_pixels(&stem.with_extension("exr")), exr_pixels(&exr));
        assert_eq!(
            want.keys().collect::<Vec<_>>(),
            got.keys().collect::<Vec<_>>()
        );
        for (k, v) in &want {
            assert!(got[k] == *v, "frame {i}: channel {k} differs");
        }
        // The frame's ids are the dataset's, and a hidden shape is not listed.
        let shown = &frame["frame"]["shown"][0];
        for o in frame["objects"].as_array().unwrap() {
            let name = o["name"].as_str().unwrap();
            assert_eq!(
                o["instance_id"].as_u64(),
                Some(instances[name]),
                "frame {i}: {name}"
            );
            if let Some(l) = o["label"].as_str() {
                assert_eq!(
                    o["label_id"].as_u64(),
                    Some(classes[l]),
                    "frame {i}: {name}"
                );
            }
            if ["box", "marble", "bead"].contains(&name) && shown.is_array() {
                assert!(
                    shown.as_array().unwrap().iter().any(|s| s == name),
                    "frame {i}: {name} is hidden"
                );
            }
        }
        let listed = frame["labels"].as_array().unwrap();
        assert_eq!(
            listed,
            ds["classes"].as_array().unwrap(),
            "frame {i}: class table"
        );
        // Every id in the layers names a listed object or class.
        for (layer, ids) in [("instance.ID", &instances), ("label.ID", &classes)] {
            for v in &want[layer] {
                assert!(
                    *v == 0.0 || ids.values().any(|&x| x as f32 == *v),
                    "frame {i}: {layer} {v}"
                );
            }
        }
    }
}

#[test]
fn ids_are_fixed_per_dataset_and_every_frame_matches_a_fresh_render_of_its_export() {
    let dir = workdir("ids");
    std::fs::write(dir.join("base.ron"), labelled_tabletop()).unwrap();
    // Subsets hide some of box, marble and bead in most frames; placement moves the rest.
    let cfg = config_on_base(&dir, |t| t);
    let out = dir.join("out");
    ok(&dataset(&cfg, &out, &[]));
    let hidden = (0..8)
        .filter(|i| {
            let f = json_file(&out.join(format!("frames/{i:06}.json")));
            f["frame"]["shown"][0].as_array().unwrap().len() < 3
        })
        .count();
    assert!(hidden >= 4, "only {hidden} frames hide a shape");
    check_against_exports(&dir, &cfg, &out);
}

#[test]
fn frames_that_reuse_geometry_name_their_own_materials() {
    let dir = workdir("reuse-ids");
    std::fs::write(dir.join("base.ron"), labelled_tabletop()).unwrap();
    // No object variations: every frame keeps the geometry, and the box's material is swapped.
    let cfg = config_on_base(&dir, |t| {
        let a = t.find("    objects: (").unwrap();
        let b = a + t[a..].find("\n    ),\n").unwrap() + "\n    ),\n".len();
        format!("{}{}", &t[..a], &t[b..])
    });
    let out = dir.join("out");
    let o = dataset(&cfg, &out, &[]);
    ok(&o);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("geometry built 1 time(s)"), "{err}");
    let mut swapped = std::collections::BTreeSet::new();
    for i in 0..8 {
        let f = json_file(&out.join(format!("frames/{i:06}.json")));
        let m = f["frame"]["swaps"][0]["material"]
            .as_str()
            .unwrap()
            .to_string();
        let the_box = f["objects"]
            .as_array()
            .unwrap()
            .iter()
            .find(|o| o["name"] == "box")
            .unwrap();
        assert_eq!(the_box["material"], m.as_str(), "frame {i}");
        swapped.insert(m);
    }
    assert!(swapped.len() >= 2, "the box kept {swapped:?}");
    check_against_exports(&dir, &cfg, &out);
}

/// The custom attributes of an EXR's first header, as text.
fn exr_attributes(p: &Path) -> BTreeMap<String, String> {
    let meta = exr::meta::MetaData::read_from_file(p, false).unwrap();
    meta.headers[0]
        .own_attributes
        .other
        .iter()
        .map(|(k, v)| {
            let v = match v {
                exr::meta::attribute::AttributeValue::Text(t) => t.to_string(),
                v => format!("{v:?}"),
            };
            (k.to_string(), v)
        })
        .collect()
}

/// The dataset exposure says what it did: the EXR header and the JSON's `sensor.exposure` give
/// its scale and the channels it scaled, and `stderr.*` scales with them (the standard error
/// of the values in the file): the same frames with and without `exposure: (e, e)` draw the
/// same scene and seed, so the ratio is 2^e up to one f32 multiply (tolerance 1e-6 relative,
/// as in `exposure_scales_the_sensor_channels_by_two_to_the_stops`).
#[test]
fn exposure_is_recorded_and_scales_the_standard_errors() {
    let dir = workdir("exposure-meta");
    let base = tabletop().replace(
        "    integrator: (max_depth: 6),\n",
        "    integrator: (max_depth: 6),\n    aovs: [\"stderr\", \"depth\"],\n",
    );
    std::fs::write(dir.join("base.ron"), base).unwrap();
    let e = -0.75f64;
    let k = 2f64.powf(e);
    let plain = config_on_base(&dir, |t| t);
    let (a, b) = (dir.join("plain"), dir.join("exposed"));
    ok(&dataset(&plain, &a, &["--frames", "0..2"]));
    let sub = dir.join("sub");
    std::fs::create_dir_all(&sub).unwrap();
    let exposed = config_on_base(&sub, |t| {
        t.replace(
            "seed: 1,",
            &format!("seed: 1,\n    sensor: (exposure: ({e}, {e})),"),
        )
    });
    std::fs::copy(dir.join("base.ron"), sub.join("base.ron")).unwrap();
    ok(&dataset(&exposed, &b, &["--frames", "0..2"]));
    for i in 0..2 {
        let stem = format!("frames/{i:06}");
        let (ja, jb) = (
            json_file(&a.join(&stem).with_extension("json")),
            json_file(&b.join(&stem).with_extension("json")),
        );
        assert!(ja["sensor"]["exposure"].is_null(), "frame {i}");
        let x = &jb["sensor"]["exposure"];
        assert!(
            (x["scale"].as_f64().unwrap() - k).abs() < 1e-7,
            "frame {i}: {x}"
        );
        assert!(
            (x["stops"].as_f64().unwrap() - e).abs() < 1e-6,
            "frame {i}: {x}"
        );
        let listed: Vec<&str> = x["channels"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c.as_str().unwrap())
            .collect();
        assert!(
            listed.contains(&"R") && listed.contains(&"stderr.*"),
            "{listed:?}"
        );
        assert!(!listed.iter().any(|c| c.starts_with("depth")), "{listed:?}");
        let h = exr_attributes(&b.join(&stem).with_extension("exr"));
        let scale: f64 = h["prism:datasetExposureScale"].parse().unwrap();
        assert!((scale - k).abs() < 1e-7, "frame {i}: header {scale}");
        assert!(!exr_attributes(&a.join(&stem).with_extension("exr"))
            .contains_key("prism:datasetExposureScale"));
        let (pa, pb) = (
            exr_pixels(&a.join(&stem).with_extension("exr")),
            exr_pixels(&b.join(&stem).with_extension("exr")),
        );
        let mut checked = 0;
        for (name, va) in pa.iter().filter(|(n, _)| n.starts_with("stderr.")) {
            for (x, y) in va.iter().zip(&pb[name]) {
                let want = *x as f64 * k;
                assert!(
                    (*y as f64 - want).abs() <= 1e-6 * want.abs(),
                    "frame {i} {name}: {y} vs {want}"
                );
            }
            checked += 1;
        }
        assert!(
            checked >= 1,
            "frame {i}: no stderr channel in {:?}",
            pa.keys()
        );
    }
}

/// A dataset started with a bare config name inside its folder and the same dataset run from
/// elsewhere with absolute paths write byte-identical `dataset.json` and frames (paths in them
/// are relative to the config or the base scene), and the second resumes the first's folder.
#[test]
fn a_dataset_is_the_same_from_any_working_directory() {
    let dir = workdir("cwd");
    let ds = dir.join("ds");
    std::fs::create_dir_all(&ds).unwrap();
    std::fs::write(ds.join("base.ron"), labelled_tabletop()).unwrap();
    let cfg = config_on_base(&ds, |t| t);
    let text = std::fs::read_to_string(&cfg)
        .unwrap()
        .replace(&format!("{:?}", ds.join("base.ron")), "\"base.ron\"");
    std::fs::write(&cfg, text).unwrap();
    let run = |cwd: &Path, cfg: &Path, out: &Path, frames: &str| {
        prism()
            .current_dir(cwd)
            .arg("dataset")
            .arg(cfg)
            .arg("-o")
            .arg(out)
            .args(["--quiet", "--frames", frames])
            .env_remove("SLURM_ARRAY_TASK_ID")
            .env_remove("SLURM_ARRAY_TASK_COUNT")
            .env_remove("JOB_COMPLETION_INDEX")
            .output()
            .unwrap()
    };
    ok(&run(
        &ds,
        Path::new("dataset.ron"),
        Path::new("out"),
        "0..3",
    ));
    let other = dir.join("out2");
    ok(&run(&std::env::temp_dir(), &cfg, &other, "0..3"));
    let here = ds.join("out");
    assert!(
        std::fs::read(here.join("dataset.json")).unwrap()
            == std::fs::read(other.join("dataset.json")).unwrap(),
        "dataset.json depends on the working directory"
    );
    let (a, b) = (frames(&here), frames(&other));
    assert_eq!(a.keys().collect::<Vec<_>>(), b.keys().collect::<Vec<_>>());
    assert_eq!(a.len(), 9);
    for (name, bytes) in &a {
        assert!(b[name] == *bytes, "{name} depends on the working directory");
    }
    // Resuming the bare-name run from elsewhere: nothing to redo, nothing refused.
    let o = run(&std::env::temp_dir(), &cfg, &here, "0..4");
    ok(&o);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("1 rendered, 3 skipped"), "{err}");
}

/// A dataset rendered to 1000 nm under an RGB sky (radiance RGB × D65, which ends at 830 nm)
/// says so at `--check`, as `prism render` of its base scene does, once, naming the map; the
/// same warning for an envmap that only the variation's `files` list names.
#[test]
fn check_reports_what_prism_render_warns_about_once() {
    let dir = workdir("warn");
    let base = tabletop().replace(
        "    integrator: (max_depth: 6),\n",
        "    integrator: (max_depth: 6),\n    spectral: (range: (400, 1000)),\n",
    );
    std::fs::write(dir.join("base.ron"), &base).unwrap();
    let o = prism()
        .arg("render")
        .arg(dir.join("base.ron"))
        .args(["-o"])
        .arg(dir.join("r.exr"))
        .args(["--spp", "1", "--quiet"])
        .output()
        .unwrap();
    ok(&o);
    let render = String::from_utf8_lossy(&o.stderr);
    assert!(render.contains("830 nm only"), "{render}");
    // The variation's sky is a copy under another name: its warning names that file.
    std::fs::copy(
        root().join("scenes/textures/sky.exr"),
        dir.join("other_sky.exr"),
    )
    .unwrap();
    let cfg = config_on_base(&dir, |t| {
        t.replace(
            &format!("[{:?}]", root().join("scenes/textures/sky.exr")),
            "[\"other_sky.exr\"]",
        )
    });
    let o = dataset(&cfg, &dir.join("out"), &["--check"]);
    ok(&o);
    let err = String::from_utf8_lossy(&o.stderr);
    let lines: Vec<&str> = err.lines().filter(|l| l.contains("830 nm only")).collect();
    assert!(lines.iter().any(|l| !l.contains("envmap.files")), "{err}");
    assert!(
        lines
            .iter()
            .any(|l| l.contains("envmap.files[0] `other_sky.exr`")),
        "{err}"
    );
    let mut unique = lines.clone();
    unique.dedup();
    assert_eq!(unique.len(), lines.len(), "a warning repeated: {err}");
}

/// `outputs.aovs` gives every frame those layers (the base scene asks for none), and `splits`
/// are listed in `dataset.json`; an unknown AOV, overlapping splits or a split past the last
/// frame are refused before any frame renders.
#[test]
fn outputs_aovs_and_splits_are_the_datasets() {
    let dir = workdir("aovs");
    let with = |splits: &str, aovs: &str| {
        let new = format!("splits: {{{splits}}},\n    outputs: (aovs: [{aovs}], preview: true,");
        move |t: String| t.replace("outputs: (preview: true,", &new)
    };
    let cfg = config(
        &dir,
        with(
            "\"train\": (0, 6), \"test\": (6, 8)",
            "\"depth\", \"label\"",
        ),
    );
    let out = dir.join("out");
    ok(&dataset(&cfg, &out, &["--frames", "0..1"]));
    let px = exr_pixels(&out.join("frames/000000.exr"));
    assert!(
        px.contains_key("depth.Z") && px.contains_key("label.ID"),
        "{:?}",
        px.keys()
    );
    let ds = json_file(&out.join("dataset.json"));
    assert_eq!(ds["splits"]["train"], serde_json::json!([0, 6]));
    assert_eq!(ds["splits"]["test"], serde_json::json!([6, 8]));
    let cases = [
        (
            "\"train\": (0, 6), \"test\": (5, 8)",
            "\"depth\"",
            "overlaps split",
        ),
        ("\"test\": (6, 9)", "\"depth\"", "within 0..8"),
        ("\"test\": (6, 8)", "\"dpeth\"", "unknown AOV \"dpeth\""),
    ];
    for (k, (splits, aovs, needle)) in cases.into_iter().enumerate() {
        let bad = workdir(&format!("aovs-bad{k}"));
        let cfg = config(&bad, with(splits, aovs));
        let o = dataset(&cfg, &bad.join("out"), &[]);
        refused(&o, &[needle]);
        assert!(frames(&bad.join("out")).is_empty(), "case {k} rendered");
    }
}
