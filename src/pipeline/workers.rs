//! What every subcommand that renders shares on its command line, the worker threads
//! (`--threads`) and progress output (`--quiet`), and what they control: the thread pool and
//! `prism render`'s progress.

use crate::error::Error;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

/// `--threads` and `--quiet`, flattened into `prism render` and `prism dataset`.
#[derive(clap::Args, Clone, Copy, Debug)]
pub struct WorkerArgs {
    /// Worker threads. Default: one per core.
    #[arg(long)]
    pub threads: Option<usize>,
    /// No progress output (the summary line is still printed).
    #[arg(short, long)]
    pub quiet: bool,
}

/// The refusal of `--spp 0` (or `spp=0` from Python), one message for every front end.
pub fn zero_spp(file: &Path) -> crate::error::InputError {
    crate::error::InputError::new(file, "--spp must be at least 1").hint(
        "give a positive number of samples per pixel (--spp 16), or leave --spp out for the scene's sampler.spp",
    )
}

/// The most worker threads a render starts: far above any machine's cores (oversubscribing
/// helps no render), far below the thread counts that take the process minutes to start.
pub const MAX_THREADS: usize = 1024;

/// The worker threads of `--threads N` (default: one per core), for every subcommand that
/// renders; `--threads 0` is refused naming `file` (the scene or config the command was given).
pub fn worker_pool(threads: Option<usize>, file: &Path) -> Result<rayon::ThreadPool, Error> {
    if threads == Some(0) {
        return Err(
            crate::error::InputError::new(file, "--threads must be at least 1")
                .field("--threads")
                .hint("give a positive number, or leave --threads out for one thread per core")
                .into(),
        );
    }
    if let Some(t) = threads.filter(|&t| t > MAX_THREADS) {
        // Each pool starts its threads up front: 10^6 of them (rayon stops at 65,535) took
        // minutes before a pixel was rendered, and a Python caller could not interrupt it.
        return Err(crate::error::InputError::new(
            file,
            format!("--threads {t} is more than the {MAX_THREADS} worker threads prism starts"),
        )
        .field("--threads")
        .hint(format!(
            "give at most {MAX_THREADS} (this machine has {} cores), or leave --threads out for one thread per core",
            std::thread::available_parallelism().map_or(1, |n| n.get())
        ))
        .into());
    }
    let mut b = rayon::ThreadPoolBuilder::new();
    if let Some(t) = threads {
        b = b.num_threads(t);
    }
    b.build()
        .map_err(|e| Error::Other(format!("cannot start worker threads: {e}")))
}

/// Progress: a bar with ETA and throughput on a terminal, a plain line every 10% otherwise.
pub(crate) struct Reporter {
    bar: Option<ProgressBar>,
    total: u64,
    done: AtomicU64,
    start: Instant,
    quiet: bool,
}

impl Reporter {
    pub(crate) fn new(total: u64, quiet: bool) -> Self {
        let bar = (!quiet && std::io::stderr().is_terminal()).then(|| {
            let b = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr());
            b.set_style(
                ProgressStyle::with_template("{bar:40} {percent:>3}%  {msg}  ETA {eta}")
                    .expect("valid template"),
            );
            b
        });
        Self {
            bar,
            total,
            done: AtomicU64::new(0),
            start: Instant::now(),
            quiet,
        }
    }

    pub(crate) fn add(&self, n: u64) {
        let before = self.done.fetch_add(n, Ordering::Relaxed);
        let now = before + n;
        let msps = now as f64 / self.start.elapsed().as_secs_f64().max(1e-9) / 1e6;
        if let Some(b) = &self.bar {
            b.set_position(now);
            b.set_message(format!("{msps:.2} Msamples/s"));
        } else if !self.quiet {
            let step = |v: u64| v * 10 / self.total.max(1);
            if step(now) > step(before) {
                crate::error::note(format_args!(
                    "progress: {:3}%  {msps:.2} Msamples/s",
                    step(now) * 10
                ));
            }
        }
    }

    pub(crate) fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}
