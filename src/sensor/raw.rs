//! The raw sensor (`sensor.raw`): what the chip records, one value per pixel in DN (`raw.Y`,
//! uint32), from the camera curve of the pixel's Bayer site.
//!
//! The model (as ISETCam's sensor pipeline, Farrell, Xiao & Wandell, "A simulation tool for
//! evaluating digital camera image quality", Proc. SPIE 5294 (2004), and EMVA 1288's linear
//! camera model; pbrt-v4's `PixelSensor` takes the same thin-lens exposure):
//!
//! 1. Photo-electrons of channel c at a pixel (mean): the thin lens on axis puts irradiance
//!    E(λ) = L(λ) · π / (4 N²) on the chip (camera.rs); a photon carries h c / λ, so
//!
//!    S_c = t · A · π / (4 N²) · (η / ĉ) · ∫ L(λ) c̄(λ) λ dλ / (h c)
//!
//!    with L in W m⁻² sr⁻¹ nm⁻¹, λ in m inside the integral, t the shutter time (s), N the
//!    f-number (`camera.exposure`), A = pitch² the pixel area (m²), c̄ the camera curve, ĉ the
//!    peak of the three curves and η the peak quantum efficiency (the measured curves are
//!    relative; η c̄/ĉ is the channel's quantum efficiency, colour filter included). The
//!    integral is three extra accumulator slots (curve c̄(λ)·λ), only when `raw` is given.
//! 2. Collected charge: e = min(Poisson(S_c + D), full well), D = dark current · t (shot noise
//!    and dark shot noise in one draw: a sum of independent Poisson counts is Poisson).
//! 3. Read-out: DN = round(g · (e + σ_r · n) + black), n ~ N(0, 1), clamped to [0, 2^bits − 1];
//!    g is the gain (DN/e⁻), σ_r the read noise (e⁻ rms).
//!
//! Unclipped, mean DN = g (S + D) + black and var DN = g² (S + D + σ_r²) + 1/12 (the last term
//! is rounding's, for a spread wider than one DN). With `noise: false` the draws are skipped
//! (e = min(S + D, full well), n = 0). The draws of pixel i come from ChaCha8 keyed by the
//! render seed with stream i (a counter-based generator): the same bits at any thread count or
//! tiling. It runs once on the finished film. The loader (`load::sensor::raw`) builds the model from
//! the scene's `raw:` config; this module knows no config.

use super::noise;
use crate::film::UintChannel;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// The EXR channel of the mosaic.
pub const CHANNEL: &str = "raw.Y";

/// Poisson means above this are saturated outright (far above any full well, and where a
/// count would lose integer precision in f64).
const SATURATED: f64 = 1e15;

/// The colour of the 2×2 Bayer tile's four sites, read left to right, top row first, from the
/// image's top-left pixel (row 0 at the top).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum BayerPattern {
    #[default]
    Rggb,
    Bggr,
    Grbg,
    Gbrg,
}

impl BayerPattern {
    pub const ALL: [BayerPattern; 4] = [
        BayerPattern::Rggb,
        BayerPattern::Bggr,
        BayerPattern::Grbg,
        BayerPattern::Gbrg,
    ];

    /// The camera channel (0 = R, 1 = G, 2 = B) of pixel (x, y).
    pub fn channel(self, x: u32, y: u32) -> usize {
        let tile: [usize; 4] = match self {
            BayerPattern::Rggb => [0, 1, 1, 2],
            BayerPattern::Bggr => [2, 1, 1, 0],
            BayerPattern::Grbg => [1, 0, 2, 1],
            BayerPattern::Gbrg => [1, 2, 0, 1],
        };
        tile[((y & 1) * 2 + (x & 1)) as usize]
    }
}

/// The conversion gain, DN per photo-electron: `PerElectron(g)`, or `UnityIso(u)`: g = ISO / u
/// with the ISO of `camera.exposure` (u is the ISO at which one electron is one DN).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Gain {
    PerElectron(f64),
    UnityIso(f64),
}

/// A raw sensor ready to read out a film.
#[derive(Clone, Debug, PartialEq)]
pub struct RawModel {
    pub pattern: BayerPattern,
    /// Accumulator slot of the first of the three photo-electron means (R, G, B).
    pub slot: usize,
    /// Mean dark electrons over the exposure.
    pub dark_e: f64,
    pub full_well: f64,
    pub read_noise: f64,
    /// DN per electron.
    pub gain: f64,
    pub black: f64,
    /// 2^bits − 1.
    pub white: f64,
    pub noise: bool,
}

impl RawModel {
    /// The DN of one pixel with mean signal `signal` e⁻ (step 2 and 3 of the module docs).
    pub fn read_out(&self, signal: f64, rng: Option<&mut ChaCha8Rng>) -> u32 {
        // NaN (an invalid pixel) reads as no signal; +inf saturates.
        let mean = signal.max(0.0) + self.dark_e;
        let (e, read) = match rng {
            None => (mean.min(self.full_well), 0.0),
            Some(r) => {
                let e = if mean >= SATURATED {
                    self.full_well
                } else if mean > 0.0 {
                    noise::poisson(mean, r).min(self.full_well)
                } else {
                    0.0
                };
                let n = noise::standard_normal(r);
                (e, self.read_noise * n)
            }
        };
        (self.gain * (e + read) + self.black)
            .round()
            .clamp(0.0, self.white) as u32
    }

    /// The mosaic of a `width`×`height` film from its accumulator means (`slots` per pixel),
    /// with noise drawn from (`seed`, pixel).
    pub fn mosaic(
        &self,
        means: &[f32],
        slots: usize,
        width: u32,
        height: u32,
        seed: u64,
    ) -> UintChannel {
        let n = width as usize * height as usize;
        let key = ChaCha8Rng::seed_from_u64(crate::math::rng::hash3(seed, 0x7a3_5e75, 0));
        let data = (0..n)
            .into_par_iter()
            .with_min_len(1024)
            .map(|i| {
                let (x, y) = ((i % width as usize) as u32, (i / width as usize) as u32);
                let c = self.pattern.channel(x, y);
                let signal = means[i * slots + self.slot + c] as f64;
                if self.noise {
                    let mut r = key.clone();
                    r.set_stream(i as u64);
                    self.read_out(signal, Some(&mut r))
                } else {
                    self.read_out(signal, None)
                }
            })
            .collect();
        UintChannel {
            name: CHANNEL.into(),
            data,
        }
    }
}

/// The pattern's name as the EXR header and the sidecar write it.
pub fn pattern_name(p: BayerPattern) -> &'static str {
    match p {
        BayerPattern::Rggb => "RGGB",
        BayerPattern::Bggr => "BGGR",
        BayerPattern::Grbg => "GRBG",
        BayerPattern::Gbrg => "GBRG",
    }
}

#[cfg(test)]
#[path = "raw_tests.rs"]
mod tests;
