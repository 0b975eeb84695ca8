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
    assert!(frames(&shared) == full);
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
