//! The mutation fuzzer's long run (docs/fuzzing.md):
//!
//! ```sh
//! cargo build --release && cargo run --release --example fuzz -- \
//!     --cases 1000000 --seed 1 --jobs 2 --binary-every 20 --out out/fuzz
//! ```
//!
//! Every case runs in-process through `prism::cli::run` (panics caught); every
//! `--binary-every`-th case also runs the `prism` binary under `prlimit --as` with a time bound
//! (hangs, memory, signals, exit codes as a user sees them). Failing cases are saved under
//! `--out`/findings as regression-corpus directories (tests/fuzz_corpus/ takes them as they are).
//! If the fuzzer itself dies (an in-process allocation failure aborts it), `--out`/workJ.case
//! names the case job J was running: rerun it alone with `--start K --cases 1 --jobs 1`.
//! Every `--dataset-every`-th case (default 5; 0: none) runs `prism dataset` on a mutated
//! dataset config into an output folder in a hostile state (engine/dataset.rs).

#[path = "engine/mod.rs"]
mod engine;

use engine::{Verdict, LIMITS};
use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::Instant;

fn main() {
    let mut cases: u64 = 10_000;
    let mut seed: u64 = 1;
    let mut jobs: u64 = 2;
    let mut every: u64 = 20;
    let mut dataset_every: u64 = 5;
    let mut start: u64 = 0;
    let mut out = PathBuf::from("out/fuzz");
    let mut repo = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut bin = None;
    let a: Vec<String> = std::env::args().skip(1).collect();
    let mut i = 0;
    while i < a.len() {
        let v = a.get(i + 1).cloned().unwrap_or_default();
        match a[i].as_str() {
            "--cases" => cases = v.parse().expect("--cases N"),
            "--seed" => seed = v.parse().expect("--seed N"),
            "--jobs" => jobs = v.parse().expect("--jobs N"),
            "--binary-every" => every = v.parse().expect("--binary-every N (0: never)"),
            "--start" => start = v.parse().expect("--start N"),
            "--dataset-every" => dataset_every = v.parse().expect("--dataset-every N (0: never)"),
            "--out" => out = PathBuf::from(v),
            "--bin" => bin = Some(PathBuf::from(v)),
            // A copy of the tree, so a long run reads seeds and assets that cannot change
            // under it while the checkout moves on.
            "--repo" => repo = PathBuf::from(v),
            other => panic!("unknown argument {other}"),
        }
        i += 2;
    }
    // Absolute, as the oracle expects every path of a case to be (a relative `out` made every
    // refusal a "broken" finding: its message names the file as given).
    let out = std::path::absolute(&out).expect("the current directory");
    let bin = bin.unwrap_or_else(|| repo.join("target/release/prism"));
    let seeds = engine::load_seeds(&repo);
    println!(
        "fuzz: {} seed scenes, {} seed files, {} dataset seeds; cases {start}..{}, seed {seed}, {jobs} jobs, binary every {every}, dataset every {dataset_every}",
        seeds.scenes.len(),
        seeds.files.len(),
        seeds.datasets.len(),
        start + cases
    );
    engine::install_panic_hook();
    let next = AtomicU64::new(start);
    let done = AtomicU64::new(0);
    let binary_runs = AtomicU64::new(0);
    let counts = Mutex::new(std::collections::BTreeMap::<String, u64>::new());
    let t0 = Instant::now();
    let findings = out.join("findings");
    std::thread::scope(|s| {
        for j in 0..jobs {
            let (seeds, next, done, counts, findings, bin, repo, out, binary_runs) = (
                &seeds,
                &next,
                &done,
                &counts,
                &findings,
                &bin,
                &repo,
                &out,
                &binary_runs,
            );
            s.spawn(move || {
                let dir = out.join(format!("work{j}"));
                loop {
                    let k = next.fetch_add(1, Ordering::Relaxed);
                    if k >= start + cases {
                        break;
                    }
                    // Every `dataset_every`-th case (k ≡ 3) runs `prism dataset`, the others
                    // `prism render` as before (their cases unchanged); the dataset cases
                    // take their turn through the binary among themselves.
                    let ds = dataset_every > 0 && k % dataset_every == 3 % dataset_every;
                    let (case, nth) = if ds {
                        (engine::make_dataset_case(seeds, seed, k), k / dataset_every)
                    } else {
                        (engine::make_case(seeds, seed, k), k)
                    };
                    // An in-process case that kills the fuzzer itself (an allocation failure
                    // aborts, the OOM killer) leaves no finding: this file names it instead.
                    let _ = std::fs::create_dir_all(&dir);
                    let _ = std::fs::write(
                        out.join(format!("work{j}.case")),
                        format!("{k}\n{}\n", case.what),
                    );
                    let mut verdicts = vec![(
                        engine::run_case_in_process(&case, &dir, repo, &LIMITS),
                        String::new(),
                    )];
                    if every > 0 && nth % every == 0 {
                        verdicts.push(engine::run_case_binary(bin, &case, &dir, repo, &LIMITS));
                        binary_runs.fetch_add(1, Ordering::Relaxed);
                    }
                    for (v, err) in verdicts {
                        let key = match &v {
                            Verdict::Ok(c) => format!("exit {c}"),
                            other => other.label().to_string(),
                        };
                        *counts.lock().unwrap().entry(key).or_default() += 1;
                        if !v.is_ok() {
                            let d = engine::save_finding(&case, &v, &err, findings);
                            println!("FINDING {} case {k}: {} -> {v:?}", v.label(), case.what);
                            println!("  saved {}", d.display());
                        }
                    }
                    let n = done.fetch_add(1, Ordering::Relaxed) + 1;
                    if n % 5000 == 0 {
                        let secs = t0.elapsed().as_secs_f64();
                        println!(
                            "{n} cases ({} binary runs) in {secs:.0} s ({:.1} cases/s): {:?}",
                            binary_runs.load(Ordering::Relaxed),
                            n as f64 / secs,
                            counts.lock().unwrap()
                        );
                    }
                }
            });
        }
    });
    let secs = t0.elapsed().as_secs_f64();
    let n = done.load(Ordering::Relaxed);
    println!(
        "done: {n} cases ({} binary runs) in {secs:.0} s ({:.1} cases/s): {:?}",
        binary_runs.load(Ordering::Relaxed),
        n as f64 / secs,
        counts.lock().unwrap()
    );
}
