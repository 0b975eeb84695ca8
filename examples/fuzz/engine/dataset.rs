//! Dataset cases (issue 27 item 5): a dataset config (configs/datasets/*.ron and small variants,
//! one kind of variation each) over a base scene, run by `prism dataset` into an output folder
//! in a state a user's folder can be in: absent, empty, foreign, a file, or a finished run's
//! folder then damaged (torn or forged manifest lines, parts of the wrong file type, foreign
//! files, stale temporaries, a damaged frame). The oracle is the render cases' promise, for a
//! folder: exit 2 changes nothing in it and names a file; exit 0 lists every selected frame
//! under its own files, each EXR finite in every channel.

use super::damage::{damage, read_regular, Damage};
use super::seeds::{absolute_strings, prepare, set_number};
use super::{Case, DatasetSeed};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The small base scene of the variants: named shapes, an area lamp, an environment map, every
/// material kind a variation edits.
const SMALL: &str = r#"(film: (width: 8, height: 6), sampler: (spp: 1),
 camera: (fov: 40, to_world: [LookAt(origin: (0, 1.2, 4), target: (0, 0.8, 0), up: (0, 1, 0))]),
 materials: {"paint": Diffuse(), "glass": Dielectric(int_ior: 1.5), "rough": RoughConductor(alpha: 0.2),
   "plastic": RoughPlastic(alpha: 0.1, diffuse_reflectance: Rgb(0.2, 0.4, 0.8)), "wood": Diffuse()},
 shapes: [(name: "table", shape: Cube, material: "wood", to_world: [Scale((1.2, 0.05, 0.8)), Translate((0, 0.7, 0))]),
   (name: "ball", shape: Sphere(radius: 0.15), material: "paint", to_world: [Translate((-0.3, 0.9, 0))]),
   (name: "box", shape: Cube, material: "plastic", to_world: [Scale((0.1, 0.1, 0.1)), Translate((0.3, 0.85, 0))]),
   (name: "lamp", shape: Rectangle, to_world: [Scale((0.4, 0.4, 1)), Rotate(axis: (1, 0, 0), angle: 90), Translate((0, 2.6, 0.3))],
    emitter: (radiance: Scaled(12, Named("D65"))))],
 emitters: [Envmap(filename: "@REPO@/scenes/textures/sky.exr", scale: 0.5)])"#;

/// One variation kind each, over `SMALL`.
const VARIANTS: &[(&str, &str)] = &[
    ("poses", "camera: (look_at: Poses([(origin: (0, 1, 4), target: (0, 0.8, 0)), (origin: (3, 1.5, 3), target: (0, 0.8, 0))]), up: (0, 1, 0), fov: (30, 50)),"),
    ("shell", "camera: (look_at: Shell(target: (0, 0.8, 0), radius: (2, 4), elevation: (5, 60), azimuth: (0, 360)), roll: 10, keep_in_view: [\"ball\"], max_attempts: 20),"),
    ("lights", "lights: [(target: \"lamp\", intensity: (1, 10), illuminants: [\"D65\", \"A\", \"F2\"]), (target: \"emitters[0]\", intensity: (0.1, 2))],"),
    ("temperature", "lights: [(target: \"lamp\", intensity: (2, 8), temperature: (2000, 9000))],"),
    ("envmap", "envmap: (target: \"emitters[0]\", files: [\"@REPO@/scenes/textures/sky.exr\"], rotate: false),"),
    ("sensor", "outputs: (spp: 1, resolution: (8, 6), aovs: [\"depth\", \"instance\", \"label\"], sensors: [(name: \"nikon\", sensor: File(\"@REPO@/configs/sensors/nikon_d810.ron\"))]), sensor: (files: [\"@REPO@/configs/sensors/cie1931.ron\", \"@REPO@/configs/sensors/raw_rggb.ron\"], exposure: (-2, 2)),"),
    ("materials", "materials: [(target: \"glass\", ior: (1.3, 1.9)), (target: \"rough\", roughness: (0.01, 0.5)), (target: \"paint\", reflectance: Library(\"cie1995_tcs\")), (target: \"plastic\", reflectance: Library(\"colorchecker\"), roughness: (0.05, 0.3))],"),
    ("objects", "splits: {\"train\": (0, 1), \"val\": (1, 2)}, swaps: [(shape: \"ball\", materials: [\"paint\", \"glass\", \"rough\"])], objects: (subsets: [(shapes: [\"ball\", \"box\"], shown: (0, 2))], place: (support: \"table\", shapes: [\"ball\", \"box\"], yaw: (0, 360), scale: (0.5, 1.5), gap: 0.01, max_attempts: 50)),"),
];

/// The dataset seeds: configs/datasets/*.ron over their base scene (paths made `@REPO@/...`,
/// frames of 8×6 at 1 spp) and the variants over `SMALL`.
pub fn dataset_seeds(repo: &Path) -> Vec<DatasetSeed> {
    let dir = repo.join("configs/datasets");
    let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "ron"))
        .collect();
    v.sort();
    let mut out = Vec::new();
    for p in v {
        let text = std::fs::read_to_string(&p).unwrap();
        let Some(scene_rel) = text
            .split("scene: \"")
            .nth(1)
            .and_then(|r| r.split('"').next())
        else {
            continue;
        };
        let scene_path = dir.join(scene_rel);
        let scene = prepare(
            &std::fs::read_to_string(&scene_path).unwrap(),
            scene_path.parent().unwrap(),
            repo,
        );
        let mut config = text.replacen(&format!("\"{scene_rel}\""), "\"scene.ron\"", 1);
        config = absolute_strings(&config, Path::new("configs/datasets"));
        config = small(&config);
        out.push(DatasetSeed {
            name: p.strip_prefix(repo).unwrap().display().to_string(),
            config,
            scene,
        });
    }
    for (name, body) in VARIANTS {
        let outputs = if body.contains("outputs:") {
            ""
        } else {
            "outputs: (spp: 1, resolution: (8, 6)), "
        };
        out.push(DatasetSeed {
            name: format!("dataset:{name}"),
            config: format!("(scene: \"scene.ron\", frames: 2, seed: 3, {outputs}{body})"),
            scene: SMALL.to_string(),
        });
    }
    out
}

/// Frames of 8×6 at 1 spp: a case renders in milliseconds. The frame count stays (splits
/// refer to it); a case selects frames 0 and 1 (`--frames 0..2`).
fn small(t: &str) -> String {
    let mut t = set_number(t, "spp", "1");
    if let Some(i) = t.find("resolution: (") {
        if let Some(j) = t[i..].find(')') {
            t.replace_range(i..i + j + 1, "resolution: (8, 6)");
        }
    }
    t
}

/// The state of the output folder before the case's run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum OutState {
    Absent,
    Empty,
    /// A user's folder: a file of theirs in it.
    Foreign,
    /// OUT is a regular file, or a dangling symbolic link.
    IsFile,
    DanglingLink,
    /// The unmutated config's run (frames 0 and 1), then damaged.
    Primed(Vec<Damage>),
}

/// A dataset case: the config (its base scene is the case's `scene`), the unmutated pair the
/// folder is primed with, the folder's state and the command's flags.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct DatasetCase {
    pub config: String,
    pub prime_config: String,
    pub prime_scene: String,
    pub state: OutState,
    pub flags: Vec<String>,
}

/// Flags a case runs with (beside `--frames 0..2 --threads 1 --quiet`).
pub const FLAGS: &[&[&str]] = &[
    &[],
    &[],
    &[],
    &["--force"],
    &["--check"],
    &["--verify"],
    &["--export-frame", "1"],
    &["--shard", "1", "--num-shards", "2"],
];

/// The command line of a dataset case (the config and OUT absolute, as in every case).
pub fn args(dir: &Path, flags: &[String]) -> Vec<String> {
    let mut a: Vec<String> = vec![
        "dataset".into(),
        dir.join("dataset.ron").display().to_string(),
        "-o".into(),
        dir.join("out").display().to_string(),
        "--frames".into(),
        "0..2".into(),
        "--threads".into(),
        "1".into(),
        "--quiet".into(),
    ];
    a.extend(flags.iter().cloned());
    a
}

/// Writes the case into `dir` (emptied first): primes the folder with the unmutated pair
/// (in-process), damages it, then writes the mutated config and scene. `fifo`: FIFOs may be
/// made (binary runs only).
pub fn materialise(case: &Case, d: &DatasetCase, dir: &Path, repo: &Path, fifo: bool) {
    let _ = std::fs::remove_dir_all(dir);
    std::fs::create_dir_all(dir).unwrap();
    let fill = |t: &str| {
        t.replace("@REPO@", &repo.display().to_string())
            .replace("@CASE@", &dir.display().to_string())
    };
    let out = dir.join("out");
    let write_pair = |config: &str, scene: &str| {
        std::fs::write(dir.join("dataset.ron"), fill(config)).unwrap();
        std::fs::write(dir.join("scene.ron"), fill(scene)).unwrap();
    };
    match &d.state {
        OutState::Absent => {}
        OutState::Empty => std::fs::create_dir(&out).unwrap(),
        OutState::Foreign => {
            std::fs::create_dir(&out).unwrap();
            std::fs::write(out.join("thesis.tex"), "mine").unwrap();
        }
        OutState::IsFile => std::fs::write(&out, "mine").unwrap(),
        OutState::DanglingLink => std::os::unix::fs::symlink(dir.join("nowhere/x"), &out).unwrap(),
        OutState::Primed(damages) => {
            write_pair(&d.prime_config, &d.prime_scene);
            let key = (fill(&d.prime_config), fill(&d.prime_scene));
            let code = primed(&key, &out, || {
                let a = super::oracle::with_program(args(dir, &[]));
                std::panic::catch_unwind(|| prism::cli::run(a)).unwrap_or(101)
            });
            if code == 0 {
                for dmg in damages {
                    damage(&out, dmg, fifo);
                }
            }
        }
    }
    write_pair(&d.config, &case.scene);
}

/// A primed folder as the unmutated pair's run left it: its exit code and, when every path
/// under OUT is a directory or a regular file, those paths (relative) with the files' bytes.
type Primed = (i32, Option<Vec<(PathBuf, Option<Vec<u8>>)>>);

thread_local! {
    /// Primed folders per (config, scene) text, per job thread. Those texts name the job's own
    /// directory, so a folder is only ever restored where it was made. The unmutated pair's
    /// run is deterministic, so a restored folder holds the bytes a fresh run would write
    /// (only mtimes differ, and resumes hash files anew in each process); restoring skips
    /// about half of a dataset case's rendering.
    static PRIMED: std::cell::RefCell<std::collections::HashMap<(String, String), Primed>> =
        Default::default();
}

/// Fills OUT as `run` would (running it the first time per key), returning its exit code.
fn primed(key: &(String, String), out: &Path, run: impl FnOnce() -> i32) -> i32 {
    let cached = PRIMED.with(|c| c.borrow().get(key).cloned());
    if let Some((code, Some(tree))) = cached {
        for (rel, bytes) in &tree {
            let p = out.join(rel);
            match bytes {
                None => std::fs::create_dir_all(&p).unwrap(),
                Some(b) => std::fs::write(&p, b).unwrap(),
            }
        }
        return code;
    }
    let code = run();
    let tree = record(out);
    PRIMED.with(|c| c.borrow_mut().insert(key.clone(), (code, tree)));
    code
}

/// OUT's directories and regular files, parents first; None if anything else is there.
fn record(out: &Path) -> Option<Vec<(PathBuf, Option<Vec<u8>>)>> {
    let mut v = Vec::new();
    let mut stack = vec![out.to_path_buf()];
    while let Some(p) = stack.pop() {
        let m = std::fs::symlink_metadata(&p).ok()?;
        let rel = p.strip_prefix(out).ok()?.to_path_buf();
        if m.is_dir() {
            v.push((rel, None));
            for e in std::fs::read_dir(&p).ok()? {
                stack.push(e.ok()?.path());
            }
        } else if m.is_file() {
            v.push((rel, Some(std::fs::read(&p).ok()?)));
        } else {
            return None;
        }
    }
    Some(v)
}

/// What OUT holds, for "exit 2 changed nothing": each path under it (links not followed) with
/// its kind, size and modification time.
pub fn snapshot(out: &Path) -> Vec<String> {
    let mut v = Vec::new();
    let mut stack = vec![out.to_path_buf()];
    while let Some(p) = stack.pop() {
        let Ok(m) = std::fs::symlink_metadata(&p) else {
            continue;
        };
        let t = m.modified().ok();
        v.push(format!(
            "{} {:?} {} {t:?}",
            p.display(),
            m.file_type(),
            m.len()
        ));
        if m.is_dir() {
            for e in std::fs::read_dir(&p).into_iter().flatten().flatten() {
                stack.push(e.path());
            }
        }
    }
    v.sort();
    v
}

/// What exit code `code` promises for a dataset case: exit 2 left OUT as it was (`before`) and
/// names a file; exit 0 claimed OUT and, for a run that renders, lists every selected frame
/// under its own files, each EXR finite in every channel.
pub fn promise(
    code: i32,
    dir: &Path,
    flags: &[String],
    stderr: Option<&str>,
    before: &[String],
) -> Option<String> {
    let out = dir.join("out");
    if code == 2 {
        let after = snapshot(&out);
        if after != before {
            let changed: Vec<&String> = after.iter().filter(|l| !before.contains(l)).collect();
            let gone: Vec<&String> = before.iter().filter(|l| !after.contains(l)).collect();
            return Some(format!(
                "exit 2 changed the output folder: new or changed {changed:?}, gone {gone:?}"
            ));
        }
        return super::oracle::names_a_file(stderr);
    }
    if !out.join("dataset.json").is_file() {
        return Some("exit 0 without OUT/dataset.json".into());
    }
    let has = |f: &str| flags.iter().any(|x| x == f);
    if has("--check") {
        return None;
    }
    if has("--export-frame") {
        let ron = out.join("frames/000001.ron");
        return (!ron.is_file()).then(|| "exit 0 without frames/000001.ron".to_string());
    }
    let selected: Vec<u32> = if has("--shard") { vec![1] } else { vec![0, 1] };
    let manifest = read_regular(&out.join("manifest.jsonl")).unwrap_or_default();
    let manifest = String::from_utf8_lossy(&manifest);
    for f in selected {
        let exr = format!("frames/{f:06}.exr");
        let own = manifest.lines().any(|l| {
            l.starts_with(&format!("{{\"frame\":{f},"))
                && l.contains(&format!("\"path\":\"{exr}\""))
        });
        if !own {
            return Some(format!(
                "exit 0 but the manifest lists no line of frame {f} with {exr}"
            ));
        }
        // Checked before it is read: a FIFO left by a damage would block the read.
        if !std::fs::symlink_metadata(out.join(&exr)).is_ok_and(|m| m.file_type().is_file()) {
            return Some(format!("exit 0 but {exr} is not a regular file"));
        }
        if let Some(bad) = super::oracle::non_finite(&out.join(&exr)) {
            return Some(format!("{exr}: {bad}"));
        }
    }
    None
}
