//! `prism dataset` runs: frames reproducible alone, shards disjoint and complete, resume after
//! `kill -9`, and `--export-frame` reproduced by `prism render`. All on configs/datasets/smoke.ron
//! (8 frames of 64×48 at 8 spp).

mod dataset_util;
use dataset_util::*;

use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

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

/// A resume trusts a listed file whose size and modification time are the ones its manifest
/// line records (it reads none of them), and `--verify` reads every one: a frame's EXR changed
/// in one byte with its size and mtime kept passes the resume untouched and is caught by
/// `--verify`, which renders it again; a file whose mtime alone changed is read and kept.
#[test]
fn verify_reads_every_frame_and_a_resume_trusts_sizes_and_mtimes() {
    let full = frames(&full_run());
    let dir = workdir("verify");
    let cfg = config(&dir, |t| t);
    let out = dir.join("out");
    ok(&dataset(&cfg, &out, &["--frames", "0..3"]));
    let text = std::fs::read_to_string(out.join("manifest.jsonl")).unwrap();
    let line: serde_json::Value = serde_json::from_str(text.lines().next().unwrap()).unwrap();
    assert!(line["files"][0]["mtime_ns"].is_u64(), "{line}");
    let set_mtime = |p: &Path, t: std::time::SystemTime| {
        let f = std::fs::File::options().write(true).open(p).unwrap();
        f.set_modified(t).unwrap();
    };
    let exr = out.join("frames/000001.exr");
    let mtime = std::fs::metadata(&exr).unwrap().modified().unwrap();
    let mut bytes = std::fs::read(&exr).unwrap();
    let at = bytes.len() - 10;
    bytes[at] ^= 1;
    std::fs::write(&exr, &bytes).unwrap();
    set_mtime(&exr, mtime);
    let tally = |o: &std::process::Output| String::from_utf8_lossy(&o.stderr).into_owned();
    let o = dataset(&cfg, &out, &["--frames", "0..3"]);
    ok(&o);
    assert!(tally(&o).contains("0 rendered, 3 skipped"), "{}", tally(&o));
    assert!(
        std::fs::read(&exr).unwrap() == bytes,
        "the resume rewrote it"
    );
    let o = dataset(&cfg, &out, &["--frames", "0..3", "--verify"]);
    ok(&o);
    let err = tally(&o);
    assert!(
        err.contains("3 listed frame(s) read in full, 1 damaged") && err.contains("[1]"),
        "{err}"
    );
    assert!(err.contains("1 rendered, 2 skipped"), "{err}");
    for (name, b) in frames(&out) {
        assert!(full[&name] == b, "{name} differs from the full run");
    }
    // Same bytes, another mtime: read in full, found intact, not rendered again.
    let two = out.join("frames/000002.exr");
    set_mtime(&two, std::time::SystemTime::UNIX_EPOCH);
    let o = dataset(&cfg, &out, &["--frames", "0..3"]);
    ok(&o);
    assert!(tally(&o).contains("0 rendered, 3 skipped"), "{}", tally(&o));
}

/// A run that dies between frame 2's renames and its manifest line (the test hook aborts the
/// process there, as `kill -9` at that moment would): frames 0 and 1 are listed, frame 2's
/// files are in place but unlisted; the resume renders frame 2 again (and lists it once) and
/// ends byte-identical to the uninterrupted run.
#[test]
fn a_kill_between_rename_and_listing_is_redone_on_resume() {
    let full = frames(&full_run());
    let dir = workdir("rename-kill");
    let cfg = config(&dir, |t| t);
    let out = dir.join("out");
    let o = prism()
        .arg("dataset")
        .arg(&cfg)
        .arg("-o")
        .arg(&out)
        .args(["--quiet", "--threads", "1"])
        .env("PRISM_TEST_ABORT_BEFORE_LISTING", "2")
        .env_remove("SLURM_ARRAY_TASK_ID")
        .env_remove("SLURM_ARRAY_TASK_COUNT")
        .env_remove("JOB_COMPLETION_INDEX")
        .output()
        .unwrap();
    assert!(!o.status.success(), "the hook did not stop the run");
    assert_eq!(manifest(&out), vec![0, 1]);
    assert!(
        out.join("frames/000002.exr").is_file(),
        "frame 2 was not renamed into place"
    );
    let o = dataset(&cfg, &out, &[]);
    ok(&o);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("6 rendered, 2 skipped"), "{err}");
    let mut m = manifest(&out);
    m.sort_unstable();
    assert_eq!(m, (0..8).collect::<Vec<_>>());
    assert!(frames(&out) == full, "the resumed dataset differs");
}
