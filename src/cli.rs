//! The `prism` command line.

use crate::config::{AdaptiveSpp, Spp};
use crate::error::Error;
use crate::output;
use clap::{Parser, Subcommand};
use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::pipeline::workers::Reporter;
use crate::pipeline::{worker_pool, WorkerArgs};

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

#[derive(clap::Args, Debug)]
pub struct ProbeArgs {
    /// The scene file (RON) defining the material.
    pub scene: PathBuf,
    /// The material's name in the scene.
    #[arg(long)]
    pub material: String,
    /// Wavelengths in nm, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "550")]
    pub lambda: Vec<f32>,
}

#[derive(clap::Args, Debug)]
pub struct ExportArgs {
    /// The scene file (RON).
    pub scene: PathBuf,
    /// Output directory: receives scene.json and meshes/.
    #[arg(short, long)]
    pub output: PathBuf,
}

#[derive(clap::Args, Debug)]
pub struct RenderArgs {
    /// The scene file (RON).
    pub scene: PathBuf,
    /// Output EXR path. Default: the scene's name with .exr, in the current directory.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Samples per pixel (overrides the scene's sampler.spp).
    #[arg(long, conflicts_with = "rel_error")]
    pub spp: Option<u32>,
    /// Adaptive sampling to this relative standard error per pixel, e.g. 0.01 (overrides the
    /// scene's sampler.spp; keeps its Adaptive min/max/target, or takes min 16, max 4096, Y).
    #[arg(long)]
    pub rel_error: Option<f32>,
    /// Random seed (overrides the scene's sampler.seed).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Render the scene at this instant, in seconds (replaces the camera's shutter with
    /// open = close = T; animated transforms take their values then).
    #[arg(long, allow_hyphen_values = true)]
    pub time: Option<f32>,
    /// Opens the shutter from OPEN to CLOSE seconds (motion blur), with READOUT seconds per row
    /// for a rolling shutter: `--shutter 0,0.02` or `--shutter 0,0.02,0.00002` (replaces the
    /// camera's shutter; a glTF file rendered directly has no other).
    #[arg(long, value_name = "OPEN,CLOSE[,READOUT]", value_parser = parse_shutter, conflicts_with = "time", allow_hyphen_values = true)]
    pub shutter: Option<crate::config::ShutterConfig>,
    /// Frames per second (overrides the scene's camera.fps): the flow layers follow each
    /// pixel's point to the frames 1/fps later and earlier.
    #[arg(long)]
    pub fps: Option<f32>,
    /// Acceleration structure (overrides the scene's `accel`); `embree` needs prism built with
    /// `--features embree`.
    #[arg(long, value_enum)]
    pub accel: Option<crate::accel::AccelKind>,
    /// Paths per packet: 1, 4, 8, 16, `auto` (the widest this CPU runs) or `off` (the scalar
    /// integrator). Every width gives the same bits; scenes the packet kernel does not take
    /// (adaptive sampling, caustics, dispersion) use the scalar integrator whatever this says.
    #[arg(long, value_enum, default_value = "auto")]
    pub simd: crate::integrator::packet::Simd,
    /// Sampler (overrides the scene's sampler.kind).
    #[arg(long, value_enum)]
    pub sampler: Option<crate::sampler::SamplerKind>,
    /// Wavelengths per path (overrides the scene's spectral.wavelengths): 1, 2, 4, 8 or 16.
    #[arg(long)]
    pub wavelengths: Option<usize>,
    /// Wavelength sampling (overrides the scene's spectral.sampling).
    #[arg(long, value_enum)]
    pub wavelength_sampling: Option<crate::spectrum::WavelengthSampling>,
    /// Caustic light tracing (overrides the scene's integrator.caustics; `on` keeps the
    /// scene's settings or takes the defaults). Unbiased either way.
    #[arg(long, value_enum)]
    pub caustics: Option<Switch>,
    /// Opt-in firefly clamp: cut each sample's radiance to at most this (overrides the
    /// scene's integrator.clamp). Biased: for previews, never for ground truth.
    #[arg(long)]
    pub clamp: Option<f32>,
    /// AOV layers, comma-separated (overrides the scene's `aovs`): depth,normal,instance,...
    /// (`--aovs ""` for none).
    #[arg(long, value_delimiter = ',')]
    pub aovs: Option<Vec<String>>,
    /// Write the sidecar's per-object 2D boxes and visible pixel counts even without a geometry
    /// or id AOV (one extra ray per pixel; docs/sidecar.md).
    #[arg(long)]
    pub boxes: bool,
    /// A sensor file (RON, configs/sensors/*.ron) replacing the scene's `sensor`/`outputs`.
    #[arg(long)]
    pub sensor: Option<PathBuf>,
    /// A further sensor on the same paths, `NAME=FILE` (repeatable; replaces the scene's
    /// `sensors`): its channels are written prefixed `NAME.` beside the main sensor's.
    #[arg(long = "also-sensor", value_name = "NAME=FILE", value_parser = parse_named_sensor)]
    pub also_sensor: Vec<(String, PathBuf)>,
    /// Also write an 8-bit sRGB PNG preview here.
    #[arg(long)]
    pub preview: Option<PathBuf>,
    /// Exposure of the preview in stops (the PNG shows radiance × 2^exposure).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub exposure: f32,
    /// Memory the render may use, e.g. `8GiB` or `512MiB` (default: what the machine has
    /// available); a scene whose estimated need exceeds it is refused before rendering.
    #[arg(long, value_parser = crate::resources::parse_size)]
    pub max_memory: Option<u64>,
    #[command(flatten)]
    pub workers: WorkerArgs,
}

/// `--also-sensor NAME=FILE`.
fn parse_named_sensor(s: &str) -> Result<(String, PathBuf), String> {
    match s.split_once('=') {
        Some((name, file)) if !name.is_empty() && !file.is_empty() => {
            Ok((name.to_string(), PathBuf::from(file)))
        }
        _ => Err(format!(
            "`{s}` is not NAME=FILE (e.g. --also-sensor nikon=configs/sensors/nikon_d810.ron)"
        )),
    }
}

/// `OPEN,CLOSE[,READOUT]` in seconds (the loader checks the values: `load::motion`).
fn parse_shutter(s: &str) -> Result<crate::config::ShutterConfig, String> {
    let v: Result<Vec<f32>, _> = s.split(',').map(|x| x.trim().parse::<f32>()).collect();
    match v.as_deref() {
        Ok(&[open, close]) => Ok(crate::config::ShutterConfig {
            open,
            close,
            readout: 0.0,
        }),
        Ok(&[open, close, readout]) => Ok(crate::config::ShutterConfig {
            open,
            close,
            readout,
        }),
        _ => Err(format!(
            "`{s}` is not OPEN,CLOSE or OPEN,CLOSE,READOUT in seconds (e.g. --shutter 0,0.02)"
        )),
    }
}

/// A feature switched on or off from the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Switch {
    On,
    Off,
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
        Command::Dataset(args) => match crate::dataset::cli::main(&args) {
            Ok(code) => return code,
            Err(e) => Err(e),
        },
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
            .hint("--simd auto picks the widest this CPU runs")
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
    // Adaptive: the most samples the render may take (pilots included).
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
