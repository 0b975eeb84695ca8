//! The raw sensor's setup: a scene's `raw:` config (and the camera's exposure) checked and
//! turned into the read-out model of `sensor::raw` (its module docs give the model).

use crate::config::sensor::{ExposureConfig, Gain, RawConfig};
use crate::error::InputError;
use crate::sensor::bands::{Response, Shape};
use crate::sensor::raw::{pattern_name, RawModel, CHANNEL};
use crate::spectrum::Curve;

/// h · c (J m), exact in the SI.
const H_C: f64 = 6.626_070_15e-34 * 299_792_458.0;

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
