//! The loop: load the dataset once, check every selected frame's plan, claim the output folder,
//! then render each frame not yet done and list it in the manifest.

use super::base::Base;
use super::frame;
use super::manifest::Out;
use super::plan;
use crate::error::{Error, InputError};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use serde_json::json;
use sha2::{Digest, Sha256};
use std::io::IsTerminal;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// What to run.
pub struct Options<'a> {
    /// Frames `lo..hi` (half-open); None: all.
    pub frames: Option<(u32, u32)>,
    /// (this shard, number of shards): frame i belongs to shard i mod n.
    pub shard: (u32, u32),
    pub force: bool,
    pub quiet: bool,
    /// Write frame i's resolved scene instead of rendering.
    pub export_frame: Option<u32>,
    /// Check and claim the folder, print what is done and what is left (JSON), render nothing.
    pub check: bool,
    /// Read every listed frame's files in full (not trusting sizes and mtimes); damaged frames
    /// are dropped from the manifest and rendered again.
    pub verify: bool,
    /// Set (by the Python module's Ctrl-C) to stop before the next frame; the frames done so
    /// far are listed, so a rerun resumes.
    pub stop: Option<&'a AtomicBool>,
}

/// The run's tally.
#[derive(Debug, Default)]
pub struct Summary {
    pub rendered: u32,
    pub skipped: u32,
    pub failed: u32,
    pub seconds: f64,
    /// The run ended early at `Options::stop`.
    pub stopped: bool,
}

/// The identity of a dataset in `dataset.json`: its config, its base scene, the SHA-256 of
/// every other file it reads (`inputs`, by path relative to the config) and prism's version,
/// with a hash of the first three.
pub fn identity(base: &Base) -> Result<serde_json::Value, Error> {
    let config = serde_json::to_value(&base.config).expect("configs serialise");
    let scene = serde_json::to_value(&base.scene).expect("configs serialise");
    let inputs = super::assets::hashes(base)?;
    let canon = serde_json::to_string(&json!({"config": config, "scene": scene, "inputs": inputs}))
        .expect("JSON values serialise");
    // The id tables every frame's `label.ID`, `instance.ID` and `material.ID` use (they follow
    // from the config and scene, so the hash covers them).
    let o = &base.objects;
    let table = |names: &[String]| {
        let rows = names.iter().enumerate();
        rows.map(|(i, n)| json!({"id": i + 1, "name": n}))
            .collect::<Vec<_>>()
    };
    let instances: Vec<_> = o
        .list
        .iter()
        .map(|x| json!({"id": x.instance_id, "name": x.name, "label": x.label, "label_id": x.label_id}))
        .collect();
    Ok(json!({
        "prism_version": env!("CARGO_PKG_VERSION"),
        "hash": super::manifest::hex(&Sha256::digest(canon.as_bytes())),
        "config": config,
        "scene": scene,
        "inputs": inputs,
        "classes": table(&o.labels),
        "instances": instances,
        "materials": table(&o.materials),
        "splits": base.config.splits,
    }))
}

/// The frames this process renders: the range, then this shard's share of it.
pub fn selection(base: &Base, opts: &Options<'_>) -> Result<Vec<u32>, InputError> {
    let n = base.config.frames;
    let (lo, hi) = opts.frames.unwrap_or((0, n));
    if lo >= hi || hi > n {
        return Err(InputError::new(
            &base.file,
            format!("--frames {lo}..{hi}: the dataset has frames 0..{n}"),
        )
        .field("--frames")
        .hint(format!(
            "give a frame below {n}, or a range lo..hi with lo < hi ≤ {n}"
        )));
    }
    let (shard, shards) = opts.shard;
    Ok((lo..hi).filter(|i| i % shards == shard).collect())
}

/// Runs the dataset at `file` into `out`.
pub fn run(file: &Path, out: &Path, opts: &Options<'_>) -> Result<Summary, Error> {
    let t0 = Instant::now();
    let mut base = Base::load(file)?;
    // Once per run, also at --check: what `prism render` of its frames would warn about.
    for w in &base.warnings {
        eprintln!("warning: {w}");
    }
    let frames = match opts.export_frame {
        Some(i) => selection(
            &base,
            &Options {
                frames: Some((i, i + 1)),
                shard: (0, 1),
                ..*opts
            },
        )?,
        None => selection(&base, opts)?,
    };
    // Every frame's draws are checked (placement, keep-in-view), and its scene built once per
    // structure, before any renders or the folder is claimed: bad input is exit 2 here, not a
    // frame that fails while the run goes on (exit 1).
    // (--export-frame writes the frame's scene as drawn, to see why it is refused.)
    if opts.export_frame.is_some() {
        frames
            .iter()
            .try_for_each(|&i| plan::plan(&base, i).map(drop))?;
    } else {
        super::check_frames::check(&base, &frames)?;
    }
    let mut out = Out::new(out.to_path_buf(), opts.verify);
    // A line of a frame the dataset does not have (frame 99 of 6) is not a finished frame.
    out.frames = base.config.frames;
    // With --verify, the frames listed before the full check (`prepare` drops damaged ones).
    let listed = if opts.verify && out.root.join(super::manifest::DATASET_JSON).is_file() {
        out.listed().unwrap_or_default()
    } else {
        Default::default()
    };
    // Held to the end: a --force run of another config cannot start over under this one.
    let _hold = out.prepare(&identity(&base)?, opts.force, file)?;
    // Temporaries of runs killed while writing (their process gone); a live run's stay.
    crate::output::guard::sweep(&out.frames_dir());
    let scene_dir = base
        .scene_file
        .parent()
        .unwrap_or(Path::new("."))
        .to_path_buf();

    if let Some(i) = opts.export_frame {
        let p = plan::plan(&base, i)?;
        let scale = p.exposure_scale;
        let mut text = super::export::scene_ron(p.scene, &scene_dir).map_err(Error::Other)?;
        if scale != 1.0 {
            // A scene has no exposure of its own: say what `prism render` leaves out.
            text = format!("// the dataset's sensor exposure scales this frame's sensor channels by {scale:e}\n{text}");
        }
        let path = out.stem(i).with_extension("ron");
        crate::output::write_atomic(&path, |tmp| {
            std::fs::write(
                tmp,
                format!(
                    "// frame {i} of {} (prism dataset --export-frame)\n{text}\n",
                    file.display()
                ),
            )
            .map_err(|e| e.to_string())
        })?;
        crate::error::note(format_args!(
            "wrote {}; `prism render {} -o frame.exr` renders frame {i}",
            path.display(),
            path.display()
        ));
        return Ok(Summary::default());
    }

    let done = out.done()?;
    if opts.verify {
        let damaged: Vec<u32> = listed
            .iter()
            .copied()
            .filter(|i| !done.contains_key(i))
            .collect();
        crate::error::note(format_args!(
            "verify: {} listed frame(s) read in full, {} damaged{}",
            listed.len(),
            damaged.len(),
            if damaged.is_empty() {
                String::new()
            } else {
                format!(" (rendered again unless --check): {damaged:?}")
            }
        ));
    }
    let todo: Vec<u32> = frames
        .iter()
        .copied()
        .filter(|i| !done.contains_key(i))
        .collect();
    if opts.check {
        let done: Vec<u32> = frames
            .iter()
            .copied()
            .filter(|i| !todo.contains(i))
            .collect();
        // The JSON is the command's result: failing to write it (`>/dev/full`) is an error.
        use std::io::Write;
        let line = json!({"frames": base.config.frames, "done": done, "todo": todo});
        writeln!(std::io::stdout().lock(), "{line}")
            .and_then(|_| std::io::stdout().lock().flush())
            .map_err(|e| {
                InputError::new(
                    file,
                    format!("cannot write the --check result to standard output: {e}"),
                )
                .field("--check")
                .hint("send standard output to a file or pipe that can take it")
            })?;
        return Ok(Summary::default());
    }
    let mut summary = Summary {
        skipped: (frames.len() - todo.len()) as u32,
        ..Summary::default()
    };
    std::fs::create_dir_all(out.frames_dir()).map_err(|e| {
        InputError::new(
            &out.frames_dir(),
            format!("cannot create the frames folder: {e}"),
        )
        .field("-o")
        .hint("give an output folder prism can write")
    })?;
    let bar = progress(todo.len() as u64, opts.quiet);
    let preview = base
        .config
        .outputs
        .preview
        .then_some(base.config.outputs.exposure);
    let mut cache = base
        .built
        .take()
        .map_or_else(frame::GeometryCache::default, frame::GeometryCache::seed);
    for (n, &i) in todo.iter().enumerate() {
        if opts.stop.is_some_and(|s| s.load(Ordering::Relaxed)) {
            summary.stopped = true;
            break;
        }
        let result = plan::plan(&base, i)
            .map_err(Error::from)
            .and_then(|p| {
                frame::render_frame(
                    &mut cache,
                    p.scene,
                    &base.scene_file,
                    &out.stem(i),
                    &p.params,
                    preview,
                    p.exposure_scale,
                )
            })
            .and_then(|r| {
                let e = out.entry(i, &r.files, r.seconds, r.invalid_samples)?;
                // For the crash tests: die as `kill -9` would between a frame's renames and
                // its manifest line (tests/dataset_runs.rs).
                if std::env::var("PRISM_TEST_ABORT_BEFORE_LISTING")
                    .is_ok_and(|v| v == i.to_string())
                {
                    std::process::abort();
                }
                out.append(&e)?;
                Ok(r)
            });
        match result {
            Ok(r) => {
                summary.rendered += 1;
                let msg = format!("frame {i} in {:.2} s", r.seconds);
                match &bar {
                    Some(b) => {
                        b.set_message(msg);
                        b.inc(1);
                    }
                    None if !opts.quiet => {
                        crate::error::note(format_args!("{msg} [{}/{}]", n + 1, todo.len()))
                    }
                    None => {}
                }
            }
            Err(e) => {
                summary.failed += 1;
                let line = format!("error: frame {i}: {e}");
                match &bar {
                    Some(b) => b.println(line),
                    None => crate::error::note(format_args!("{line}")),
                }
            }
        }
    }
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    // The contact sheet covers every frame the manifest lists (every shard's) with a preview.
    let pngs: Vec<_> = out
        .listed()?
        .into_iter()
        .map(|i| (i, out.stem(i).with_extension("png")))
        .filter(|(_, p)| preview.is_some() && p.is_file())
        .collect();
    let sheet = out.root.join("contact_sheet.png");
    if let Some(p) = super::sheet::write_frames(&pngs, &base.sheet_layers, &sheet)? {
        crate::error::note(format_args!("contact sheet: {}", p.display()));
    }
    let png = |i: u32| out.stem(i).with_extension("png");
    let listed = out.listed()?;
    if let Some(p) = super::sequence::previews(&base, &listed, png, &out.root)? {
        crate::error::note(format_args!("preview animation: {}", p.display()));
    }
    summary.seconds = t0.elapsed().as_secs_f64();
    crate::error::note(format_args!(
        "dataset: {} frame(s) selected: {} rendered, {} skipped (already done), {} failed{}, in {:.2} s (geometry built {} time(s)) -> {}",
        frames.len(),
        summary.rendered,
        summary.skipped,
        summary.failed,
        if summary.stopped {
            ", stopped early (a rerun resumes)"
        } else {
            ""
        },
        summary.seconds,
        cache.builds,
        out.root.display()
    ));
    Ok(summary)
}

/// A bar over frames with ETA on a terminal; None otherwise (a line per frame instead).
fn progress(total: u64, quiet: bool) -> Option<ProgressBar> {
    (!quiet && std::io::stderr().is_terminal()).then(|| {
        let b = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr());
        b.set_style(
            ProgressStyle::with_template("{bar:40} {pos}/{len} frames  {msg}  ETA {eta}")
                .expect("valid template"),
        );
        b
    })
}
