//! A scene's index of refraction (`config::IorConfig`) resolved into an `Ior` checked over the
//! render's wavelength range (finite and > 0 everywhere).

use super::spectrum::{Context, Role};
use crate::config::{IorConfig, IorForm, SpectrumConfig, MAX_IOR, MIN_IOR};
use crate::error::InputError;
use crate::spectrum::Ior;

impl IorConfig {
    /// Resolves to an `Ior` that is finite and > 0 over `ctx.range`.
    pub fn resolve(&self, ctx: &Context) -> Result<Ior, InputError> {
        let err = |m: String| {
            InputError::new(ctx.file, m)
                .field(ctx.field)
                .hint("an index of refraction is a number in [0.01, 100], a name (\"bk7\") or Glass(\"…\") (scenes/README.md)")
        };
        let ior = match self {
            IorConfig::Value(v) | IorConfig::Form(IorForm::Value(v)) => Ior::Constant(*v),
            IorConfig::Name(name) | IorConfig::Form(IorForm::Named(name)) => Ior::named(name)
                .ok_or_else(|| {
                    err(format!("unknown index of refraction name \"{name}\"")).hint(format!(
                        "the named values (Mitsuba 3's) are: {}; dispersive glasses are written Glass(\"…\"): {}",
                        Ior::names().join(", "),
                        Ior::glass_names().join(", ")
                    ))
                })?,
            IorConfig::Form(IorForm::Glass(name)) => Ior::glass(name).ok_or_else(|| {
                err(format!("unknown glass \"{name}\"")).hint(format!(
                    "the glasses (spectra/glasses.txt) are: {}; constant named values are written Named(\"…\")",
                    Ior::glass_names().join(", ")
                ))
            })?,
            IorConfig::Form(IorForm::Sellmeier { b, c }) => {
                if b.iter().chain(c).any(|v| !v.is_finite()) {
                    return Err(err(format!(
                        "Sellmeier coefficients b {b:?}, c {c:?} must be finite"
                    )));
                }
                Ior::Sellmeier { b: *b, c: *c }
            }
            IorConfig::Form(IorForm::Cauchy { a, b }) => {
                if !(a.is_finite() && b.is_finite()) {
                    return Err(err(format!(
                        "Cauchy coefficients a = {a}, b = {b} must be finite"
                    )));
                }
                Ior::Cauchy { a: *a, b: *b }
            }
            IorConfig::Form(IorForm::Spectrum(s)) => {
                if matches!(
                    s,
                    SpectrumConfig::Rgb(..)
                        | SpectrumConfig::ColourSpace(..)
                        | SpectrumConfig::Named(_)
                        | SpectrumConfig::Blackbody(_)
                ) {
                    return Err(err("an index of refraction cannot be an RGB colour, an illuminant or a blackbody".into())
                        .hint("write Spectrum(Tabulated([(nm, n), ...])), Spectrum(File(path: ...)) or Spectrum(Constant(n))"));
                }
                // Emission's checks (finite, ≥ 0) apply; > 0 is checked below.
                let mut notes = Vec::new();
                Ior::Curve(s.resolve(Role::Emission, ctx, &mut notes)?)
            }
        };
        let (lo, hi) = ctx.range;
        let (min, max) = ior.min_max(lo, hi);
        // The hint fits the form written: a constant has neither poles nor a range to cover.
        let constant = matches!(ior, Ior::Constant(_));
        if !(min.is_finite() && max.is_finite()) {
            if constant {
                return Err(err(format!(
                    "the index of refraction {min} is not a finite number"
                ))
                .hint("write a number > 0, e.g. 1.5 (glass) or 1.33 (water)"));
            }
            let hint = match self {
                IorConfig::Form(IorForm::Sellmeier { .. }) => "a Sellmeier cᵢ equal to some λ² (in µm²) inside the range makes a pole; check the coefficients' units",
                _ => "check the coefficients or values (λ in µm for Cauchy)",
            };
            return Err(err(format!(
                "the index of refraction is not a finite number somewhere in {lo}–{hi} nm"
            ))
            .hint(hint));
        }
        if min <= 0.0 {
            if constant {
                return Err(err(format!("an index of refraction must be > 0, not {min}"))
                    .hint("write a number > 0, e.g. 1.5 (glass) or 1.33 (water); a medium outside the object is set with ext_ior"));
            }
            let hint = match self {
                IorConfig::Form(IorForm::Spectrum(_)) => "a tabulated index must cover the whole spectral range (it is 0 outside its data)",
                IorConfig::Form(IorForm::Cauchy { .. }) => "n = a + b/λ² (λ in µm) must stay > 0: a is about 1.3–1.9 for glasses",
                _ => "check the coefficients (λ in µm, c in µm²)",
            };
            return Err(err(format!(
                "an index of refraction must be > 0, but this one reaches {min} in {lo}–{hi} nm"
            ))
            .hint(hint));
        }
        // Beyond these, ratios of two indices and their squares leave f32's range (an index of
        // 1e-45 made the relative index infinite and the refracted ray NaN); real dielectrics
        // lie within about 1–4.
        if min < MIN_IOR || max > MAX_IOR {
            let v = if min < MIN_IOR { min } else { max };
            let at = if constant {
                String::new()
            } else {
                format!(" (reached in {lo}–{hi} nm)")
            };
            return Err(err(format!(
                "the index of refraction {v}{at} is outside [{MIN_IOR}, {MAX_IOR}]"
            ))
            .hint("real dielectrics have indices of about 1–4, e.g. 1.5 (glass) or 1.33 (water)"));
        }
        Ok(ior)
    }
}
