//! `prism dataset` labels and layers: ids fixed per dataset, frames matching a fresh render of
//! their export, reused geometry, the working directory, and `outputs.aovs`/`splits`.

mod dataset_util;
use dataset_util::*;

use std::collections::BTreeMap;
use std::path::Path;

/// Frames 0..n of `out` (config `cfg`) against `prism render` of its exported scene:
/// the EXR's pixels bit for bit (ids included) and the JSON's `labels`, `materials` and
/// `objects` (names, ids, labels, materials, transforms) equal; and every id a frame uses is the
/// one `dataset.json`'s tables give its class and instance.
fn check_against_exports(dir: &Path, cfg: &Path, out: &Path, n: u32) {
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
    for i in 0..n {
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
        // Every key of the EXR header but the two that differ by design: `prism:scene` (the
        // frame names its base scene, the render its exported copy) and `prism:renderSeconds`
        // (a frame's files must not depend on the clock).
        let (mut hw, mut hg) = (exr_header(&stem.with_extension("exr")), exr_header(&exr));
        assert_eq!(hw["prism:renderSeconds"], "see manifest.jsonl", "frame {i}");
        assert_eq!(hw["prism:scene"], "base.ron", "frame {i}");
        for k in ["prism:scene", "prism:renderSeconds"] {
            hw.remove(k);
            hg.remove(k);
        }
        assert_eq!(
            hw.keys().collect::<Vec<_>>(),
            hg.keys().collect::<Vec<_>>(),
            "frame {i}: header keys"
        );
        assert!(hw.len() > 20, "frame {i}: only {} header keys", hw.len());
        for (k, v) in &hw {
            assert_eq!(v, &hg[k], "frame {i}: header `{k}` differs");
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

/// smoke.ron with a second sensor on the same paths (`nikon.*` channels in every frame).
fn two_sensors(t: String) -> String {
    let nikon = root().join("configs/sensors/nikon_d810.ron");
    t.replace(
        "outputs: (preview: true,",
        &format!("outputs: (sensors: [(name: \"nikon\", sensor: File({nikon:?}))], preview: true,"),
    )
}

/// Subsets, placement, swaps, two sensors and the id layers: every frame's EXR (sensor and
/// id channels) equals `prism render` of its export bit for bit, and its JSON's tables.
#[test]
fn ids_are_fixed_per_dataset_and_every_frame_matches_a_fresh_render_of_its_export() {
    let dir = workdir("ids");
    std::fs::write(dir.join("base.ron"), labelled_tabletop()).unwrap();
    // Subsets hide some of box, marble and bead in most frames; placement moves the rest.
    let cfg = config_on_base(&dir, two_sensors);
    let out = dir.join("out");
    ok(&dataset(&cfg, &out, &[]));
    let hidden = (0..8)
        .filter(|i| {
            let f = json_file(&out.join(format!("frames/{i:06}.json")));
            f["frame"]["shown"][0].as_array().unwrap().len() < 3
        })
        .count();
    assert!(hidden >= 4, "only {hidden} frames hide a shape");
    check_against_exports(&dir, &cfg, &out, 8);
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
    check_against_exports(&dir, &cfg, &out, 8);
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

/// The id dataset (subsets, swaps, placement, two sensors, the id AOVs) killed: once between a
/// frame's renames and its manifest line (seeded frame), then twice by SIGKILL at seeded
/// moments; every listed frame stays the uninterrupted run's, and the resumed folder is
/// byte-identical to it (the long form, 40 frames and 10 kills, is `forty_frames_match_their_exports`).
#[test]
fn the_id_dataset_killed_at_random_moments_resumes_byte_identical() {
    let dir = workdir("ids-kill");
    std::fs::write(dir.join("base.ron"), labelled_tabletop()).unwrap();
    let cfg = config_on_base(&dir, two_sensors);
    let t = std::time::Instant::now();
    ok(&dataset(&cfg, &dir.join("full"), &[]));
    let whole = t.elapsed().as_secs_f64();
    let full = frames(&dir.join("full"));
    let mut rng = 29u64;
    let abort_at = (lcg(&mut rng) * 8.0) as u32;
    kill_and_resume(&cfg, &dir.join("out"), &full, abort_at, 2, 0.6 * whole, rng);
}

/// The long form (a benchmark: `cargo test --release --test dataset_ids -- --ignored`): 40
/// frames with subsets, swaps, placement, two sensors and the id AOVs, every one checked
/// against an independent `prism render` of its exported scene as above (pixels, ids, JSON
/// tables, every EXR header key); the run killed between a seeded frame's renames and its
/// manifest line and then `PRISM_KILLS` times (default 10) by SIGKILL at seeded moments, resumed
/// byte-identical; and the run started inside the config's folder with a bare config name
/// byte-identical to the one started elsewhere with absolute paths.
#[test]
#[ignore]
fn forty_frames_match_their_exports() {
    let dir = workdir("forty");
    std::fs::write(dir.join("base.ron"), labelled_tabletop()).unwrap();
    let cfg = config_on_base(&dir, |t| {
        assert!(t.contains("frames: 8,"));
        two_sensors(t).replace("frames: 8,", "frames: 40,")
    });
    let out = dir.join("out");
    let t = std::time::Instant::now();
    ok(&dataset(&cfg, &out, &[]));
    let whole = t.elapsed().as_secs_f64();
    check_against_exports(&dir, &cfg, &out, 40);
    let full = frames(&out);
    let kills: u32 = std::env::var("PRISM_KILLS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(10);
    let mut rng = 40u64;
    let abort_at = (lcg(&mut rng) * 40.0) as u32;
    kill_and_resume(
        &cfg,
        &dir.join("killed"),
        &full,
        abort_at,
        kills,
        whole,
        rng,
    );
    // From inside the config's folder, by its bare name, with a relative output folder.
    let text = std::fs::read_to_string(&cfg)
        .unwrap()
        .replace(&format!("{:?}", dir.join("base.ron")), "\"base.ron\"");
    // The same folder (paths to files outside it are relative to it, so a folder one level
    // deeper would write other `../` paths), the config rewritten in place.
    std::fs::write(&cfg, text).unwrap();
    let o = prism()
        .current_dir(&dir)
        .args(["dataset", "dataset.ron", "-o", "here", "--quiet"])
        .env_remove("SLURM_ARRAY_TASK_ID")
        .env_remove("SLURM_ARRAY_TASK_COUNT")
        .env_remove("JOB_COMPLETION_INDEX")
        .output()
        .unwrap();
    ok(&o);
    let here = frames(&dir.join("here"));
    assert_eq!(here.len(), full.len());
    for (name, bytes) in &here {
        assert!(
            full[name] == *bytes,
            "{name} depends on the working directory"
        );
    }
}
