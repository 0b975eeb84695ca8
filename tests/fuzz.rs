//! The mutation fuzzer's fixed-seed sample and regression corpus (docs/fuzzing.md). The engine
//! is examples/fuzz/engine/ (seeds, mutations, the oracle); its long run is `cargo run --release --example fuzz`.
//!
//! - `oracle_*`: the verdicts can fail: stand-in programs that panic, hang, die by a signal or
//!   exit 1 are each flagged.
//! - `corpus_replays`: every case of tests/fuzz_corpus/ (fuzzer findings and hostile inputs of
//!   issue 14) runs through the binary: exit 0 or 2, and the exit code and messages its
//!   `expect` file names.
//! - `fixed_seed_sample`: 5000 cases in-process (`prism::cli::run`, panics caught) and every
//!   tenth of them also through the binary under `prlimit --as` with a time bound.
//! - `dataset_fixed_seed_sample`: every dataset seed as it is, then 40 dataset cases (a
//!   mutated config run by `prism dataset` into a folder in a hostile state) in-process, every
//!   fifth also through the binary.

#[path = "../examples/fuzz/engine/mod.rs"]
mod engine;
mod scratch;

use engine::{Verdict, LIMITS};
use scratch::{scratch, Scratch};
use std::path::PathBuf;
use std::time::Duration;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn bin() -> PathBuf {
    PathBuf::from(env!("CARGO_BIN_EXE_prism"))
}

/// The case's own folder: removed when the test passes, kept (and named) when it fails.
fn work(name: &str) -> Scratch {
    scratch("fuzz", name)
}

#[test]
fn oracle_flags_panics_hangs_signals_wrong_exit_codes_and_broken_promises() {
    let dir = work("oracle");
    let limits = engine::Limits {
        timeout: Duration::from_secs(1),
        cpu_seconds: 1,
        ..LIMITS
    };
    let scene = dir.join("scene.ron");
    std::fs::write(&scene, "()").unwrap();
    // EXRs a stand-in renders: all finite, and one NaN in the G channel of pixel (1, 0).
    let exr = |name: &str, bad: f32| {
        let p = dir.join(name);
        exr::prelude::write_rgb_file(&p, 2, 2, |x, y| {
            (1.0f32, if (x, y) == (1, 0) { bad } else { 0.5 }, 0.25)
        })
        .unwrap();
        p.display().to_string()
    };
    let (good, nan) = (exr("good.exr", 0.5), exr("nan.exr", f32::NAN));
    // $2 is the scene and $4 the EXR path of the oracle's arguments.
    let wrote = |src: &str| format!("cp {src} \"$4\"; echo {{}} > \"${{4%.exr}}.json\"; exit 0");
    let refused = "echo \"error: $2: bad\" >&2; exit 2";
    let (wrote_good, wrote_nan) = (wrote(&good), wrote(&nan));
    let left = format!("touch \"$4\"; {refused}");
    let cases = [
        (
            "echo \"thread 'main' panicked at x\" >&2; exit 101",
            "panic",
        ),
        ("echo \"thread 'main' panicked at x\" >&2; exit 2", "panic"),
        ("sleep 30", "hang"),
        // Busy: ended by the CPU-time bound (SIGXCPU); checked below that the wall bound,
        // raised for it, did not fire instead.
        ("while :; do :; done", "hang"),
        // Slow but working (three bursts of CPU with pauses shorter than the 1 s bound, more
        // than 1 s in all): not a hang, as a starved prism on a loaded machine is not.
        (
            "for k in 1 2 3 4; do i=0; while [ $i -lt 30000 ]; do i=$((i+1)); done; sleep 0.4; done; echo \"error: $2: bad\" >&2; exit 2",
            "ok",
        ),
        ("kill -SEGV $$", "signal"),
        ("exit 1", "wrong-exit"),
        (refused, "ok"),
        (&wrote_good, "ok"),
        // The promises of exit 0 and 2 (oracle::promise).
        ("echo 'error: bad input' >&2; exit 2", "broken"),
        (&left, "broken"),
        ("exit 0", "broken"),
        (&wrote_nan, "broken"),
    ];
    for (i, (body, want)) in cases.iter().enumerate() {
        let fake = dir.join(format!("fake{i}.sh"));
        std::fs::write(&fake, format!("#!/bin/sh\n{body}\n")).unwrap();
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&fake, std::fs::Permissions::from_mode(0o755)).unwrap();
        let busy = body.starts_with("while");
        let limits = engine::Limits {
            timeout: Duration::from_secs(if busy { 60 } else { 1 }),
            cpu_seconds: if body.starts_with("for") { 10 } else { 1 },
            ..limits
        };
        for n in engine::OUTPUTS {
            let _ = std::fs::remove_file(dir.join(n));
        }
        let start = std::time::Instant::now();
        let (v, _) = engine::run_binary(&fake, &scene, &dir, &limits);
        assert_eq!(v.label(), *want, "`{body}` gave {v:?}");
        // 1 s of CPU: well under the 60 s wall bound even on a loaded machine.
        assert!(
            !busy || start.elapsed() < Duration::from_secs(50),
            "the busy loop ran {:?}: the CPU-time bound did not end it",
            start.elapsed()
        );
    }
}

#[test]
fn corpus_replays() {
    let corpus = repo().join("tests/fuzz_corpus");
    let mut dirs: Vec<PathBuf> = std::fs::read_dir(&corpus)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_dir())
        .collect();
    dirs.sort();
    assert!(dirs.len() >= 10, "the corpus is in tests/fuzz_corpus/");
    let dir = work("corpus");
    for d in dirs {
        let case = engine::load_corpus_case(&d);
        let (v, err) = engine::run_case_binary(&bin(), &case, &dir, &repo(), &LIMITS);
        assert!(v.is_ok(), "{}: {v:?}\n{err}", d.display());
        if let Ok(expect) = std::fs::read_to_string(d.join("expect")) {
            let mut lines = expect.lines();
            let code: i32 = lines.next().unwrap().parse().unwrap();
            assert_eq!(v, Verdict::Ok(code), "{}: {err}", d.display());
            for want in lines.filter(|l| !l.is_empty()) {
                assert!(err.contains(want), "{}: no `{want}` in\n{err}", d.display());
            }
        }
    }
}

/// In-process cases; every `BINARY_EVERY`-th also runs the binary. Measured on this machine
/// (2 cores, shared): see docs/fuzzing.md.
const CASES: u64 = 5000;
const BINARY_EVERY: u64 = 10;
const SEED: u64 = 14;

#[test]
fn fixed_seed_sample() {
    let seeds = engine::load_seeds(&repo());
    assert!(seeds.scenes.len() >= 30 && seeds.files.len() >= 20);
    engine::install_panic_hook();
    let jobs = 2;
    let failures = std::sync::Mutex::new(Vec::new());
    let counts = std::sync::Mutex::new([0u64; 2]);
    std::thread::scope(|s| {
        for j in 0..jobs {
            let (seeds, failures, counts) = (&seeds, &failures, &counts);
            s.spawn(move || {
                let dir = work(&format!("sample{j}"));
                for k in (j..CASES).step_by(jobs as usize) {
                    let case = engine::make_case(seeds, SEED, k);
                    let scene = engine::materialise(&case, &dir, &repo());
                    let mut vs =
                        vec![(engine::run_in_process(&scene, &dir, &LIMITS), String::new())];
                    if k % BINARY_EVERY == 0 {
                        let scene = engine::materialise(&case, &dir, &repo());
                        vs.push(engine::run_binary(&bin(), &scene, &dir, &LIMITS));
                    }
                    for (v, err) in vs {
                        if let Verdict::Ok(c) = v {
                            counts.lock().unwrap()[(c == 2) as usize] += 1;
                        } else {
                            failures
                                .lock()
                                .unwrap()
                                .push(format!("case {k} ({}): {v:?}\n{err}", case.what));
                        }
                    }
                }
            });
        }
    });
    let f = failures.into_inner().unwrap();
    assert!(f.is_empty(), "{} failing cases:\n{}", f.len(), f.join("\n"));
    let [ok, refused] = counts.into_inner().unwrap();
    // Both outcomes occur in quantity: the sample exercises rendering, not only the parser.
    assert!(
        ok > 200 && refused > 200,
        "{ok} rendered, {refused} refused"
    );
    eprintln!("{ok} rendered, {refused} refused");
}

const DATASET_CASES: u64 = 40;
const DATASET_SEED: u64 = 27;

#[test]
fn dataset_fixed_seed_sample() {
    let seeds = engine::load_seeds(&repo());
    assert!(
        seeds.datasets.len() >= 10,
        "{} dataset seeds",
        seeds.datasets.len()
    );
    engine::install_panic_hook();
    // Each seed as it is, into a new folder, renders: the cases mutate working configs.
    let dir = work("dataset-seeds");
    for (k, s) in seeds.datasets.iter().enumerate() {
        let case = engine::Case {
            index: k as u64,
            what: s.name.clone(),
            scene: s.scene.clone(),
            file: None,
            dataset: Some(engine::DatasetCase {
                config: s.config.clone(),
                prime_config: s.config.clone(),
                prime_scene: s.scene.clone(),
                state: engine::OutState::Absent,
                flags: vec![],
            }),
        };
        let (v, err) = engine::run_case_binary(&bin(), &case, &dir, &repo(), &LIMITS);
        assert_eq!(v, Verdict::Ok(0), "seed {}: {err}", s.name);
    }
    let jobs = 2;
    let failures = std::sync::Mutex::new(Vec::new());
    let counts = std::sync::Mutex::new([0u64; 2]);
    std::thread::scope(|sc| {
        for j in 0..jobs {
            let (seeds, failures, counts) = (&seeds, &failures, &counts);
            sc.spawn(move || {
                let dir = work(&format!("dataset{j}"));
                for k in (j..DATASET_CASES).step_by(jobs as usize) {
                    let case = engine::make_dataset_case(seeds, DATASET_SEED, k);
                    let mut vs = vec![(
                        engine::run_case_in_process(&case, &dir, &repo(), &LIMITS),
                        String::new(),
                    )];
                    if k % 5 == 0 {
                        vs.push(engine::run_case_binary(
                            &bin(),
                            &case,
                            &dir,
                            &repo(),
                            &LIMITS,
                        ));
                    }
                    for (v, err) in vs {
                        if let Verdict::Ok(c) = v {
                            counts.lock().unwrap()[(c == 2) as usize] += 1;
                        } else {
                            failures
                                .lock()
                                .unwrap()
                                .push(format!("case {k} ({}): {v:?}\n{err}", case.what));
                        }
                    }
                }
            });
        }
    });
    drop(dir);
    let f = failures.into_inner().unwrap();
    assert!(f.is_empty(), "{} failing cases:\n{}", f.len(), f.join("\n"));
    let [ok, refused] = counts.into_inner().unwrap();
    // Both outcomes occur: the sample runs datasets, not only the config parser.
    assert!(ok > 5 && refused > 5, "{ok} ran, {refused} refused");
    eprintln!("{ok} ran, {refused} refused");
}

/// The CPU bound follows the samples a case asks for (examples/fuzz/engine/work.rs): run 13's
/// case 731603 (2 frames of 80×6 at 32,768 spp; 30.6 s of CPU alone, exit 0) was a "hang" at
/// the flat 20 s. Exact sample counts (the text's numbers multiplied), the bound 20 s + 5 µs
/// per sample, capped at 600 s; small cases keep 20 s; `max_spp:` is not `spp:`.
#[test]
fn the_cpu_bound_grows_with_the_samples_a_case_asks_for() {
    let scene = "(film: (width: 8, height: 6), sampler: (spp: 1), camera: (fov: 40))";
    let case = |config: Option<&str>| engine::Case {
        index: 0,
        what: String::new(),
        scene: scene.into(),
        file: None,
        dataset: config.map(|c| engine::DatasetCase {
            config: c.into(),
            prime_config: String::new(),
            prime_scene: String::new(),
            state: engine::OutState::Absent,
            flags: vec!["--force".into()],
        }),
    };
    let found = case(Some(
        "(scene: \"scene.ron\", frames: 2, seed: 3, outputs: (spp: 32768, resolution: (80, 6)))",
    ));
    assert_eq!(engine::samples_asked(&found), 2.0 * 32768.0 * 80.0 * 6.0);
    let bound = engine::limits_for(&found, &LIMITS).cpu_seconds;
    assert_eq!(bound, 20 + 157, "20 s + 31,457,280 × 5 µs");
    assert!(
        bound as f64 > 2.0 * 30.6,
        "{bound} s leaves no margin over 30.6 s"
    );

    // A render case runs at --spp 1: its film alone.
    let render = case(None);
    assert_eq!(engine::samples_asked(&render), 48.0);
    assert_eq!(engine::limits_for(&render, &LIMITS).cpu_seconds, 20);

    let huge = case(Some(
        "(outputs: (spp: 1e30, resolution: (1e9, 1e9)), max_spp: 9e40)",
    ));
    assert_eq!(engine::limits_for(&huge, &LIMITS).cpu_seconds, 600);
    let other = case(Some(
        "(outputs: (resolution: (4, 4)), max_spp: 9e9, integrator: (max_depth: 8))",
    ));
    assert_eq!(
        engine::samples_asked(&other),
        2.0 * 8.0 * 6.0,
        "spp 1 from the scene, film 8×6"
    );
}
