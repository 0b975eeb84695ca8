//! The `prism` command line: its subcommands, and `prism render` and `prism export` (their flags
//! and value parsers in `args`).

mod args;

use crate::config::{AdaptiveSpp, Spp};
use crate::error::Error;
use crate::output;
use crate::pipeline::worker_pool;
use crate::pipeline::workers::Reporter;
pub use args::{ExportArgs, ProbeArgs, RenderArgs, Switch};
use clap::{Parser, Subcommand};
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Parser, Debug)]
#[command(
    name = "prism",
    version,
    about = "A spectral path tracer for physically based dataset generation",
    long_about = "prism renders RON scene files with hero-wavelength spectral path tracing into \
                  multi-channel OpenEXR: linear sRGB, CIE XYZ and spectral radiance bands \
                  (W m^-2 sr^-1 nm^-1). The scene format is documented in scenes/README.md."
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Render a scene file to a multi-channel OpenEXR.
    Render(RenderArgs),
    /// Write the fully resolved scene (every default filled in, every spectrum tabulated, meshes
    /// as world-space PLY) as JSON, for other tools such as the Mitsuba 3 comparison.
    Export(ExportArgs),
    /// Print a material's BSDF values at directions read from stdin (for tests against
    /// independent implementations; see src/probe.rs).
    #[command(hide = true)]
    ProbeBsdf(ProbeArgs),
    /// Render a dataset: many frames of one scene with varied cameras, lights, materials and
    /// objects, seeded per frame, resumable and shardable (configs/README.md).
    Dataset(crate::dataset::cli::DatasetArgs),
}

pub use crate::error::note;

/// Runs the CLI; returns the process exit code.
pub fn main() -> i32 {
    run(std::env::args_os())
}

/// As `main`, with the command line given (the fuzzer runs prism in-process through it).
pub fn run<I, T>(args: I) -> i32
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    let cli = Cli::parse_from(args);
    let result = match cli.command {
        Command::Render(args) => render(&args),
        Command::Export(args) => {
            // Export allocates no film: the memory check is for renders.
            crate::resources::configure(Some(u64::MAX), None);
            export(&args)
        }
        Command::ProbeBsdf(a) => crate::probe::probe(
            &a.scene,
            &a.material,
            &a.lambda,
            std::io::stdin().lock(),
            std::io::stdout().lock(),
        ),
        Command::Dataset(args) => {
            // SIGINT/SIGTERM: remove the temporaries being written, exit 130/143.
            output::interrupt::install();
            match crate::dataset::cli::main(&args, None) {
                // Exit code 1 if a frame failed.
                Ok(s) => return i32::from(s.failed > 0),
                Err(e) => Err(e),
            }
        }
    };
    match result {
        Ok(()) => 0,
        Err(e) => {
            note(format_args!("error: {e}"));
            e.exit_code()
        }
    }
}

fn render(args: &RenderArgs) -> Result<(), Error> {
    if args.spp == Some(0) {
        return Err(crate::pipeline::workers::zero_spp(&args.scene).into());
    }
    let pool = worker_pool(args.workers.threads, &args.scene)?;
    if let Err(why) = args.simd.check() {
        return Err(crate::error::InputError::new(&args.scene, why)
            .field("--simd")
            .hint("--simd auto picks a width this CPU runs")
            .into());
    }
    if !args.exposure.is_finite() {
        return Err(crate::error::InputError::new(
            &args.scene,
            format!(
                "--exposure {} is not a finite number of stops",
                args.exposure
            ),
        )
        .hint("give a number such as --exposure -1.5")
        .into());
    }
    if let Some(t) = args.time.filter(|t| !t.is_finite()) {
        return Err(crate::error::InputError::new(
            &args.scene,
            format!("--time {t} is not a finite number of seconds"),
        )
        .hint("give a time such as --time 0.5")
        .into());
    }
    crate::resources::configure(args.max_memory, args.workers.threads);
    output::interrupt::install();
    let out = args
        .output
        .clone()
        .unwrap_or_else(|| default_output(&args.scene));
    output::guard::check_names(&out, args.preview.as_deref())?;
    let t_load = Instant::now();
    let job = crate::load::load(&args.scene, |cfg| {
        if let Some(spp) = args.spp {
            cfg.sampler.spp = Spp::Fixed(spp);
        }
        if let Some(rel_error) = args.rel_error {
            let base = cfg.sampler.spp.adaptive().unwrap_or(AdaptiveSpp {
                rel_error,
                min: 16,
                max: 4096,
                target: Default::default(),
                floor: 1e-3,
            });
            cfg.sampler.spp = Spp::Adaptive(AdaptiveSpp { rel_error, ..base });
        }
        if let Some(seed) = args.seed {
            cfg.sampler.seed = seed;
        }
        if let Some(t) = args.time {
            crate::load::motion::set_time(cfg, t);
        }
        if let Some(sh) = args.shutter {
            cfg.camera.shutter = Some(sh);
        }
        if args.fps.is_some() {
            cfg.camera.fps = args.fps;
        }
        if let Some(accel) = args.accel {
            cfg.accel = accel;
        }
        if let Some(kind) = args.sampler {
            cfg.sampler.kind = kind;
        }
        if let Some(c) = args.exr_compression {
            cfg.film.exr_compression = c;
        }
        if let Some(n) = args.wavelengths {
            cfg.spectral.wavelengths = n;
        }
        if let Some(w) = args.wavelength_sampling {
            cfg.spectral.sampling = w;
        }
        if let Some(p) = &args.sensor {
            cfg.sensor = Some(crate::load::sensor::cli_override(p));
            cfg.outputs = Default::default();
        }
        if !args.also_sensor.is_empty() {
            cfg.sensors = args
                .also_sensor
                .iter()
                .map(|(name, p)| crate::config::sensor::NamedSensor {
                    name: name.clone(),
                    sensor: crate::load::sensor::cli_override(p),
                })
                .collect();
        }
        if args.clamp.is_some() {
            cfg.integrator.clamp = args.clamp;
        }
        if let Some(a) = &args.aovs {
            cfg.aovs = a.iter().filter(|n| !n.is_empty()).cloned().collect();
        }
        cfg.boxes |= args.boxes;
        match args.caustics {
            Some(Switch::On) => {
                cfg.integrator.caustics = Some(cfg.integrator.caustics.unwrap_or_default())
            }
            Some(Switch::Off) => cfg.integrator.caustics = None,
            None => {}
        }
    })?;
    let mut job = job;
    job.settings.simd = args.simd;
    let load_s = t_load.elapsed().as_secs_f64();
    for w in &job.warnings {
        note(format_args!("warning: {w}"));
    }
    crate::pipeline::check_outputs(&job, &out, args.preview.as_deref())?;
    let s = &job.settings;
    // Adaptive: at most `spp` (= max) a pixel, pilot included, or a discarded pilot more for
    // a pixel alone in its tile: an upper bound for the progress line.
    let per_pixel = s.spp as u64 + s.adaptive.map_or(0, |a| a.min as u64);
    let total = s.width as u64 * s.height as u64 * per_pixel;
    let reporter = Reporter::new(total, args.workers.quiet);
    let r = pool.install(|| crate::pipeline::render(&job, 1.0, &|n| reporter.add(n)));
    reporter.finish();
    let files = crate::pipeline::Files {
        scene: &args.scene,
        exr: &out,
        sidecar: crate::pipeline::Sidecar::Render,
        preview: args.preview.as_deref().map(|p| (p, args.exposure)),
    };
    crate::pipeline::write(&job, &r, &files)?;
    let (stats, render_s) = (&r.stats, r.seconds);
    let msps = stats.samples as f64 / render_s / 1e6;
    note(format_args!(
        "rendered {}x{} at {} spp ({:.1} Msamples) in {:.2} s ({:.2} Msamples/s, {} thread{}); scene load {:.2} s; {} invalid samples{} -> {}",
        s.width,
        s.height,
        crate::config::Spp::of(s),
        stats.samples as f64 / 1e6,
        render_s,
        msps,
        pool.current_num_threads(),
        if pool.current_num_threads() == 1 { "" } else { "s" },
        load_s,
        stats.invalid_samples,
        match s.path.clamp {
            Some(c) => format!(", {} clamped at {c}", stats.clamped_samples),
            None => String::new(),
        },
        out.display()
    ));
    Ok(())
}

/// `prism export`: the output files are checked against the scene's inputs first; every
/// failure to write them is the user's to fix (exit 2).
fn export(args: &ExportArgs) -> Result<(), Error> {
    output::interrupt::install();
    let job = crate::load::load(&args.scene, |_| {})?;
    for f in crate::export::planned_files(&job, &args.output) {
        output::guard::check_output(&f, "-o", &job.inputs)?;
    }
    crate::export::export(&job, &args.scene, &args.output).map_err(|e| match e {
        Error::Input(_) => e,
        e => crate::error::InputError::new(&args.output, e.to_string())
            .field("-o")
            .hint("choose a writable output directory")
            .into(),
    })
}

fn default_output(scene: &Path) -> PathBuf {
    let stem = scene
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "render".into());
    PathBuf::from(format!("{stem}.exr"))
}
