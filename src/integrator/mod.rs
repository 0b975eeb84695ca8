//! Rendering: the image is cut into tiles rendered in parallel; every pixel takes all its
//! samples in order, so its value depends only on (scene, seed, pixel) and never on threads.

pub mod adaptive;
pub mod albedo;
pub mod aov;
pub mod caustics;
pub mod flow;
pub mod packet;
pub mod path;

use crate::film::Film;
use crate::filter::Filter;
use crate::sampler::{PixelSampler, SamplerKind};
use crate::scene::Scene;
use crate::sensor::FilmChannels;
use crate::sensor::Sensor;
use crate::spectrum::{Spectrum, WavelengthSampler, Wavelengths};
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
    /// Samples per pixel; with `adaptive`, the most a pixel's estimate takes.
    pub spp: u32,
    /// Adaptive sampling (`adaptive`): each pixel's count from a pilot batch of its own.
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
/// camera samples), the colour channels staying bit for bit those of `render`. Caustic light tracing adds no per-pixel
/// samples, so the scene loader refuses the `stderr` AOV with it.
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
    /// an adaptive pilot batch is not counted: it is not in the estimate).
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
        .map(|&(x0, y0)| {
            // A call before the tile's work too: a caller stopping the render (the Python
            // module's Ctrl-C unwinds from it) skips the tiles not yet begun.
            progress(0);
            let r = match packets {
                Some(w) => {
                    packet::render_tile::<N, SE>(w, scene, settings, sensor, progress, x0, y0)
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
        for (m, add) in means.iter_mut().zip(c.render::<N>(scene, settings, sensor)) {
            *m = (*m as f64 + add) as f32;
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

/// Per-tile sample counts (pilot samples included).
#[derive(Clone, Copy, Default)]
struct TileCounts {
    samples: u64,
    invalid: u64,
    clamped: u64,
}

/// A tile's pixels, in its own row-major order: slot means, slot standard errors (with `SE`),
/// and each pixel's estimate's sample count.
struct TileOut {
    means: Vec<f32>,
    se: Vec<f32>,
    spp: Vec<u32>,
    counts: TileCounts,
}

/// One pixel's accumulators: per-slot sums, and with squares, each sample's own slot values
/// (`one`) and the sums of their squares.
struct Sums {
    acc: Vec<f64>,
    one: Vec<f64>,
    acc2: Vec<f64>,
}

impl Sums {
    fn new(slots: usize, squares: bool) -> Self {
        let n = if squares { slots } else { 0 };
        Sums {
            acc: vec![0.0; slots],
            one: vec![0.0; n],
            acc2: vec![0.0; n],
        }
    }

    fn clear(&mut self) {
        self.acc.iter_mut().for_each(|a| *a = 0.0);
        self.acc2.iter_mut().for_each(|a| *a = 0.0);
    }
}

/// What every sample of a tile shares.
struct Pass<'a, const N: usize> {
    scene: &'a Scene,
    settings: &'a RenderSettings,
    sensor: &'a Sensor,
    caustics: Option<&'a Caustics<'a>>,
    clamp: f32,
    radiance: path::RadianceFn<N>,
    /// Called with 0 every `CHECK_EVERY` samples of a pixel: a caller stopping the render
    /// (the Python module's Ctrl-C unwinds from it) stops it inside a long tile too.
    progress: &'a (dyn Fn(u64) + Sync),
}

/// Samples between two `progress(0)` calls inside a pixel (a power of two; at ~1 µs a
/// sample, a few milliseconds).
pub(crate) const CHECK_EVERY: u32 = 4096;

impl<const N: usize> Pass<'_, N> {
    /// Samples `0..n` of pixel (x, y) from `sampler`, summed into `sums` (with `SQ`, their
    /// squares too: a second add into a scratch, so `acc` sums exactly as without them).
    #[inline(always)]
    fn take<const SQ: bool>(
        &self,
        x: u32,
        y: u32,
        sampler: &mut PixelSampler,
        n: u32,
        sums: &mut Sums,
        counts: &mut TileCounts,
    ) {
        let settings = self.settings;
        counts.samples += n as u64;
        // In runs of CHECK_EVERY samples, with the check between runs: no cost per sample.
        for run in (0..n).step_by(CHECK_EVERY as usize) {
            if run > 0 {
                (self.progress)(0);
            }
            for s in run..n.min(run.saturating_add(CHECK_EVERY)) {
                sampler.start(s);
                let offset = settings.filter.sample(sampler.next_2d());
                let film = Vec2::new(x as f32 + 0.5, y as f32 + 0.5) + offset;
                let wl = settings.wavelengths.sample::<N>(sampler.next_1d());
                let ray = self.scene.camera_ray(film, y, sampler);
                let l = (self.radiance)(
                    self.scene,
                    ray,
                    &wl,
                    sampler,
                    &settings.path,
                    settings.dispersion,
                    self.caustics,
                );
                add_sample::<N, SQ>(self.sensor, self.clamp, l, &wl, sums, counts);
            }
        }
    }
}

/// Adds one camera sample's radiance `l` at `wl` to a pixel's `sums` (with `SQ`, its squares
/// too: a second add into a scratch, so `acc` sums exactly as without them). The scalar loop
/// and the packet kernel's in-order flush both come here, so they sum alike.
#[inline(always)]
fn add_sample<const N: usize, const SQ: bool>(
    sensor: &Sensor,
    clamp: f32,
    mut l: Spectrum<N>,
    wl: &Wavelengths<N>,
    sums: &mut Sums,
    counts: &mut TileCounts,
) {
    if !l.is_finite() {
        counts.invalid += 1;
        return;
    }
    if l.max_value() > clamp {
        counts.clamped += 1;
        l = Spectrum::from_fn(|j| l[j].min(clamp));
    }
    sensor.add(&mut sums.acc, &l, &wl.estimator_weights(), wl);
    if SQ {
        sums.one.iter_mut().for_each(|a| *a = 0.0);
        sensor.add(&mut sums.one, &l, &wl.estimator_weights(), wl);
        let sq = sums.acc2.iter_mut().zip(&sums.one);
        sq.for_each(|(q, v)| *q += v * v);
    }
}

/// Appends a finished pixel of `n` samples (its `sums`) to `out`.
#[inline(always)]
fn finish_pixel<const SE: bool>(sums: &Sums, n: u32, out: &mut TileOut) {
    let inv_n = 1.0 / n as f64;
    out.means
        .extend(sums.acc.iter().map(|&a| (a * inv_n) as f32));
    out.spp.push(n);
    if SE {
        // Unbiased sample variance over n samples (invalid ones count as 0), / n.
        let n = n as f64;
        out.se
            .extend(sums.acc.iter().zip(&sums.acc2).map(|(&s, &q)| {
                let var = if n > 1.0 {
                    ((q - s * s / n) / (n - 1.0)).max(0.0)
                } else {
                    0.0
                };
                (var / n).sqrt() as f32
            }));
    }
}

/// `dispersive`: some material of the scene samples directions by wavelength (see
/// `path::radiance`).
fn render_tile<const N: usize, const SE: bool>(
    scene: &Scene,
    settings: &RenderSettings,
    sensor: &Sensor,
    dispersive: bool,
    caustics: Option<&Caustics>,
    progress: &(dyn Fn(u64) + Sync),
    (x0, y0): (u32, u32),
) -> TileOut {
    let (x1, y1) = (
        (x0 + TILE).min(settings.width),
        (y0 + TILE).min(settings.height),
    );
    let slots = sensor.slots();
    let pixels = ((x1 - x0) * (y1 - y0)) as usize;
    let mut out = TileOut {
        means: Vec::with_capacity(pixels * slots),
        se: Vec::with_capacity(if SE { pixels * slots } else { 0 }),
        spp: Vec::with_capacity(pixels),
        counts: TileCounts::default(),
    };
    let mut sums = Sums::new(slots, SE);
    let pass = Pass::<N> {
        scene,
        settings,
        sensor,
        caustics,
        clamp: settings.path.clamp.unwrap_or(f32::INFINITY),
        radiance: match (dispersive, caustics.is_some()) {
            (true, true) => path::radiance::<N, true, true>,
            (true, false) => path::radiance::<N, true, false>,
            (false, true) => path::radiance::<N, false, true>,
            (false, false) => path::radiance::<N, false, false>,
        },
        progress,
    };
    // Adaptive: the pilot's accumulators, the slots it judges and the seed of its stream.
    let adaptive = settings.adaptive.map(|a| {
        let slots_judged = adaptive::target_slots(&a, sensor);
        (a, Sums::new(slots, true), slots_judged)
    });
    let pilot_seed = adaptive::pilot_seed(settings.seed);
    let mut adaptive = adaptive;
    for y in y0..y1 {
        for x in x0..x1 {
            let pixel = y as u64 * settings.width as u64 + x as u64;
            let n = match &mut adaptive {
                None => settings.spp,
                Some((a, pilot, judged)) => {
                    pilot.clear();
                    let mut ps = PixelSampler::new(settings.sampler, pilot_seed, pixel);
                    pass.take::<true>(x, y, &mut ps, a.min, pilot, &mut out.counts);
                    let (s, q) = (&pilot.acc, &pilot.acc2);
                    adaptive::count(a, settings.sampler, a.min, s, q, judged)
                }
            };
            sums.clear();
            let mut sampler = PixelSampler::new(settings.sampler, settings.seed, pixel);
            pass.take::<SE>(x, y, &mut sampler, n, &mut sums, &mut out.counts);
            finish_pixel::<SE>(&sums, n, &mut out);
        }
    }
    out
}
