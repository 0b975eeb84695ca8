//! Adaptive sampling: how many samples a pixel's estimate takes.
//!
//! The stopping rule keeps the estimate unbiased, and wastes no sample. Every pixel of a tile
//! first takes the first `min` samples of its ordinary stream (its pilot); then each pixel's
//! count n comes from the pilots of its neighbours in the tile (the 3×3 block less the pixel
//! itself: the largest count any of them asks for), never from its own, and the pixel
//! takes samples `min..n` of its stream. Its estimate is the mean of its first n samples,
//! pilot included, the very samples a fixed-spp render of n averages (bit for bit), and n does
//! not depend on any of them, so E[estimate | n] is the pixel's value for every n, and so is
//! E[estimate]. Letting a pixel's own pilot set its count, or stopping when its running error
//! is small, would not be: the count would then depend on the samples it averages (tested in
//! `tests/adaptive.rs`). A pixel with no neighbour in its tile (a 1×1 tile) draws a pilot from
//! a stream of its own (`pilot_seed`) and discards it.
//!
//! Why neighbours: the earlier rule (each pixel's own pilot from a separate stream, discarded)
//! spent 35% of the materials benchmark's samples at `--rel-error 0.2` on pilots no estimate
//! used (docs/performance.md). The largest of the neighbours' counts rather than one from
//! their pooled mean and variance: on that scene the pooled count under-sampled sharp
//! caustics (time to equal error 2.39× Mitsuba's best against 2.08×; 3.16× before).

use crate::math::rng::hash3;
use crate::sampler::SamplerKind;
use crate::sensor::{Sensor, XYZ_SLOTS};
use serde::{Deserialize, Serialize};

/// Render each pixel until the standard error of its estimate is below `rel_error` of its
/// value: every pixel's first `min` samples (its pilot, kept in its estimate) set its
/// neighbours' counts, never its own, so no count depends on the samples it averages
/// (unbiased; `integrator::adaptive`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AdaptiveSpp {
    /// Target standard error over value, e.g. 0.01.
    pub rel_error: f32,
    /// Pilot samples per pixel (at least 2, kept in its estimate), and the fewest it takes.
    pub min: u32,
    /// The most samples the estimate takes.
    pub max: u32,
    /// Which estimates must meet the target: `Y` (default) or every spectral band (`Bands`).
    #[serde(default)]
    pub target: ErrorTarget,
    /// Values below this count as this when the relative error is formed (radiance units,
    /// default 0.001), so near-black pixels stop at an absolute error of rel_error × floor
    /// instead of running to `max`.
    #[serde(default = "default_floor")]
    pub floor: f32,
}

fn default_floor() -> f32 {
    1e-3
}

/// What `Adaptive` measures the error of.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum ErrorTarget {
    /// The luminance Y.
    #[default]
    Y,
    /// Every spectral band of the sensor (the worst one decides).
    Bands,
}

/// The seed of every pixel's pilot stream: a hash of the render seed, so that no pilot sample
/// is a sample of any pixel's ordinary stream.
pub fn pilot_seed(seed: u64) -> u64 {
    hash3(seed, 0xada9_71fe, 0x9170)
}

/// The accumulator slots whose error must meet the target: Y, or every band.
pub fn target_slots(a: &AdaptiveSpp, sensor: &Sensor) -> Vec<usize> {
    match (a.target, sensor.bands()) {
        (ErrorTarget::Bands, Some(b)) => (XYZ_SLOTS..XYZ_SLOTS + b.count as usize).collect(),
        // The loader refuses `Bands` without bands.
        _ => vec![1],
    }
}

/// One pixel's pilot, per judged slot: the mean and the unbiased sample variance.
pub struct Pilot {
    slots: Vec<(f64, f64)>,
}

impl Pilot {
    /// From per-slot sums and sums of squares over `n` samples, at the judged `slots`.
    pub fn of(n: u32, sums: &[f64], squares: &[f64], slots: &[usize]) -> Pilot {
        let nf = n as f64;
        let slots = slots
            .iter()
            .map(|&k| {
                let mean = sums[k] / nf;
                let var = ((squares[k] - sums[k] * sums[k] / nf) / (nf - 1.0)).max(0.0);
                (mean, var)
            })
            .collect();
        Pilot { slots }
    }
}

/// The pixels of the 3×3 block around (x, y) in a w × h tile, (x, y) itself left out.
pub fn neighbours(x: u32, y: u32, w: u32, h: u32) -> impl Iterator<Item = (u32, u32)> {
    let (x, y) = (x as i64, y as i64);
    (-1..=1i64)
        .flat_map(move |dy| (-1..=1i64).map(move |dx| (x + dx, y + dy)))
        .filter(move |&(nx, ny)| {
            (nx, ny) != (x, y) && (0..w as i64).contains(&nx) && (0..h as i64).contains(&ny)
        })
        .map(|(nx, ny)| (nx as u32, ny as u32))
}

/// The estimate's sample count from `pilots` (None if there are none): the least count whose
/// standard error √(s²/count) is within rel_error of every target slot's mean, for the s² and
/// mean of every pilot (means below `floor` count as `floor`), clamped to [min, max]. With the
/// Sobol sampler it is rounded up to a power of two (at most `max`): Sobol points are best
/// stratified in such blocks.
pub fn count_from<'a>(
    a: &AdaptiveSpp,
    kind: SamplerKind,
    pilots: impl Iterator<Item = &'a Pilot>,
) -> Option<u32> {
    let rel = a.rel_error as f64;
    let mut need: Option<f64> = None;
    for p in pilots {
        for &(mean, var) in &p.slots {
            let tol = rel * mean.abs().max(a.floor as f64);
            // `max` keeps a NaN need out unless every one is NaN (then `is_finite` catches it).
            need = Some(need.map_or(var / (tol * tol), |n| n.max(var / (tol * tol))));
        }
    }
    let need = need?;
    // `need` is NaN or infinite only if the sums overflowed: then the most samples.
    let c = if need.is_finite() {
        need.ceil().clamp(a.min as f64, a.max as f64) as u32
    } else {
        a.max
    };
    Some(match kind {
        SamplerKind::Sobol => c.next_power_of_two().min(a.max),
        SamplerKind::Independent => c,
    })
}

/// Each pixel's count from its neighbours' pilots in a `tw` × `th` tile; None for a pixel
/// with no neighbour (a 1×1 tile), whose count needs a pilot of its own.
pub fn counts(
    a: &AdaptiveSpp,
    kind: SamplerKind,
    pilots: &[Pilot],
    (tw, th): (u32, u32),
) -> Vec<Option<u32>> {
    (0..tw * th)
        .map(|i| {
            let (cx, cy) = (i % tw, i / tw);
            let near = neighbours(cx, cy, tw, th).map(|(nx, ny)| &pilots[(ny * tw + nx) as usize]);
            count_from(a, kind, near)
        })
        .collect()
}

/// `count_from` one pilot of `n` samples given by its per-slot sums and sums of squares.
pub fn count(
    a: &AdaptiveSpp,
    kind: SamplerKind,
    n: u32,
    sums: &[f64],
    squares: &[f64],
    slots: &[usize],
) -> u32 {
    let p = Pilot::of(n, sums, squares, slots);
    count_from(a, kind, std::iter::once(&p)).unwrap_or(a.max)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spp(min: u32, max: u32) -> AdaptiveSpp {
        AdaptiveSpp {
            rel_error: 0.1,
            min,
            max,
            target: ErrorTarget::Y,
            floor: 1e-3,
        }
    }

    /// Samples 0, 2, 0, 2 (mean 1, s² = 4/3): SE = √(4/3 / c) ≤ 0.1 needs c ≥ 133.3.
    #[test]
    fn count_meets_the_target() {
        let (s, q) = ([0.0, 4.0, 0.0], [0.0, 8.0, 0.0]);
        let c = |kind, max| count(&spp(4, max), kind, 4, &s, &q, &[1]);
        assert_eq!(c(SamplerKind::Independent, 4096), 134);
        assert_eq!(c(SamplerKind::Sobol, 4096), 256);
        assert_eq!(c(SamplerKind::Sobol, 200), 200);
        assert_eq!(c(SamplerKind::Independent, 100), 100);
        // No spread: the fewest.
        let flat = count(
            &spp(4, 64),
            SamplerKind::Independent,
            4,
            &s,
            &[0.0, 4.0, 0.0],
            &[1],
        );
        assert_eq!(flat, 4);
        // A black pixel with a little noise is held to the floor's absolute error.
        let dark = count(
            &spp(4, 1 << 20),
            SamplerKind::Independent,
            4,
            &[0.0; 3],
            &[0.0, 4e-6, 0.0],
            &[1],
        );
        assert_eq!(dark, (4e-6f64 / 3.0 / 1e-8).ceil() as u32);
    }

    #[test]
    fn pilot_stream_differs_from_the_render_seed() {
        assert_ne!(pilot_seed(0), 0);
        assert_ne!(pilot_seed(1), pilot_seed(0));
    }
}
