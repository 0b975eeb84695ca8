//! The flags of `prism render`, `export` and `probe-bsdf`, and their value parsers.

use crate::pipeline::WorkerArgs;
use std::path::PathBuf;

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
    /// Paths per packet: 1, 4, 8, 16, `auto` (8 with AVX2, else 4) or `off` (the scalar
    /// integrator). Every width gives the same bits; scenes the packet kernel does not take
    /// (a dispersive material) use the scalar integrator whatever this says.
    #[arg(long, value_enum, default_value = "auto")]
    pub simd: crate::integrator::packet::Simd,
    /// The EXR's lossless compression (overrides the scene's film.exr_compression): `zip`
    /// (default), `piz`, `rle` or `none` (the fastest to write).
    #[arg(long, value_enum)]
    pub exr_compression: Option<crate::config::ExrCompression>,
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
