//! `prism dataset` refusals and warnings: bad input refused (exit 2) before any frame renders,
//! a frame's scene that its render would refuse refused at `--check` (issue 30), a changed
//! input refuses the resume, and `--check` reports what `prism render` warns about.

mod dataset_util;
use dataset_util::*;

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
    // 10^6 threads took minutes to start (rayon starts up to 65,535 per pool).
    refused(
        &dataset(&cfg, &dir.join("t"), &["--threads", "1000000"]),
        &[
            "dataset.ron: --threads",
            "more than the 1024",
            "hint: give at most 1024",
        ],
    );
    assert!(!dir.join("t").exists());
    // --force starts the dataset over.
    ok(&dataset(&cfg2, &out, &["--force", "--frames", "0"]));
    assert_eq!(manifest(&out), vec![0]);
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

/// Every example in configs/datasets passes `--check` (each frame planned, every input read,
/// the output folder claimed) with its paths as written, run from its own folder.
#[test]
fn every_example_config_checks() {
    let ds = root().join("configs/datasets");
    let mut n = 0;
    for e in std::fs::read_dir(&ds).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "ron") {
            let out = workdir(&format!("example-{n}"));
            let o = prism()
                .current_dir(&ds)
                .arg("dataset")
                .arg(p.file_name().unwrap())
                .arg("-o")
                .arg(out.join("out"))
                .args(["--check", "--quiet"])
                .output()
                .unwrap();
            assert!(
                o.status.success(),
                "{}: {}",
                p.display(),
                String::from_utf8_lossy(&o.stderr)
            );
            n += 1;
        }
    }
    assert!(n >= 3, "{n} example configs");
}

/// An edit of a file's text.
type Edit = dyn Fn(String) -> String;

/// A tiny video dataset (configs/datasets/sequence.ron: 2 sequences of 2 frames, 16×12 at
/// 1 spp) on `dir`/base.ron, the tabletop with `scene` applied, and `edit` on the config.
fn sequence(
    dir: &std::path::Path,
    scene: &dyn Fn(String) -> String,
    edit: &dyn Fn(String) -> String,
) -> std::path::PathBuf {
    std::fs::write(dir.join("base.ron"), scene(tabletop())).unwrap();
    let ds = root().join("configs/datasets");
    let text = std::fs::read_to_string(ds.join("sequence.ron"))
        .unwrap()
        .replace(
            "\"scenes/tabletop.ron\"",
            &format!("{:?}", dir.join("base.ron")),
        )
        .replace(
            "\"../../scenes/textures/sky.exr\"",
            &format!("{:?}", root().join("scenes/textures/sky.exr")),
        )
        .replace("sequences: 3", "sequences: 2")
        .replace("frames_per_sequence: 8", "frames_per_sequence: 2")
        .replace(
            "spp: 8, resolution: (96, 72)",
            "spp: 1, resolution: (16, 12)",
        );
    let p = dir.join("dataset.ron");
    std::fs::write(&p, edit(text)).unwrap();
    p
}

/// A frame's scene that its render would refuse is refused at `--check` and before the first
/// frame of a run (exit 2, naming the dataset's field, the scene's file and field and the fix;
/// no output folder), not frame by frame while the run goes on (exit 1). The cases: a moving
/// object whose keys would shear (its base transform scales after it rotates, so the spin
/// about +y makes a shear: `motion.objects[0]`), and an open shutter on a scene with caustic
/// light tracing (`motion.shutter`). And a glTF model with its own node animation moved by
/// `motion.objects` (nested motion, issue 30 item 2) is not refused: it renders, exit 0.
#[test]
fn frames_whose_scene_the_render_would_refuse_are_refused_at_check() {
    let dir = workdir("frame-check");
    let sheared = |t: String| {
        let from = "Scale((0.12, 0.12, 0.12)), Translate((0.3, 0.87, -0.2))";
        assert!(t.contains(from));
        t.replace(
            from,
            "Rotate(axis: (0, 0, 1), angle: 30), Scale((0.2, 0.1, 0.1)), Translate((0.3, 0.87, -0.2))",
        )
    };
    let caustics = |t: String| {
        t.replace(
            "integrator: (max_depth: 6)",
            "integrator: (max_depth: 6, caustics: (light_paths: 1000))",
        )
    };
    let open = |t: String| t.replace("objects: [(shapes", "shutter: 0.5, objects: [(shapes");
    let cases: [(&str, &Edit, &Edit, &[&str]); 2] = [
        (
            "shear",
            &sheared,
            &|t| t,
            &[
                "dataset.ron",
                "motion.objects[0]",
                "base.ron",
                "shapes[4].animation",
                "shears",
                "frame 0",
            ],
        ),
        (
            "caustics",
            &caustics,
            &open,
            &[
                "dataset.ron",
                "motion.shutter",
                "base.ron",
                "integrator.caustics",
                "open shutter",
            ],
        ),
    ];
    for (name, scene, edit, needles) in cases {
        let cfg = sequence(&dir, scene, edit);
        for args in [&["--check"][..], &[]] {
            let out = dir.join(format!("{name}{}", args.len()));
            refused(&dataset(&cfg, &out, args), needles);
            assert!(!out.exists(), "{name} {args:?}: the output folder was made");
        }
    }
    // Nested motion: AnimatedTriangle (node animation) moved by motion.objects, flow layers on.
    let tri = root().join("tests/data/gltf/AnimatedTriangle.gltf");
    let nested = |t: String| {
        t.replace(
            "(name: \"bead\"",
            &format!("(name: \"tri\", shape: Gltf(path: {tri:?}), material: \"metal\", to_world: [Scale((0.2, 0.2, 0.2)), Translate((0.3, 0.9, 0.3))]),\n        (name: \"bead\""),
        )
    };
    let moved = |t: String| {
        open(t).replace(
            "shapes: [\"ball\", \"box\"], speed",
            "shapes: [\"ball\", \"tri\"], speed",
        )
    };
    let cfg = sequence(&dir, &nested, &moved);
    let out = dir.join("nested");
    ok(&dataset(&cfg, &out, &["--check"]));
    ok(&dataset(&cfg, &out, &[]));
    assert_eq!(manifest(&out), vec![0, 1, 2, 3]);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A camera trajectory drawn so far out that the scene refuses it (a walk whose keys reach
/// beyond 1e18, which 32-bit geometry cannot normalise) is the dataset's error while the frames
/// are planned: exit 2 at `--check` and on a run, naming the dataset's `motion.camera` with the
/// scene's words inside, and no output folder. Before, the message named the scene's
/// `camera.animation.keys[0].to_world` as a field of the dataset file, with a hint about Scale
/// and Matrix steps the user never wrote. (A shell drawn as far out is refused when the config
/// is read: `camera.look_at.radius`.)
#[test]
fn a_drawn_camera_walk_the_scene_refuses_names_the_dataset_field() {
    let dir = workdir("drawn-camera");
    let walk = |t: String| {
        t.replace(
            "camera: Orbit(speed: (15, 35))",
            "camera: Walk(speed: (1e20, 2e20), turn: 30)",
        )
    };
    let cfg = sequence(&dir, &|t| t, &walk);
    for args in [&["--check"][..], &[]] {
        let out = dir.join(format!("walk{}", args.len()));
        let o = dataset(&cfg, &out, args);
        refused(
            &o,
            &[
                "dataset.ron: motion.camera:",
                "frame 0",
                "camera.animation",
                "`motion.camera`",
            ],
        );
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!err.contains("Scale and Matrix"), "{err}");
        assert!(!out.exists(), "{args:?}: the output folder was made");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
