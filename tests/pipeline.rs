//! One pipeline for `prism render` and `prism dataset` (issue 25): a dataset frame's EXR
//! header has exactly the keys `prism render` writes for the frame's exported scene. On
//! configs/datasets/smoke.ron, one frame of 64×48 at 8 spp.
//!
//! `PRISM_TEST_BIN` runs the test against another binary (e.g. one built before the pipeline,
//! whose frames had 4 `prism:` keys against the render's 11: the test fails there).

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;

fn prism() -> Command {
    let bin = std::env::var_os("PRISM_TEST_BIN")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_BIN_EXE_prism")));
    Command::new(bin)
}

fn run(cmd: &mut Command) {
    let o = cmd.output().unwrap();
    assert!(
        o.status.success(),
        "exit {:?}\n{}",
        o.status.code(),
        String::from_utf8_lossy(&o.stderr)
    );
}

/// The attribute names of an EXR's header (its own and its shared ones).
fn header_keys(p: &Path) -> BTreeSet<String> {
    let meta = exr::meta::MetaData::read_from_file(p, false).unwrap();
    let h = &meta.headers[0];
    h.own_attributes
        .other
        .keys()
        .chain(h.shared_attributes.other.keys())
        .map(|k| k.to_string())
        .collect()
}

#[test]
fn a_dataset_frame_has_the_header_keys_of_prism_render() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let dir = std::env::temp_dir().join(format!("prism-pipeline-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    // smoke.ron with its paths made absolute (as tests/dataset_util does).
    let ds = root.join("configs/datasets");
    let text = std::fs::read_to_string(ds.join("smoke.ron"))
        .unwrap()
        .replace(
            "\"scenes/tabletop.ron\"",
            &format!("{:?}", ds.join("scenes/tabletop.ron")),
        )
        .replace(
            "\"../../scenes/textures/sky.exr\"",
            &format!("{:?}", root.join("scenes/textures/sky.exr")),
        );
    let cfg = dir.join("dataset.ron");
    std::fs::write(&cfg, text).unwrap();
    let frames = dir.join("frames");
    let exported = dir.join("exported");
    for (out, extra) in [
        (&frames, ["--frames", "3"]),
        (&exported, ["--export-frame", "3"]),
    ] {
        run(prism()
            .arg("dataset")
            .arg(&cfg)
            .arg("-o")
            .arg(out)
            .arg("--quiet")
            .args(extra)
            .env_remove("SLURM_ARRAY_TASK_ID")
            .env_remove("SLURM_ARRAY_TASK_COUNT")
            .env_remove("JOB_COMPLETION_INDEX"));
    }
    let rendered = dir.join("render.exr");
    run(prism()
        .arg("render")
        .arg(exported.join("frames/000003.ron"))
        .arg("-o")
        .arg(&rendered)
        .arg("--quiet"));
    let frame = header_keys(&frames.join("frames/000003.exr"));
    let render = header_keys(&rendered);
    // Exact equality, no key left out on either side: both come from pipeline::header.
    assert_eq!(frame, render, "dataset frame vs prism render");
    assert!(
        render.iter().filter(|k| k.starts_with("prism:")).count() >= 11,
        "{render:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
