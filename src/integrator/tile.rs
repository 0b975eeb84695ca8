//! One tile of the scalar loop: every pixel's samples in order, summed into per-slot
//! accumulators (with squares for the standard error and adaptive sampling's pilot), and the
//! accumulators the packet kernel's in-order flush shares with it.

use super::adaptive;
use super::caustics::Caustics;
use super::path;
use super::{RenderSettings, TILE};
use crate::sampler::PixelSampler;
use crate::scene::Scene;
use crate::sensor::Sensor;
use crate::spectrum::{Spectrum, Wavelengths};
use glam::Vec2;

/// Per-tile sample counts (pilot samples included).
#[derive(Clone, Copy, Default)]
pub(crate) struct TileCounts {
    pub(crate) samples: u64,
    pub(crate) invalid: u64,
    pub(crate) clamped: u64,
}

/// A tile's pixels, in its own row-major order: slot means, slot standard errors (with `SE`),
/// and each pixel's estimate's sample count.
pub(crate) struct TileOut {
    pub(crate) means: Vec<f32>,
    pub(crate) se: Vec<f32>,
    pub(crate) spp: Vec<u32>,
    pub(crate) counts: TileCounts,
}

/// One pixel's accumulators: per-slot sums, and with squares, each sample's own slot values
/// (`one`) and the sums of their squares.
pub(crate) struct Sums {
    pub(crate) acc: Vec<f64>,
    one: Vec<f64>,
    pub(crate) acc2: Vec<f64>,
}

impl Sums {
    pub(crate) fn new(slots: usize, squares: bool) -> Self {
        let n = if squares { slots } else { 0 };
        Sums {
            acc: vec![0.0; slots],
            one: vec![0.0; n],
            acc2: vec![0.0; n],
        }
    }

    pub(crate) fn clear(&mut self) {
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
    /// Samples `from..n` of pixel (x, y) from `sampler`, summed into `sums` (with `SQ`, their
    /// squares too: a second add into a scratch, so `acc` sums exactly as without them).
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn take<const SQ: bool>(
        &self,
        x: u32,
        y: u32,
        sampler: &mut PixelSampler,
        from: u32,
        n: u32,
        sums: &mut Sums,
        counts: &mut TileCounts,
    ) {
        let settings = self.settings;
        counts.samples += n.saturating_sub(from) as u64;
        // In runs of CHECK_EVERY samples, with the check between runs: no cost per sample.
        for run in (from..n).step_by(CHECK_EVERY as usize) {
            if run > from {
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
pub(crate) fn add_sample<const N: usize, const SQ: bool>(
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
pub(crate) fn finish_pixel<const SE: bool>(sums: &Sums, n: u32, out: &mut TileOut) {
    let inv_n = 1.0 / n as f64;
    out.means
        .extend(sums.acc.iter().map(|&a| (a * inv_n) as f32));
    out.spp.push(n);
    if SE {
        let n = n as f64;
        out.se.extend(
            sums.acc
                .iter()
                .zip(&sums.acc2)
                .map(|(&s, &q)| standard_error(s, q, n)),
        );
    }
}

/// `finish_pixel` into place `i` of `out`'s vectors, sized for the tile (the packet kernel's
/// lanes finish their pixels out of order).
#[inline(always)]
pub(crate) fn finish_pixel_at<const SE: bool>(sums: &Sums, n: u32, out: &mut TileOut, i: usize) {
    let slots = sums.acc.len();
    let inv_n = 1.0 / n as f64;
    let means = &mut out.means[i * slots..(i + 1) * slots];
    for (m, &a) in means.iter_mut().zip(&sums.acc) {
        *m = (a * inv_n) as f32;
    }
    out.spp[i] = n;
    if SE {
        let se = &mut out.se[i * slots..(i + 1) * slots];
        for ((e, &s), &q) in se.iter_mut().zip(&sums.acc).zip(&sums.acc2) {
            *e = standard_error(s, q, n as f64);
        }
    }
}

/// The standard error of a mean of `n` samples whose sum is `s` and sum of squares `q`: the
/// unbiased sample variance (invalid samples count as 0), / n.
#[inline(always)]
fn standard_error(s: f64, q: f64, n: f64) -> f32 {
    let var = if n > 1.0 {
        ((q - s * s / n) / (n - 1.0)).max(0.0)
    } else {
        0.0
    };
    (var / n).sqrt() as f32
}

/// `dispersive`: some material of the scene samples directions by wavelength (see
/// `path::radiance`).
pub(crate) fn render_tile<const N: usize, const SE: bool>(
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
    if let Some(a) = &settings.adaptive {
        adaptive_tile::<N, SE>(&pass, a, (x0, y0, x1, y1), &mut out);
        return out;
    }
    for y in y0..y1 {
        for x in x0..x1 {
            let pixel = y as u64 * settings.width as u64 + x as u64;
            sums.clear();
            let mut sampler = PixelSampler::new(settings.sampler, settings.seed, pixel);
            let n = settings.spp;
            pass.take::<SE>(x, y, &mut sampler, 0, n, &mut sums, &mut out.counts);
            finish_pixel::<SE>(&sums, n, &mut out);
        }
    }
    out
}

/// A tile under adaptive sampling (`adaptive` says why this order is unbiased): every pixel's
/// first `min` samples (its pilot, kept), then each pixel's count from its neighbours' pilots
/// in the tile and the samples up to it.
fn adaptive_tile<const N: usize, const SE: bool>(
    pass: &Pass<N>,
    a: &adaptive::AdaptiveSpp,
    (x0, y0, x1, y1): (u32, u32, u32, u32),
    out: &mut TileOut,
) {
    let settings = pass.settings;
    let (tw, th) = (x1 - x0, y1 - y0);
    let judged = adaptive::target_slots(a, pass.sensor);
    let at = |i: usize| (x0 + i as u32 % tw, y0 + i as u32 / tw);
    let stream = |seed: u64, (x, y): (u32, u32)| {
        let pixel = y as u64 * settings.width as u64 + x as u64;
        PixelSampler::new(settings.sampler, seed, pixel)
    };
    let sampler_of = |xy| stream(settings.seed, xy);
    let mut sums: Vec<Sums> = (0..tw * th)
        .map(|_| Sums::new(pass.sensor.slots(), true))
        .collect();
    for (i, s) in sums.iter_mut().enumerate() {
        let (x, y) = at(i);
        pass.take::<true>(x, y, &mut sampler_of((x, y)), 0, a.min, s, &mut out.counts);
    }
    let pilots: Vec<adaptive::Pilot> = sums
        .iter()
        .map(|s| adaptive::Pilot::of(a.min, &s.acc, &s.acc2, &judged))
        .collect();
    let counts = adaptive::counts(a, settings.sampler, &pilots, (tw, th));
    for (i, s) in sums.iter_mut().enumerate() {
        let (x, y) = at(i);
        let n = match counts[i] {
            Some(n) => n,
            // A lone pixel (a 1×1 tile): a pilot of its own from a stream of its own,
            // discarded.
            None => {
                let mut own = Sums::new(pass.sensor.slots(), true);
                let mut ps = stream(adaptive::pilot_seed(settings.seed), (x, y));
                pass.take::<true>(x, y, &mut ps, 0, a.min, &mut own, &mut out.counts);
                adaptive::count(a, settings.sampler, a.min, &own.acc, &own.acc2, &judged)
            }
        };
        pass.take::<SE>(x, y, &mut sampler_of((x, y)), a.min, n, s, &mut out.counts);
        finish_pixel::<SE>(s, n, out);
    }
}
