//! Helpers shared by the tests/dataset_*.rs files: smoke.ron configs with absolute paths, running
//! `prism dataset`, and reading its frames, manifest and EXRs.
#![allow(dead_code)]

#[path = "../scratch/mod.rs"]
pub mod scratch;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub fn prism() -> Command {
    Command::new(env!("CARGO_BIN_EXE_prism"))
}

pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

pub fn workdir(name: &str) -> scratch::Scratch {
    scratch::scratch("dataset", name)
}

/// smoke.ron with its paths made absolute and `edit` applied, written into `dir`.
pub fn config(dir: &Path, edit: impl Fn(String) -> String) -> PathBuf {
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
pub fn tabletop() -> String {
    std::fs::read_to_string(root().join("configs/datasets/scenes/tabletop.ron"))
        .unwrap()
        .replace(
            "\"../../../scenes/textures/sky.exr\"",
            &format!("{:?}", root().join("scenes/textures/sky.exr")),
        )
}

/// `config(dir, edit)` with `dir`/base.ron (an edited `tabletop()`) as the frames' base scene.
pub fn config_on_base(dir: &Path, edit: impl Fn(String) -> String) -> PathBuf {
    let tabletop = format!("{:?}", root().join("configs/datasets/scenes/tabletop.ron"));
    let base = format!("{:?}", dir.join("base.ron"));
    config(dir, |t| edit(t).replace(&tabletop, &base))
}

pub fn dataset(cfg: &Path, out: &Path, extra: &[&str]) -> Output {
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

pub fn ok(o: &Output) {
    assert!(
        o.status.success(),
        "exit {:?}\n{}",
        o.status.code(),
        String::from_utf8_lossy(&o.stderr)
    );
}

/// Every file under OUT/frames (but temporary ones) with its bytes.
pub fn frames(out: &Path) -> BTreeMap<String, Vec<u8>> {
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
pub fn manifest(out: &Path) -> Vec<u64> {
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
pub fn full_run() -> PathBuf {
    // Shared by the binary's tests, so its folder lives as long as the process (a static is
    // never dropped): the one folder a passing run leaves behind.
    static FULL: std::sync::OnceLock<(scratch::Scratch, PathBuf)> = std::sync::OnceLock::new();
    FULL.get_or_init(|| {
        let dir = workdir("full");
        let cfg = config(&dir, |t| t);
        let out = dir.join("out");
        ok(&dataset(&cfg, &out, &[]));
        assert_eq!(manifest(&out), (0..8).collect::<Vec<_>>());
        (dir, out)
    })
    .1
    .clone()
}

/// The pixel data of an EXR, channel by channel.
pub fn exr_pixels(p: &Path) -> BTreeMap<String, Vec<f32>> {
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

/// Exit 2 and an `error:` naming the file, the field and the fix (the callers check that
/// nothing was rendered).
pub fn refused(o: &Output, needles: &[&str]) {
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

pub fn json_file(p: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

/// The custom attributes of an EXR's first header, as text.
pub fn exr_attributes(p: &Path) -> BTreeMap<String, String> {
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

/// tabletop() with class labels and the id layers: the ball and box are "toy", the marble
/// "marble", the bead "bead", the table "furniture" (sorted: bead 1, furniture 2, marble 3,
/// toy 4 while every shape shows).
pub fn labelled_tabletop() -> String {
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

/// smoke.ron with `seed` and `sensor: <variation>` (NIKON, CIE: those sensor files).
pub fn sensor_config(dir: &Path, seed: u64, variation: &str) -> PathBuf {
    let s = root().join("configs/sensors");
    let v = variation
        .replace("NIKON", &format!("{:?}", s.join("nikon_d810.ron")))
        .replace("CIE", &format!("{:?}", s.join("cie1931.ron")));
    config(dir, |t| {
        t.replace("seed: 1,", &format!("seed: {seed},\n    sensor: {v},"))
    })
}

/// Everything the first header of an EXR says, by key: its custom attributes (as
/// `exr_attributes`) and, under `(...)` keys, its channels, compression, blocks, line order,
/// size, shared attributes and the layer's standard attributes.
pub fn exr_header(p: &Path) -> BTreeMap<String, String> {
    let meta = exr::meta::MetaData::read_from_file(p, false).unwrap();
    let h = &meta.headers[0];
    let mut m = exr_attributes(p);
    let mut own = h.own_attributes.clone();
    own.other.clear();
    let rest = [
        ("(channels)", format!("{:?}", h.channels)),
        ("(compression)", format!("{:?}", h.compression)),
        ("(blocks)", format!("{:?}", h.blocks)),
        ("(line_order)", format!("{:?}", h.line_order)),
        ("(layer_size)", format!("{:?}", h.layer_size)),
        ("(shared)", format!("{:?}", h.shared_attributes)),
        ("(layer)", format!("{:?}", own)),
        ("(headers)", meta.headers.len().to_string()),
    ];
    for (k, v) in rest {
        m.insert(k.to_string(), v);
    }
    m
}

/// A small deterministic generator of kill moments in [0, 1).
pub fn lcg(state: &mut u64) -> f64 {
    *state = state
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*state >> 11) as f64 / (1u64 << 53) as f64
}

/// Runs `cfg` into `out`, dying first between frame `abort_at`'s renames and its manifest line
/// (the test hook aborts there, as `kill -9` at that moment would), then `kills` times by SIGKILL
/// at seeded moments in the first `window` seconds of a run; after each death every listed
/// frame is listed once and is byte-identical to `full`'s; then resumes to the end and asserts
/// the folder's frames equal `full` byte for byte.
pub fn kill_and_resume(
    cfg: &Path,
    out: &Path,
    full: &BTreeMap<String, Vec<u8>>,
    abort_at: u32,
    kills: u32,
    window: f64,
    seed: u64,
) {
    let o = prism()
        .arg("dataset")
        .arg(cfg)
        .arg("-o")
        .arg(out)
        .arg("--quiet")
        .env("PRISM_TEST_ABORT_BEFORE_LISTING", abort_at.to_string())
        .env_remove("SLURM_ARRAY_TASK_ID")
        .env_remove("SLURM_ARRAY_TASK_COUNT")
        .env_remove("JOB_COMPLETION_INDEX")
        .output()
        .unwrap();
    assert!(!o.status.success(), "the hook did not stop the run");
    let stem = format!("{abort_at:06}");
    assert!(
        !manifest(out).contains(&(abort_at as u64))
            && out.join(format!("frames/{stem}.exr")).is_file(),
        "frame {abort_at}: renamed and unlisted"
    );
    let mut rng = seed;
    let mut listed = manifest(out);
    for k in 0..kills {
        let mut child = prism()
            .arg("dataset")
            .arg(cfg)
            .arg("-o")
            .arg(out)
            .arg("--quiet")
            .env_remove("SLURM_ARRAY_TASK_ID")
            .env_remove("SLURM_ARRAY_TASK_COUNT")
            .env_remove("JOB_COMPLETION_INDEX")
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(std::time::Duration::from_secs_f64(lcg(&mut rng) * window));
        let _ = child.kill(); // SIGKILL on Unix
        let _ = child.wait();
        let now = manifest(out);
        let mut once = now.clone();
        once.sort_unstable();
        once.dedup();
        assert_eq!(
            once.len(),
            now.len(),
            "kill {k}: a frame listed twice: {now:?}"
        );
        assert!(
            listed.iter().all(|i| now.contains(i)),
            "kill {k}: lost a frame: {listed:?} -> {now:?}"
        );
        let files = frames(out);
        for i in &now {
            for ext in ["exr", "json", "png"] {
                let name = format!("{i:06}.{ext}");
                assert!(
                    files.get(&name) == full.get(&name),
                    "kill {k}: listed {name} is not the uninterrupted run's"
                );
            }
        }
        listed = now;
    }
    ok(&dataset(cfg, out, &[]));
    let got = frames(out);
    assert_eq!(
        got.keys().collect::<Vec<_>>(),
        full.keys().collect::<Vec<_>>()
    );
    for (name, bytes) in &got {
        assert!(full[name] == *bytes, "{name}: the resumed run differs");
    }
    assert!(
        std::fs::read(out.join("contact_sheet.png")).ok().is_some(),
        "no contact sheet after the resume"
    );
}
