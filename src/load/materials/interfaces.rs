//! The interfaces of conductors, dielectrics and plastics: their indices of refraction and
//! specular factors.

use crate::bsdf::ConductorParams;
use crate::config::{IorConfig, SpectrumConfig};
use crate::error::InputError;
use crate::load::{spectrum_ctx, Role};
use crate::spectrum::{metals, Curve, RelativeIor};
use crate::texture::SpectralTexture;
use std::path::Path;

/// A conductor's index of refraction (a named metal, explicit `eta` and `k`, or Mitsuba's
/// default: η = 0, κ = 1, a perfect mirror) and its specular factor.
#[allow(clippy::too_many_arguments)]
pub(super) fn conductor(
    material: Option<&str>,
    eta: Option<&SpectrumConfig>,
    k: Option<&SpectrumConfig>,
    specular: &SpectrumConfig,
    field: &str,
    file: &Path,
    range: (f32, f32),
    warnings: &mut Vec<String>,
) -> Result<ConductorParams, InputError> {
    let ctx = |sub: &str| format!("{field}.{sub}");
    // Mitsuba's `material: "none"` is its default, the mirror that eta = 0, k = 1 describe.
    let named = material.filter(|m| !m.eq_ignore_ascii_case("none"));
    let (eta, k) = match named {
        Some(name) => {
            if eta.is_some() || k.is_some() {
                return Err(InputError::new(
                    file,
                    format!("give either `material: \"{name}\"` or `eta` and `k`, not both"),
                )
                .field(field)
                .hint("drop `eta` and `k` to use the named metal's, or drop `material`"));
            }
            let (eta, k) = metals::named_metal(name).ok_or_else(|| {
                InputError::new(file, format!("unknown metal `{name}`"))
                    .field(ctx("material"))
                    .hint(format!(
                        "the named metals are: {}; or \"none\" for a perfect mirror",
                        metals::metal_names().join(", ")
                    ))
            })?;
            let (lo, hi) = range;
            if let Some((a, b)) = eta.support() {
                if a > lo || b < hi {
                    warnings.push(format!(
                        "{}: {}: the data for `{name}` cover {a}–{b} nm only; outside them its eta and k are 0 (a perfect mirror) in the render range {lo}–{hi} nm{}",
                        file.display(),
                        ctx("material"),
                        match metals::covering_alternatives(name, lo, hi).as_slice() {
                            [] => String::new(),
                            alt => format!("; {} cover the whole range", alt.join(", ")),
                        },
                    ));
                }
            }
            (eta, k)
        }
        None => {
            let part = |s: Option<&SpectrumConfig>, name: &str, default: f32, warnings: &mut _| {
                s.map_or(Ok(Curve::Constant(default)), |s| {
                    s.resolve(Role::Ior, &spectrum_ctx(file, &ctx(name), range), warnings)
                })
            };
            (
                part(eta, "eta", 0.0, warnings)?,
                part(k, "k", 1.0, warnings)?,
            )
        }
    };
    Ok(ConductorParams {
        eta,
        k,
        specular_reflectance: specular.resolve_texture(
            Role::Reflectance,
            &spectrum_ctx(file, &ctx("specular_reflectance"), range),
            warnings,
        )?,
    })
}

// Dielectrics.
/// n_int / n_ext of a dielectric, each checked over the render range.
pub(super) fn relative_ior(
    int: &IorConfig,
    ext: &IorConfig,
    field: &str,
    file: &Path,
    range: (f32, f32),
) -> Result<RelativeIor, InputError> {
    let int = int.resolve(&spectrum_ctx(file, &format!("{field}.int_ior"), range))?;
    let ext = ext.resolve(&spectrum_ctx(file, &format!("{field}.ext_ior"), range))?;
    Ok(RelativeIor::new(int, ext))
}

/// A dielectric's `specular_reflectance` and `specular_transmittance` (reflectances, in [0, 1]).
pub(super) fn specular(
    r: &SpectrumConfig,
    t: &SpectrumConfig,
    field: &str,
    file: &Path,
    range: (f32, f32),
    warnings: &mut Vec<String>,
) -> Result<(SpectralTexture, SpectralTexture), InputError> {
    let resolve = |s: &SpectrumConfig, name: &str, warnings: &mut Vec<String>| {
        s.resolve_texture(
            Role::Reflectance,
            &spectrum_ctx(file, &format!("{field}.{name}"), range),
            warnings,
        )
    };
    Ok((
        resolve(r, "specular_reflectance", warnings)?,
        resolve(t, "specular_transmittance", warnings)?,
    ))
}

// Plastics.
/// A plastic's relative index η = int / ext. Mitsuba's plastics take scalar indices, so a
/// dispersive one (a glass, Sellmeier, Cauchy, a varying table) is refused.
pub(super) fn plastic_eta(
    int: &IorConfig,
    ext: &IorConfig,
    field: &str,
    file: &Path,
    range: (f32, f32),
) -> Result<f32, InputError> {
    let one = |c: &IorConfig, name: &str| {
        let sub = format!("{field}.{name}");
        let ior = c.resolve(&spectrum_ctx(file, &sub, range))?;
        if !ior.is_constant() {
            return Err(InputError::new(
                file,
                format!("a plastic's {name} must be one number, but this index varies with wavelength"),
            )
            .field(sub)
            .hint("plastics (as Mitsuba's) take a constant index: write a number (1.5) or a name (\"bk7\", \"polypropylene\"); for dispersion use Dielectric or RoughDielectric"));
        }
        Ok(ior.eval_one(0.5 * (range.0 + range.1)))
    };
    Ok(one(int, "int_ior")? / one(ext, "ext_ior")?)
}

/// Mitsuba's share of samples for the specular lobe: mean(specular) / (mean(diffuse) + mean(specular)).
pub(super) fn specular_weight(
    diffuse: &SpectralTexture,
    specular: &SpectralTexture,
    (lo, hi): (f32, f32),
) -> f32 {
    let (d, s) = (diffuse.mean(lo, hi), specular.mean(lo, hi));
    if d + s > 0.0 {
        s / (d + s)
    } else {
        0.5
    }
}
