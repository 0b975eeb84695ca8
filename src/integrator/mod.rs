//! Rendering: the image is cut into tiles rendered in parallel; every pixel takes all its
//! samples in order, so its value depends only on (scene, seed, pixel) and never on threads.

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

/// Renders `scene`; `progress` is called with the number of camera samples each finished tile took.
pub fn render(
    scene: &Scene,
    settings: &RenderSettings,
    channels: &FilmChannels,
    progress: &(dyn Fn(u64) + Sync),
) -> (Film, RenderStats) {
    let sensor = Sensor::new(channels.bands);
    let (means, mut stats) = match settings.lanes {
        1 => render_lanes::<1>(scene, settings, &sensor, progress),
        2 => render_lanes::<2>(scene, settings, &sensor, progress),
        4 => render_lanes::<4>(scene, settings, &sensor, progress),
        8 => render_lanes::<8>(scene, settings, &sensor, progress),
        16 => render_lanes::<16>(scene, settings, &sensor, progress),
        n => panic!("{n} wavelengths per path is not supported (config validation lets only {SUPPORTED_LANES:?} through)"),
    };
    let film = Film::from_means(
        settings.width,
        settings.height,
        channels,
        &means,
        sensor.slots(),
    );
    // Finite samples can still sum past f32's range; such pixels count as invalid too.
    stats.invalid_samples += film.nonfinite_pixels();
    (film, stats)
}

fn render_lanes<const N: usize>(
    scene: &Scene,
    settings: &RenderSettings,
    sensor: &Sensor,
    progress: &(dyn Fn(u64) + Sync),
) -> (Vec<f32>, RenderStats) {
    let (w, h) = (settings.width, settings.height);
    let slots = sensor.slots();
    let dispersive = scene.materials.iter().any(|m| m.dispersive());
    let tiles: Vec<(u32, u32)> = (0..h.div_ceil(TILE))
        .flat_map(|ty| (0..w.div_ceil(TILE)).map(move |tx| (tx * TILE, ty * TILE)))
        .collect();
    let caustics = settings.path.caustics.and_then(|c| Caustics::new(scene, c));
    let results: Vec<(Vec<f32>, TileCounts)> = tiles
        .par_iter()
        .map(|&(x0, y0)| {
            let r = render_tile::<N>(
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
    let (mut invalid, mut clamped) = (0, 0);
    for (&(x0, y0), (tile, counts)) in tiles.iter().zip(&results) {
        invalid += counts.invalid;
        clamped += counts.clamped;
        let tw = (x0 + TILE).min(w) - x0;
        for (i, px) in tile.chunks_exact(slots).enumerate() {
            let (x, y) = (x0 + i as u32 % tw, y0 + i as u32 / tw);
            let at = (y * w + x) as usize * slots;
            means[at..at + slots].copy_from_slice(px);
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
fn render_tile<const N: usize>(
    scene: &Scene,
    settings: &RenderSettings,
    sensor: &Sensor,
    dispersive: bool,
    caustics: Option<&Caustics>,
    x0: u32,
    y0: u32,
) -> (Vec<f32>, TileCounts) {
    let (x1, y1) = (
        (x0 + TILE).min(settings.width),
        (y0 + TILE).min(settings.height),
    );
    let slots = sensor.slots();
    let mut out = Vec::with_capacity(((x1 - x0) * (y1 - y0)) as usize * slots);
    let mut acc = vec![0.0f64; slots];
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
            let pixel = y as u64 * settings.width as u64 + x as u64;
            let mut sampler = PixelSampler::new(settings.sampler, settings.seed, pixel);
            for s in 0..settings.spp {
                sampler.start(s);
                let offset = settings.filter.sample(sampler.next_2d());
                let film = Vec2::new(x as f32 + 0.5, y as f32 + 0.5) + offset;
                let wl = settings.wavelengths.sample::<N>(sampler.next_1d());
                let ray = scene.camera.ray(film);
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
            }
            out.extend(acc.iter().map(|&a| (a * inv_spp) as f32));
        }
    }
    (out, counts)
}
