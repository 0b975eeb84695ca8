//! `prism dataset CONFIG -o OUT`: the command line of the dataset runner.

use super::run::{self, Options, Summary};
use crate::error::{Error, InputError};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

#[derive(clap::Args, Debug)]
pub struct DatasetArgs {
    /// The dataset config (RON; configs/README.md).
    pub config: PathBuf,
    /// Output folder: frames/, dataset.json, manifest.jsonl. A rerun resumes it.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Only these frames: `17`, or a half-open range `10..20`.
    #[arg(long)]
    pub frames: Option<String>,
    /// Write frame N's resolved scene to OUT/frames/NNNNNN.ron (for `prism render`) instead of
    /// rendering.
    #[arg(long, value_name = "N")]
    pub export_frame: Option<u32>,
    /// This shard's index (frames i with i mod num-shards == shard). Default: from
    /// SLURM_ARRAY_TASK_ID (minus SLURM_ARRAY_TASK_MIN) or JOB_COMPLETION_INDEX, else 0.
    #[arg(long)]
    pub shard: Option<u32>,
    /// Number of shards. Default: SLURM_ARRAY_TASK_COUNT, else 1.
    #[arg(long)]
    pub num_shards: Option<u32>,
    /// Check the config and claim the output folder, print the frames done and left as JSON
    /// on stdout, render nothing (for drivers such as prism_tools' Ray runner).
    #[arg(long)]
    pub check: bool,
    /// Start over in an output folder that holds another dataset (or other files).
    #[arg(long)]
    pub force: bool,
    /// Check every listed frame's files by their SHA-256 (a resume otherwise trusts a file
    /// whose size and modification time are as listed); damaged frames are rendered again
    /// (with --check: only reported).
    #[arg(long)]
    pub verify: bool,
    #[command(flatten)]
    pub workers: crate::pipeline::WorkerArgs,
}

/// Runs `prism dataset` in this process; `stop` ends it before the next frame. Signals are
/// the caller's: the CLI installs its SIGINT/SIGTERM handler, a library user (the Python
/// module) keeps its own, so its forked workers can still be terminated.
pub fn main(args: &DatasetArgs, stop: Option<&AtomicBool>) -> Result<Summary, Error> {
    let frames = args
        .frames
        .as_deref()
        .map(|s| parse_frames(s, &args.config))
        .transpose()?;
    let shard = shard(args, &|k| std::env::var(k).ok())?;
    let pool = crate::pipeline::worker_pool(args.workers.threads, &args.config)?;
    let opts = Options {
        frames,
        shard,
        force: args.force,
        quiet: args.workers.quiet,
        export_frame: args.export_frame,
        check: args.check,
        verify: args.verify,
        stop,
    };
    pool.install(|| run::run(&args.config, &args.output, &opts))
}

fn arg_error(config: &Path, field: &str, message: impl Into<String>) -> Error {
    // A caller's own hint (`with_hint`) replaces this one.
    InputError::new(config, message)
        .field(field)
        .hint(format!("`prism dataset --help` describes {field}"))
        .into()
}

/// `17` → (17, 18); `10..20` → (10, 20).
pub fn parse_frames(s: &str, config: &Path) -> Result<(u32, u32), Error> {
    let bad = || {
        arg_error(
            config,
            "--frames",
            format!("`{s}` is not a frame or a range"),
        )
        .with_hint("write one frame (17) or a half-open range (10..20)")
    };
    match s.split_once("..") {
        Some((a, b)) => {
            let lo = a.trim().parse::<u32>().map_err(|_| bad())?;
            let hi = b.trim().parse::<u32>().map_err(|_| bad())?;
            Ok((lo, hi))
        }
        None => {
            let i = s.trim().parse::<u32>().map_err(|_| bad())?;
            Ok((i, i + 1))
        }
    }
}

/// (shard, shards) from the flags, else the scheduler's environment.
pub fn shard(
    args: &DatasetArgs,
    env: &dyn Fn(&str) -> Option<String>,
) -> Result<(u32, u32), Error> {
    let num = |k: &str| -> Result<Option<u32>, Error> {
        env(k)
            .map(|v| {
                v.trim().parse::<u32>().map_err(|_| {
                    arg_error(
                        &args.config,
                        k,
                        format!("the environment variable {k}={v} is not a whole number"),
                    )
                })
            })
            .transpose()
    };
    let shard = match args.shard {
        Some(s) => s,
        None => match (num("SLURM_ARRAY_TASK_ID")?, num("JOB_COMPLETION_INDEX")?) {
            (Some(id), _) => id - num("SLURM_ARRAY_TASK_MIN")?.unwrap_or(0).min(id),
            (None, Some(k)) => k,
            (None, None) => 0,
        },
    };
    let shards = match args.num_shards {
        Some(n) => n,
        None => num("SLURM_ARRAY_TASK_COUNT")?.unwrap_or(1),
    };
    if shards == 0 || shard >= shards {
        return Err(arg_error(
            &args.config,
            "--shard",
            format!("shard {shard} of {shards}: the shard must be below the number of shards"),
        )
        .with_hint(
            "with Kubernetes' JOB_COMPLETION_INDEX pass --num-shards (the Job's completions)",
        ));
    }
    Ok((shard, shards))
}

trait WithHint {
    fn with_hint(self, hint: &str) -> Self;
}

impl WithHint for Error {
    fn with_hint(self, hint: &str) -> Self {
        match self {
            Error::Input(e) => Error::Input(Box::new((*e).hint(hint))),
            other => other,
        }
    }
}
