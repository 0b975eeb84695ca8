//! `prism dataset` objects drawn from an asset folder (src/dataset/asset_folder.rs): meshes of
//! a folder with their class from a `pattern,class` file, scaled to a size, their ids fixed per
//! dataset in `dataset.json`, shown a few per frame and placed on the support.

mod dataset_util;
use dataset_util::*;

/// An edit of the config text.
type Edit = Box<dyn Fn(String) -> String>;

use std::collections::BTreeMap;
use std::path::Path;

/// `dir/assets`: prism.obj copied as two "mug" files and one the catch-all calls "clutter".
fn folder(dir: &Path, classes: &str) {
    let a = dir.join("assets");
    std::fs::create_dir_all(&a).unwrap();
    for n in ["mug_a.obj", "mug_b.obj", "thing.obj"] {
        std::fs::copy(root().join("scenes/meshes/prism.obj"), a.join(n)).unwrap();
    }
    std::fs::write(a.join("notes.txt"), "not a mesh").unwrap();
    std::fs::write(dir.join("classes.csv"), classes).unwrap();
}

fn with_assets(fields: &'static str) -> impl Fn(String) -> String {
    move |t: String| {
        t.replace(
            "    objects: (\n",
            &format!("    objects: (\n        assets: ({fields}),\n"),
        )
        .replace(
            "outputs: (preview: true,",
            "outputs: (aovs: [\"instance\", \"label\"], preview: true,",
        )
    }
}

const ASSETS: &str = "folder: \"assets\", classes: \"classes.csv\", material: \"plastic\", size: 0.25, shown: (1, 2)";

/// Each asset's box has the longest side `size` (to 1e-5 relative: f32 bounds); `dataset.json`
/// lists the classes "mug" and "clutter" and the three assets with those class ids; each frame
/// shows 1–2 assets, lists exactly those in `objects` with the dataset's ids, places them on
/// the table, and its label layer holds only listed class ids; some frame shows a mug's pixels.
#[test]
fn assets_from_a_folder_have_fixed_ids_and_are_placed() {
    let dir = workdir("assets");
    folder(&dir, "# pattern,class\nmug_*.obj,mug\n*,clutter\n");
    let cfg = config(&dir, with_assets(ASSETS));
    let base = prism::dataset::Base::load(&cfg).unwrap();
    for n in ["asset:mug_a.obj", "asset:mug_b.obj", "asset:thing.obj"] {
        let (lo, hi) = base.bounds[base.names[n]];
        let side = (hi - lo).max_element();
        assert!((side / 0.25 - 1.0).abs() < 1e-5, "{n}: longest side {side}");
    }
    let out = dir.join("out");
    ok(&dataset(&cfg, &out, &["--frames", "0..6"]));
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
    assert!(
        classes.contains_key("mug") && classes.contains_key("clutter"),
        "{classes:?}"
    );
    let mut ids = BTreeMap::new();
    for x in ds["instances"].as_array().unwrap() {
        let name = x["name"].as_str().unwrap().to_string();
        if let Some(file) = name.strip_prefix("asset:") {
            let want = if file.starts_with("mug_") {
                "mug"
            } else {
                "clutter"
            };
            assert_eq!(x["label"], want, "{name}");
            assert_eq!(x["label_id"].as_u64(), Some(classes[want]), "{name}");
            ids.insert(name, x["id"].as_u64().unwrap());
        }
    }
    assert_eq!(ids.len(), 3, "{ids:?}");
    let mut mug_pixels = 0;
    for i in 0..6 {
        let f = json_file(&out.join(format!("frames/{i:06}.json")));
        let drawn: Vec<String> = f["frame"]["assets"]
            .as_array()
            .unwrap()
            .iter()
            .map(|s| s.as_str().unwrap().to_string())
            .collect();
        assert!((1..=2).contains(&drawn.len()), "frame {i}: {drawn:?}");
        let listed: Vec<&str> = f["objects"]
            .as_array()
            .unwrap()
            .iter()
            .filter_map(|o| o["name"].as_str().filter(|n| n.starts_with("asset:")))
            .collect();
        assert_eq!(listed, drawn, "frame {i}: shown assets");
        for o in f["objects"].as_array().unwrap() {
            if let Some(id) = ids.get(o["name"].as_str().unwrap()) {
                assert_eq!(o["instance_id"].as_u64(), Some(*id), "frame {i}");
            }
        }
        let placed: Vec<&str> = f["frame"]["placement"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| p["shape"].as_str().unwrap())
            .collect();
        assert!(
            drawn.iter().all(|d| placed.contains(&d.as_str())),
            "frame {i}: {placed:?}"
        );
        let px = exr_pixels(&out.join(format!("frames/{i:06}.exr")));
        for v in &px["label.ID"] {
            assert!(
                *v == 0.0 || classes.values().any(|&c| c as f32 == *v),
                "frame {i}: label {v}"
            );
            mug_pixels += (*v == classes["mug"] as f32) as u32;
        }
    }
    assert!(mug_pixels > 0, "no frame shows a mug");
}

/// A file no pattern matches, a missing folder, `shown` beyond the folder, and assets without
/// `objects.place` are refused at `--check` (exit 2, field, fix).
#[test]
fn bad_asset_folders_are_refused_at_check() {
    let dir = workdir("assets-bad");
    folder(&dir, "mug_*.obj,mug\n");
    let cases: [(Edit, &[&str]); 4] = [
        (
            Box::new(with_assets(ASSETS)),
            &["objects.assets.classes", "thing.obj", "*,other"],
        ),
        (
            Box::new(with_assets("folder: \"gone\", classes: \"classes.csv\", material: \"plastic\", size: 0.25, shown: (1, 2)")),
            &["objects.assets.folder", "cannot list"],
        ),
        (
            Box::new(with_assets("folder: \"assets\", classes: \"classes.csv\", material: \"plastic\", size: 0.25, shown: (1, 5)")),
            &["objects.assets.shown", "hi ≤ 3"],
        ),
        (
            Box::new(|t: String| {
                let t = with_assets(ASSETS)(t);
                let a = t.find("        place: (").unwrap();
                let b = a + t[a..].find('\n').unwrap() + 1;
                format!("{}{}", &t[..a], &t[b..])
            }),
            &["objects.assets", "objects.place"],
        ),
    ];
    for (k, (edit, needles)) in cases.into_iter().enumerate() {
        if k > 0 {
            std::fs::write(dir.join("classes.csv"), "mug_*.obj,mug\n*,clutter\n").unwrap();
        }
        let cfg = config(&dir, edit);
        let out = dir.join(format!("out{k}"));
        refused(&dataset(&cfg, &out, &["--check"]), needles);
        assert!(!out.exists(), "case {k}: the output folder was made");
    }
}

/// The `classes` file's patterns: `*` any run, `?` one character, the whole name matched.
#[test]
fn class_patterns_match_whole_file_names() {
    use prism::dataset::asset_folder::matches;
    assert!(matches("mug_*.obj", "mug_01.obj"));
    assert!(matches("*", "anything.ply"));
    assert!(matches("chair_??.ply", "chair_12.ply"));
    assert!(!matches("chair_??.ply", "chair_123.ply"));
    assert!(matches("*a*b*", "xxaxxbxx"));
    assert!(!matches("mug_*.obj", "mug_01.ply"));
    assert!(!matches("mug", "mug_01.obj"));
    assert!(matches("*.obj", ".obj"));
}

/// `dir/models`: prism.obj as "mug_a.obj" and the multi-part OrientationTest.gltf (13 meshes
/// under 13 nodes, 7 materials; tests/data/gltf/README.md) as "compass.gltf".
fn mixed_folder(dir: &Path) {
    let a = dir.join("models");
    std::fs::create_dir_all(&a).unwrap();
    std::fs::copy(root().join("scenes/meshes/prism.obj"), a.join("mug_a.obj")).unwrap();
    std::fs::copy(
        root().join("tests/data/gltf/OrientationTest.gltf"),
        a.join("compass.gltf"),
    )
    .unwrap();
    std::fs::write(dir.join("classes.csv"), "mug_*.obj,mug\n*.gltf,model\n").unwrap();
}

const MIXED: &str =
    "folder: \"models\", classes: \"classes.csv\", material: \"plastic\", size: 0.5, shown: (2, 2)";

/// A folder with an OBJ and a multi-part glTF: the glTF is ONE object. Its box's longest side
/// (all parts, after their node transforms) is `size` (to 1e-5 relative: f32 bounds);
/// `dataset.json` and every frame list it once, with the same instance id; every pixel of its
/// class carries that one instance id, and those pixels show several of its own materials
/// (so the mask covers several parts, not one); `prism render` of a frame's `--export-frame`
/// gives its id layers and objects exactly.
#[test]
fn a_gltf_asset_is_one_object_with_its_own_materials() {
    let dir = workdir("assets-gltf");
    mixed_folder(&dir);
    let cfg = config(&dir, |t| {
        with_assets(MIXED)(t)
            .replace(
                "aovs: [\"instance\", \"label\"]",
                "aovs: [\"instance\", \"label\", \"material\"]",
            )
            .replace("resolution: (64, 48)", "resolution: (96, 72)")
    });
    let base = prism::dataset::Base::load(&cfg).unwrap();
    let (lo, hi) = base.bounds[base.names["asset:compass.gltf"]];
    let side = (hi - lo).max_element();
    assert!((side / 0.5 - 1.0).abs() < 1e-5, "longest side {side}");
    let out = dir.join("out");
    ok(&dataset(&cfg, &out, &["--frames", "0..3"]));
    let ds = json_file(&out.join("dataset.json"));
    let model = ds["classes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["name"] == "model")
        .unwrap()["id"]
        .as_u64()
        .unwrap();
    let listed: Vec<&serde_json::Value> = ds["instances"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|x| x["name"].as_str().unwrap().contains("compass"))
        .collect();
    assert_eq!(listed.len(), 1, "{listed:?}");
    assert_eq!(listed[0]["name"], "asset:compass.gltf");
    assert_eq!(listed[0]["label_id"].as_u64(), Some(model));
    let id = listed[0]["id"].as_u64().unwrap();
    let mut materials = std::collections::BTreeSet::new();
    for i in 0..3 {
        let f = json_file(&out.join(format!("frames/{i:06}.json")));
        let mine: Vec<&serde_json::Value> = f["objects"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|o| o["name"].as_str().unwrap().contains("compass"))
            .collect();
        assert_eq!(mine.len(), 1, "frame {i}: {mine:?}");
        assert_eq!(mine[0]["instance_id"].as_u64(), Some(id), "frame {i}");
        let px = exr_pixels(&out.join(format!("frames/{i:06}.exr")));
        for ((l, n), m) in px["label.ID"]
            .iter()
            .zip(&px["instance.ID"])
            .zip(&px["material.ID"])
        {
            if *l == model as f32 {
                assert_eq!(*n, id as f32, "frame {i}: a part with its own instance id");
                materials.insert(*m as u32);
            } else {
                assert_ne!(*n, id as f32, "frame {i}: the model's id off its class");
            }
        }
    }
    assert!(
        materials.len() >= 2,
        "the model's pixels show materials {materials:?}"
    );
    // The frame's exported scene keeps the model one object: `prism render` of it gives the
    // frame's layers and objects exactly.
    ok(&dataset(&cfg, &out, &["--export-frame", "1"]));
    let exr = dir.join("again.exr");
    let scene = out.join("frames/000001.ron");
    ok(&prism()
        .args(["render", "-q", "-o"])
        .arg(&exr)
        .arg(&scene)
        .output()
        .unwrap());
    let (a, b) = (exr_pixels(&exr), exr_pixels(&out.join("frames/000001.exr")));
    for k in ["instance.ID", "label.ID", "material.ID"] {
        assert_eq!(a[k], b[k], "{k}");
    }
    let (ja, jb) = (
        json_file(&dir.join("again.json")),
        json_file(&out.join("frames/000001.json")),
    );
    assert_eq!(ja["objects"], jb["objects"]);
}

/// A broken glTF in the folder is refused at `--check`: exit 2, the field and the file named.
#[test]
fn a_broken_gltf_asset_is_refused_at_check() {
    let dir = workdir("assets-gltf-bad");
    mixed_folder(&dir);
    std::fs::write(dir.join("models/broken.gltf"), "{ \"asset\": ").unwrap();
    let cfg = config(&dir, with_assets(MIXED));
    let out = dir.join("out");
    refused(
        &dataset(&cfg, &out, &["--check"]),
        &["objects.assets.folder", "broken.gltf"],
    );
    assert!(!out.exists(), "the output folder was made");
}

/// One listing serves asset and texture folders (src/dataset/files.rs): only the named
/// extensions (any case; a folder named like a file is skipped), sorted by name; an empty or
/// missing folder is an error naming it, with a hint.
#[test]
fn folders_are_listed_sorted_by_extension() {
    use prism::dataset::files::list_files;
    use prism::error::InputError;
    let dir = workdir("list-files");
    std::fs::create_dir_all(dir.join("sub.obj")).unwrap();
    for n in ["b.OBJ", "a.ply", "c.txt", "d.gltf"] {
        std::fs::write(dir.join(n), "x").unwrap();
    }
    let err = |m: String| InputError::new(Path::new("d.ron"), m);
    let got = list_files(&dir, &["obj", "ply"], "OBJ or PLY", err).unwrap();
    let names: Vec<&str> = got.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["a.ply", "b.OBJ"]);
    let none = list_files(&dir, &["exr"], "EXR", err).unwrap_err();
    assert!(none.message.contains("holds no EXR file"), "{none}");
    assert!(none.hint.is_some());
    let gone = list_files(&dir.join("gone"), &["exr"], "EXR", err).unwrap_err();
    assert!(gone.message.contains("cannot list"), "{gone}");
}
