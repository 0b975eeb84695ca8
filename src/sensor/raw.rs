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
//! tiling. It runs once on the finished film.

use super::bands::{Response, Shape};
use crate::config::sensor::{BayerPattern, ExposureConfig, Gain, RawConfig};
use crate::error::InputError;
use crate::film::UintChannel;
use crate::spectrum::Curve;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Poisson, StandardNormal};
use rayon::prelude::*;

/// The EXR channel of the mosaic.
pub const CHANNEL: &str = "raw.Y";

/// h · c (J m), exact in the SI.
const H_C: f64 = 6.626_070_15e-34 * 299_792_458.0;

/// Poisson means above this are saturated outright (far above any full well; rand_distr
/// refuses means near 2^64).
const SATURATED: f64 = 1e15;

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
                    let p = Poisson::new(mean).expect("a finite positive mean");
                    p.sample(r).min(self.full_well)
                } else {
                    0.0
                };
                let n: f64 = StandardNormal.sample(r);
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
fn pattern_name(p: BayerPattern) -> &'static str {
    match p {
        BayerPattern::Rggb => "RGGB",
        BayerPattern::Bggr => "BGGR",
        BayerPattern::Grbg => "GRBG",
        BayerPattern::Gbrg => "GBRG",
    }
}

/// What `build` makes of a `raw` config.
pub struct RawSetup {
    /// The model, its `slot` still to be set.
    pub model: RawModel,
    /// The three photo-electron responses (R, G, B), appended after the camera's.
    pub photons: [Response; 3],
    /// EXR header attributes (`prism:raw.*`).
    pub header: Vec<(String, String)>,
}

/// Checks `cfg` and builds the model, the photo-electron responses for the camera's `curves`
/// and the header attributes. `err(field, message, fix)` makes the error for a field of `raw`.
pub fn build(
    cfg: &RawConfig,
    curves: &[Curve; 3],
    exposure: Option<ExposureConfig>,
    range: (f32, f32),
    err: &dyn Fn(&str, String, &str) -> InputError,
) -> Result<RawSetup, InputError> {
    let Some(exp) = exposure else {
        return Err(err(
            "",
            "the raw sensor needs the camera's exposure (shutter time and f-number)".into(),
            "add camera.exposure, e.g. exposure: (iso: 100, shutter: 0.01, f_number: 4)",
        ));
    };
    let positive = |v: f64, field: &str, what: &str, max: f64| -> Result<(), InputError> {
        if v.is_finite() && v > 0.0 && v <= max {
            Ok(())
        } else {
            Err(err(
                field,
                format!("{field} is {v}; it must be a positive {what} (at most {max:e})"),
                "configs/README.md lists the raw sensor's fields and typical values",
            ))
        }
    };
    let non_negative = |v: f64, field: &str, what: &str| -> Result<(), InputError> {
        if v.is_finite() && v >= 0.0 {
            Ok(())
        } else {
            Err(err(
                field,
                format!("{field} is {v}; it must be a non-negative {what}"),
                "write 0 for none; configs/README.md lists typical values",
            ))
        }
    };
    positive(cfg.pixel_pitch, "pixel_pitch", "pixel pitch in µm", 1e4)?;
    positive(
        cfg.quantum_efficiency,
        "quantum_efficiency",
        "quantum efficiency",
        1.0,
    )?;
    positive(cfg.full_well, "full_well", "capacity in electrons", 1e12)?;
    non_negative(cfg.read_noise, "read_noise", "read noise in e⁻ rms")?;
    non_negative(cfg.dark_current, "dark_current", "dark current in e⁻/s")?;
    let gain = match cfg.gain {
        Gain::PerElectron(g) => {
            positive(g, "gain", "number of DN per electron", 1e9)?;
            g
        }
        Gain::UnityIso(u) => {
            positive(u, "gain", "unity-gain ISO", 1e9)?;
            exp.iso as f64 / u
        }
    };
    if !(1..=32).contains(&cfg.bits) {
        return Err(err(
            "bits",
            format!("bits is {}; the DN are 1 to 32 bits deep", cfg.bits),
            "write the ADC's bit depth, e.g. bits: 12 or bits: 14",
        ));
    }
    let white = ((1u64 << cfg.bits) - 1) as f64;
    non_negative(cfg.black_level, "black_level", "number of DN")?;
    if cfg.black_level >= white {
        return Err(err(
            "black_level",
            format!(
                "black_level {} leaves no room below the {}-bit white level {white}",
                cfg.black_level, cfg.bits
            ),
            "lower black_level or raise bits",
        ));
    }
    // The curves' common peak ĉ, on a 0.25 nm grid over the visible and NIR and the range.
    let (lo, hi) = (range.0.min(300.0), range.1.max(1100.0));
    let steps = ((hi - lo) * 4.0) as usize;
    let peak = (0..=steps)
        .map(|k| lo + k as f32 * 0.25)
        .flat_map(|l| curves.iter().map(move |c| c.eval_one(l)))
        .fold(0.0f32, f32::max) as f64;
    if !(peak.is_finite() && peak > 0.0) {
        return Err(err(
            "",
            "the camera's curves are zero everywhere".into(),
            "give camera curves that respond somewhere in the spectral range",
        ));
    }
    let (t, f_number) = (exp.shutter as f64, exp.f_number as f64);
    let area = (cfg.pixel_pitch * 1e-6).powi(2);
    // e⁻ per unit of ∫ L c̄ λ dλ with λ in nm (hence 1e-9), module docs step 1.
    let scale = t * area * std::f64::consts::PI / (4.0 * f_number * f_number)
        * (cfg.quantum_efficiency / peak)
        * 1e-9
        / H_C;
    // The product of valid inputs can still leave f32 (f_number 1e-21: an infinite scale):
    // the electrons per unit signal must be a normal f32 with room for any plausible radiance.
    if !(1e-25..=1e25).contains(&scale) {
        return Err(err(
            "",
            format!("the electron scale shutter · pixel area · π / (4 · f_number²) · QE / peak / (h c) is {scale:e} e⁻ per unit signal; it must lie in [1e-25, 1e25]"),
            "check camera.exposure (shutter, f_number) and raw.pixel_pitch",
        ));
    }
    let dark_e = cfg.dark_current * t;
    if !dark_e.is_finite() {
        return Err(err(
            "dark_current",
            format!("dark_current · shutter is {dark_e:e} electrons"),
            "write a dark current in e⁻/s, e.g. dark_current: 0.1",
        ));
    }
    if !(gain.is_finite() && gain <= 1e9) {
        return Err(err(
            "gain",
            format!(
                "the gain iso / unity-gain ISO is {gain:e} DN per electron; it must be at most 1e9"
            ),
            "raise the unity-gain ISO or give gain: PerElectron(...)",
        ));
    }
    let responses = curves.clone().map(|c| Response {
        shape: Shape::Photons(c),
        scale: scale as f32,
    });
    let model = RawModel {
        pattern: cfg.pattern,
        slot: 0,
        dark_e,
        full_well: cfg.full_well,
        read_noise: cfg.read_noise,
        gain,
        black: cfg.black_level,
        white,
        noise: cfg.noise,
    };
    let header = [
        ("channel", CHANNEL.to_string()),
        ("pattern", pattern_name(cfg.pattern).to_string()),
        ("pixelPitch", format!("{:e}", cfg.pixel_pitch)),
        ("quantumEfficiency", format!("{:e}", cfg.quantum_efficiency)),
        ("fullWell", format!("{:e}", cfg.full_well)),
        ("readNoise", format!("{:e}", cfg.read_noise)),
        ("darkCurrent", format!("{:e}", cfg.dark_current)),
        ("darkElectrons", format!("{:e}", model.dark_e)),
        ("gain", format!("{gain:e}")),
        ("blackLevel", format!("{:e}", cfg.black_level)),
        ("bits", cfg.bits.to_string()),
        ("whiteLevel", format!("{white:e}")),
        ("electronScale", format!("{scale:e}")),
        ("noise", cfg.noise.to_string()),
        ("units", "pixelPitch um; fullWell, readNoise (rms), darkElectrons e-; darkCurrent e-/s; gain DN/e-; blackLevel, whiteLevel DN; electronScale e- per W m^-2 sr^-1 nm^-1 x nm^2 (of the integral of L c lambda); noise seeded by the render seed".to_string()),
    ]
    .map(|(k, v)| (format!("prism:raw.{k}"), v))
    .to_vec();
    Ok(RawSetup {
        model,
        photons: responses,
        header,
    })
}

#[cfg(test)]
#[path = "raw_tests.rs"]
mod tests;
