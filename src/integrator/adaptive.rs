//! Adaptive sampling: how many samples a pixel's estimate takes.
//!
//! The stopping rule keeps the estimate unbiased. A pilot batch of `min` samples, drawn from a
//! stream of its own (`pilot_seed`), measures the pixel's variance and is then discarded; the
//! count n it gives sets how many samples of the pixel's ordinary stream (the very samples a
//! fixed-spp render of n would take) are averaged. Those samples are independent of the pilot,
//! so E[estimate | n] is the pixel's value for every n, and so is E[estimate]. Averaging the
//! pilot in, or stopping when the running error is small, would not be: the count would then
//! depend on the samples it averages (tested in `tests/adaptive.rs`).

use crate::math::rng::hash3;
use crate::sampler::SamplerKind;
use crate::sensor::{Sensor, XYZ_SLOTS};
use serde::{Deserialize, Serialize};

/// Render each pixel until the standard error of its estimate is below `rel_error` of its
/// value: a pilot batch of `min` samples (from a stream of its own, then discarded) gives the
/// pixel's variance, which sets the count n of a fresh batch that alone is the estimate, so the
/// count never depends on the samples it averages (unbiased; `integrator::adaptive`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AdaptiveSpp {
    /// Target standard error over value, e.g. 0.01.
    pub rel_error: f32,
    /// Pilot samples per pixel (at least 2), and the fewest the estimate takes.
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

/// The estimate's sample count from the pilot's per-slot sums and sums of squares over `n`
/// samples: the least count whose standard error √(s²/count) is within rel_error of every
/// target slot's mean (means below `floor` count as `floor`), clamped to [min, max]. With the
/// Sobol sampler it is rounded up to a power of two (at most `max`): Sobol points are best
/// stratified in such blocks.
pub fn count(
    a: &AdaptiveSpp,
    kind: SamplerKind,
    n: u32,
    sums: &[f64],
    squares: &[f64],
    slots: &[usize],
) -> u32 {
    let nf = n as f64;
    let rel = a.rel_error as f64;
    let mut need = 0.0f64;
    for &k in slots {
        let mean = sums[k] / nf;
        let var = ((squares[k] - sums[k] * sums[k] / nf) / (nf - 1.0)).max(0.0);
        let tol = rel * mean.abs().max(a.floor as f64);
        need = need.max(var / (tol * tol));
    }
    // `need` is NaN or infinite only if the sums overflowed: then the most samples.
    let c = if need.is_finite() {
        need.ceil().clamp(a.min as f64, a.max as f64) as u32
    } else {
        a.max
    };
    match kind {
        SamplerKind::Sobol => c.next_power_of_two().min(a.max),
        SamplerKind::Independent => c,
    }
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
