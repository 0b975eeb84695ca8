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
//! If the fuzzer itself dies (an in-process allocation failure aborts it), `--out`/workJ/case
//! names the case job J was running: rerun it alone with `--start K --cases 1 --jobs 1`.

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
    let mut start: u64 = 0;
    let mut out = PathBuf::from("out/fuzz");
    let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut bin = repo.join("target/release/prism");
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
            "--out" => out = PathBuf::from(v),
            "--bin" => bin = PathBuf::from(v),
            other => panic!("unknown argument {other}"),
        }
        i += 2;
    }
    let seeds = engine::load_seeds(&repo);
    println!(
        "fuzz: {} seed scenes, {} seed files; cases {start}..{}, seed {seed}, {jobs} jobs, binary every {every}",
        seeds.scenes.len(),
        seeds.files.len(),
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
                    let case = engine::make_case(seeds, seed, k);
                    let scene = engine::materialise(&case, &dir, repo);
                    // An in-process case that kills the fuzzer itself (an allocation failure
                    // aborts, the OOM killer) leaves no finding: this file names it instead.
                    let _ = std::fs::write(dir.join("case"), format!("{k}\n{}\n", case.what));
                    let mut verdicts =
                        vec![(engine::run_in_process(&scene, &dir, &LIMITS), String::new())];
                    if every > 0 && k % every == 0 {
                        let scene = engine::materialise(&case, &dir, repo);
                        verdicts.push(engine::run_binary(bin, &scene, &dir, &LIMITS));
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
