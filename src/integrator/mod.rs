//! Rendering: the image is cut into tiles rendered in parallel; every pixel takes all its
//! samples in order, so its value depends only on (scene, seed, pixel) and never on threads.

pub mod adaptive;
pub mod albedo;
pub mod aov;
pub mod caustics;
pub mod flow;
pub mod packet;
pub mod path;
mod tile;

use crate::film::Film;
use crate::filter::Filter;
use crate::sampler::SamplerKind;
use crate::scene::Scene;
use crate::sensor::FilmChannels;
use crate::sensor::Sensor;
use crate::spectrum::WavelengthSampler;
pub use caustics::CausticSettings;
use caustics::Caustics;
pub use path::{Dispersion, PathSettings};
use rayon::prelude::*;
use tile::render_tile;
pub(crate) use tile::{add_sample, finish_pixel_at, Sums, TileCounts, TileOut, CHECK_EVERY};

/// Wavelengths per path the renderer is compiled for.
pub const SUPPORTED_LANES: [usize; 5] = [1, 2, 4, 8, 16];

/// Everything about how to render, besides the scene itself.
#[derive(Clone, Debug)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    /// Samples per pixel; with `adaptive`, the most a pixel's estimate takes.
    pub spp: u32,
    /// Adaptive sampling (`adaptive`): each pixel's count from its neighbours' pilots.
    pub adaptive: Option<adaptive::AdaptiveSpp>,
    pub seed: u64,
    pub sampler: SamplerKind,
    /// Wavelengths per path (one of `SUPPORTED_LANES`).
    pub lanes: usize,
    pub wavelengths: WavelengthSampler,
    pub filter: Filter,
    pub path: PathSettings,
    pub dispersion: Dispersion,
    /// Packet width (`--simd`); scenes `packet::unsupported` names use the scalar loop.
    pub simd: packet::Simd,
}

/// What a render measured about itself.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RenderStats {
    pub samples: u64,
    /// Camera samples whose radiance was NaN or infinite (counted, and left out of the image),
    /// plus pixels whose accumulated value overflowed to a non-finite one (left in it).
    pub invalid_samples: u64,
    /// Camera samples cut down by the opt-in `clamp`.
    pub clamped_samples: u64,
}

const TILE: u32 = 16;

/// Renders `scene`; `progress` is called with the number of camera samples each finished tile took
/// (and with 0 as each tile begins).
pub fn render(
    scene: &Scene,
    settings: &RenderSettings,
    channels: &FilmChannels,
    progress: &(dyn Fn(u64) + Sync),
) -> (Film, RenderStats) {
    let (film, stats, _) = render_film(scene, settings, channels, false, progress);
    (film, stats)
}

/// As `render`, also returning each pixel's sample count and, with `stderr`, its standard
/// error of every accumulator slot (X, Y, Z, bands; `slots` per pixel, from the spread of its
/// camera samples, plus with caustic light tracing the variance of its light paths' mean), the
/// colour channels staying bit for bit those of `render`.
pub fn render_film(
    scene: &Scene,
    settings: &RenderSettings,
    channels: &FilmChannels,
    stderr: bool,
    progress: &(dyn Fn(u64) + Sync),
) -> (Film, RenderStats, PixelErrors) {
    let sensor = &channels.sensor;
    let (means, mut stats, se) = match (settings.lanes, stderr) {
        (1, false) => render_lanes::<1, false>(scene, settings, sensor, progress),
        (2, false) => render_lanes::<2, false>(scene, settings, sensor, progress),
        (4, false) => render_lanes::<4, false>(scene, settings, sensor, progress),
        (8, false) => render_lanes::<8, false>(scene, settings, sensor, progress),
        (16, false) => render_lanes::<16, false>(scene, settings, sensor, progress),
        (1, true) => render_lanes::<1, true>(scene, settings, sensor, progress),
        (2, true) => render_lanes::<2, true>(scene, settings, sensor, progress),
        (4, true) => render_lanes::<4, true>(scene, settings, sensor, progress),
        (8, true) => render_lanes::<8, true>(scene, settings, sensor, progress),
        (16, true) => render_lanes::<16, true>(scene, settings, sensor, progress),
        (n, _) => panic!("{n} wavelengths per path is not supported (config validation lets only {SUPPORTED_LANES:?} through)"),
    };
    let (w, h, slots) = (settings.width, settings.height, sensor.slots());
    let film = channels.develop(w, h, &means, slots, settings.seed);
    // Finite samples can still sum past f32's range; such pixels count as invalid too.
    stats.invalid_samples += film.nonfinite_pixels();
    (film, stats, se)
}

/// Per-pixel measurements beside the film, row-major.
#[derive(Clone, Debug, Default)]
pub struct PixelErrors {
    /// With `stderr`: each pixel's standard error of every accumulator slot (`slots` per
    /// pixel); empty otherwise.
    pub stderr: Vec<f32>,
    /// The samples each pixel's estimate averaged (`settings.spp` everywhere unless adaptive;
    /// an adaptive pixel's pilot is in its estimate and its count).
    pub spp: Vec<u32>,
}

/// `SE`: also return each pixel's standard error per slot (empty otherwise).
fn render_lanes<const N: usize, const SE: bool>(
    scene: &Scene,
    settings: &RenderSettings,
    sensor: &Sensor,
    progress: &(dyn Fn(u64) + Sync),
) -> (Vec<f32>, RenderStats, PixelErrors) {
    let (w, h) = (settings.width, settings.height);
    let slots = sensor.slots();
    let dispersive = scene.materials.iter().any(|m| m.dispersive());
    let tiles: Vec<(u32, u32)> = (0..h.div_ceil(TILE))
        .flat_map(|ty| (0..w.div_ceil(TILE)).map(move |tx| (tx * TILE, ty * TILE)))
        .collect();
    let caustics = settings.path.caustics.and_then(|c| Caustics::new(scene, c));
    let packets = packet::width(scene, settings);
    let results: Vec<TileOut> = tiles
        .par_iter()
        // Every tile its own job: rayon otherwise runs a range of tiles as one unsplittable
        // leaf, and a thread left with the costly end of a frame ran it alone (15% of a
        // tabletop frame's wall time single-threaded).
        .with_max_len(1)
        .map(|&(x0, y0)| {
            // A call before the tile's work too: a caller stopping the render (the Python
            // module's Ctrl-C unwinds from it) skips the tiles not yet begun.
            progress(0);
            let r = match packets {
                Some(w) => {
                    let c = caustics.as_ref();
                    packet::render_tile::<N, SE>(w, scene, settings, sensor, c, progress, x0, y0)
                }
                None => render_tile::<N, SE>(
                    scene,
                    settings,
                    sensor,
                    dispersive,
                    caustics.as_ref(),
                    progress,
                    (x0, y0),
                ),
            };
            progress(r.counts.samples);
            r
        })
        .collect();
    let mut means = vec![0.0f32; (w * h) as usize * slots];
    let mut se = vec![0.0f32; if SE { means.len() } else { 0 }];
    let mut spp = vec![0u32; (w * h) as usize];
    let (mut samples, mut invalid, mut clamped) = (0, 0, 0);
    for (&(x0, y0), r) in tiles.iter().zip(&results) {
        samples += r.counts.samples;
        invalid += r.counts.invalid;
        clamped += r.counts.clamped;
        let tw = (x0 + TILE).min(w) - x0;
        for (i, px) in r.means.chunks_exact(slots).enumerate() {
            let (x, y) = (x0 + i as u32 % tw, y0 + i as u32 / tw);
            let at = (y * w + x) as usize * slots;
            means[at..at + slots].copy_from_slice(px);
            spp[at / slots] = r.spp[i];
            if SE {
                se[at..at + slots].copy_from_slice(&r.se[i * slots..(i + 1) * slots]);
            }
        }
    }
    if let Some(c) = &caustics {
        // Light paths per camera sample of the estimates (an adaptive render's count is
        // known only now; a fixed one's is width · height · spp).
        let estimated: u64 = spp.iter().map(|&n| n as u64).sum();
        let (add, var) = c.render::<N, SE>(scene, settings, sensor, estimated);
        for (m, add) in means.iter_mut().zip(add) {
            *m = (*m as f64 + add) as f32;
        }
        // The two estimates are independent: their variances add.
        for (e, v) in se.iter_mut().zip(var) {
            let e0 = *e as f64;
            *e = (e0 * e0 + v).sqrt() as f32;
        }
    }
    (
        means,
        RenderStats {
            samples,
            invalid_samples: invalid,
            clamped_samples: clamped,
        },
        PixelErrors { stderr: se, spp },
    )
}
