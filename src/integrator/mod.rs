//! Rendering: the image is cut into tiles rendered in parallel; every pixel takes all its
//! samples in order, so its value depends only on (scene, seed, pixel) and never on threads.

pub mod albedo;
pub mod aov;
pub mod caustics;
pub mod path;

use crate::film::{Film, FilmChannels};
use crate::filter::Filter;
use crate::sampler::{PixelSampler, SamplerKind};
use crate::scene::Scene;
use crate::sensor::Sensor;
use crate::spectrum::{Spectrum, WavelengthSampler};
pub use caustics::CausticSettings;
use caustics::Caustics;
use glam::Vec2;
pub use path::{Dispersion, PathSettings};
use rayon::prelude::*;

/// Wavelengths per path the renderer is compiled for.
pub const SUPPORTED_LANES: [usize; 5] = [1, 2, 4, 8, 16];

/// Everything about how to render, besides the scene itself.
#[derive(Clone, Debug)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    pub seed: u64,
    pub sampler: SamplerKind,
    /// Wavelengths per path (one of `SUPPORTED_LANES`).
    pub lanes: usize,
    pub wavelengths: WavelengthSampler,
    pub filter: Filter,
    pub path: PathSettings,
    pub dispersion: Dispersion,
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

/// As `render`; with `stderr`, also each pixel's standard error of every accumulator slot
/// (X, Y, Z, bands; `slots` per pixel, from the spread of its camera samples), the colour
/// channels staying bit for bit those of `render`. Caustic light tracing adds no per-pixel
/// samples, so the scene loader refuses the `stderr` AOV with it.
pub fn render_film(
    scene: &Scene,
    settings: &RenderSettings,
    channels: &FilmChannels,
    stderr: bool,
    progress: &(dyn Fn(u64) + Sync),
) -> (Film, RenderStats, Vec<f32>) {
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
    let mut film = Film::from_means(
        settings.width,
        settings.height,
        channels,
        &means,
        sensor.slots(),
    );
    if let Some(raw) = &sensor.raw {
        let (w, h, slots) = (settings.width, settings.height, sensor.slots());
        film.uint_channels
            .push(raw.mosaic(&means, slots, w, h, settings.seed));
    }
    // Finite samples can still sum past f32's range; such pixels count as invalid too.
    stats.invalid_samples += film.nonfinite_pixels();
    (film, stats, se)
}

/// `SE`: also return each pixel's standard error per slot (empty otherwise).
fn render_lanes<const N: usize, const SE: bool>(
    scene: &Scene,
    settings: &RenderSettings,
    sensor: &Sensor,
    progress: &(dyn Fn(u64) + Sync),
) -> (Vec<f32>, RenderStats, Vec<f32>) {
    let (w, h) = (settings.width, settings.height);
    let slots = sensor.slots();
    let dispersive = scene.materials.iter().any(|m| m.dispersive());
    let tiles: Vec<(u32, u32)> = (0..h.div_ceil(TILE))
        .flat_map(|ty| (0..w.div_ceil(TILE)).map(move |tx| (tx * TILE, ty * TILE)))
        .collect();
    let caustics = settings.path.caustics.and_then(|c| Caustics::new(scene, c));
    let results: Vec<(Vec<f32>, Vec<f32>, TileCounts)> = tiles
        .par_iter()
        .map(|&(x0, y0)| {
            // A call before the tile's work too: a caller stopping the render (the Python
            // module's Ctrl-C unwinds from it) skips the tiles not yet begun.
            progress(0);
            let r = render_tile::<N, SE>(
                scene,
                settings,
                sensor,
                dispersive,
                caustics.as_ref(),
                x0,
                y0,
            );
            let (x1, y1) = ((x0 + TILE).min(w), (y0 + TILE).min(h));
            progress(((x1 - x0) * (y1 - y0)) as u64 * settings.spp as u64);
            r
        })
        .collect();
    let mut means = vec![0.0f32; (w * h) as usize * slots];
    let mut se = vec![0.0f32; if SE { means.len() } else { 0 }];
    let (mut invalid, mut clamped) = (0, 0);
    for (&(x0, y0), (tile, tile_se, counts)) in tiles.iter().zip(&results) {
        invalid += counts.invalid;
        clamped += counts.clamped;
        let tw = (x0 + TILE).min(w) - x0;
        for (i, px) in tile.chunks_exact(slots).enumerate() {
            let (x, y) = (x0 + i as u32 % tw, y0 + i as u32 / tw);
            let at = (y * w + x) as usize * slots;
            means[at..at + slots].copy_from_slice(px);
            if SE {
                se[at..at + slots].copy_from_slice(&tile_se[i * slots..(i + 1) * slots]);
            }
        }
    }
    if let Some(c) = &caustics {
        for (m, add) in means.iter_mut().zip(c.render::<N>(scene, settings, sensor)) {
            *m = (*m as f64 + add) as f32;
        }
    }
    let samples = w as u64 * h as u64 * settings.spp as u64;
    (
        means,
        RenderStats {
            samples,
            invalid_samples: invalid,
            clamped_samples: clamped,
        },
        se,
    )
}

/// Per-tile sample counts.
#[derive(Clone, Copy, Default)]
struct TileCounts {
    invalid: u64,
    clamped: u64,
}

/// `dispersive`: some material of the scene samples directions by wavelength (see
/// `path::radiance`).
fn render_tile<const N: usize, const SE: bool>(
    scene: &Scene,
    settings: &RenderSettings,
    sensor: &Sensor,
    dispersive: bool,
    caustics: Option<&Caustics>,
    x0: u32,
    y0: u32,
) -> (Vec<f32>, Vec<f32>, TileCounts) {
    let (x1, y1) = (
        (x0 + TILE).min(settings.width),
        (y0 + TILE).min(settings.height),
    );
    let slots = sensor.slots();
    let mut out = Vec::with_capacity(((x1 - x0) * (y1 - y0)) as usize * slots);
    let mut acc = vec![0.0f64; slots];
    // Standard errors: each sample's own contribution and the sums of their squares.
    let (mut se_out, mut one, mut acc2) = if SE {
        (
            Vec::with_capacity(out.capacity()),
            vec![0.0f64; slots],
            vec![0.0f64; slots],
        )
    } else {
        (Vec::new(), Vec::new(), Vec::new())
    };
    let mut counts = TileCounts::default();
    let clamp = settings.path.clamp.unwrap_or(f32::INFINITY);
    let inv_spp = 1.0 / settings.spp as f64;
    let radiance = match (dispersive, caustics.is_some()) {
        (true, true) => path::radiance::<N, true, true>,
        (true, false) => path::radiance::<N, true, false>,
        (false, true) => path::radiance::<N, false, true>,
        (false, false) => path::radiance::<N, false, false>,
    };
    for y in y0..y1 {
        for x in x0..x1 {
            acc.iter_mut().for_each(|a| *a = 0.0);
            if SE {
                acc2.iter_mut().for_each(|a| *a = 0.0);
            }
            let pixel = y as u64 * settings.width as u64 + x as u64;
            let mut sampler = PixelSampler::new(settings.sampler, settings.seed, pixel);
            for s in 0..settings.spp {
                sampler.start(s);
                let offset = settings.filter.sample(sampler.next_2d());
                let film = Vec2::new(x as f32 + 0.5, y as f32 + 0.5) + offset;
                let wl = settings.wavelengths.sample::<N>(sampler.next_1d());
                let ray = scene.camera.ray(film, &mut sampler);
                let mut l = radiance(
                    scene,
                    ray,
                    &wl,
                    &mut sampler,
                    &settings.path,
                    settings.dispersion,
                    caustics,
                );
                if !l.is_finite() {
                    counts.invalid += 1;
                    continue;
                }
                if l.max_value() > clamp {
                    counts.clamped += 1;
                    l = Spectrum::from_fn(|j| l[j].min(clamp));
                }
                sensor.add(&mut acc, &l, &wl.estimator_weights(), &wl);
                if SE {
                    // A second add into a scratch, so `acc` sums exactly as without SE.
                    one.iter_mut().for_each(|a| *a = 0.0);
                    sensor.add(&mut one, &l, &wl.estimator_weights(), &wl);
                    acc2.iter_mut().zip(&one).for_each(|(q, v)| *q += v * v);
                }
            }
            out.extend(acc.iter().map(|&a| (a * inv_spp) as f32));
            if SE {
                // Unbiased sample variance over spp samples (invalid ones count as 0), / spp.
                let n = settings.spp as f64;
                se_out.extend(acc.iter().zip(&acc2).map(|(&s, &q)| {
                    let var = if n > 1.0 {
                        ((q - s * s / n) / (n - 1.0)).max(0.0)
                    } else {
                        0.0
                    };
                    (var / n).sqrt() as f32
                }));
            }
        }
    }
    (out, se_out, counts)
}
