//! Materials from the config.

use crate::bsdf::microfacet::Microfacet;
use crate::bsdf::{fresnel, roughplastic, ConductorParams, Material, MAX_LOBES};
use crate::config::{
    spectrum::uv_map, spectrum_ctx, FloatConfig, FloatTextureConfig, IorConfig, MaterialConfig,
    Role, SpectrumConfig,
};
use crate::error::InputError;
use crate::spectrum::{metals, Curve, Ior, RelativeIor};
use crate::texture::{self, FloatTexture, SpectralTexture, TexelRange};
use std::path::Path;

/// Builds material `name`; its spectra are checked over the render's wavelength `range`.
pub fn material(
    name: &str,
    m: &MaterialConfig,
    file: &Path,
    range: (f32, f32),
    warnings: &mut Vec<String>,
) -> Result<Material, InputError> {
    let field = format!("materials.\"{name}\"");
    let mat = build(m, &field, file, range, warnings)?;
    if mat.max_lobes() > MAX_LOBES {
        return Err(InputError::new(file, format!("this material combines {} BSDFs; at most {MAX_LOBES} can be blended or masked together", mat.max_lobes()))
            .field(field)
            .hint("flatten nested Blend/Mask materials"));
    }
    Ok(mat)
}

fn build(
    m: &MaterialConfig,
    field: &str,
    file: &Path,
    range: (f32, f32),
    warnings: &mut Vec<String>,
) -> Result<Material, InputError> {
    let ctx = |sub: &str| format!("{field}.{sub}");
    Ok(match m {
        MaterialConfig::Diffuse { reflectance } => Material::Diffuse {
            reflectance: reflectance.resolve_texture(
                Role::Reflectance,
                &spectrum_ctx(file, &ctx("reflectance"), range),
                warnings,
            )?,
        },
        MaterialConfig::Twosided { bsdf, back } => {
            let front = build(bsdf, &ctx("bsdf"), file, range, warnings)?;
            let back = match back {
                Some(b) => build(b, &ctx("back"), file, range, warnings)?,
                None => front.clone(),
            };
            Material::Twosided {
                front: Box::new(front),
                back: Box::new(back),
            }
        }
        MaterialConfig::Blend {
            weight,
            bsdf0,
            bsdf1,
        } => Material::Blend {
            a: Box::new(build(bsdf0, &ctx("bsdf0"), file, range, warnings)?),
            b: Box::new(build(bsdf1, &ctx("bsdf1"), file, range, warnings)?),
            weight: float(weight, &ctx("weight"), file)?,
        },
        MaterialConfig::Mask { opacity, bsdf } => Material::Mask {
            inner: Box::new(build(bsdf, &ctx("bsdf"), file, range, warnings)?),
            opacity: float(opacity, &ctx("opacity"), file)?,
        },
        // Conductors.
        MaterialConfig::RoughConductor {
            distribution,
            alpha,
            alpha_u,
            alpha_v,
            material,
            eta,
            k,
            specular_reflectance,
        } => {
            let (alpha_u, alpha_v) = roughnesses(alpha, alpha_u, alpha_v, field, file)?;
            Material::RoughConductor {
                params: conductor(
                    material.as_deref(),
                    eta.as_ref(),
                    k.as_ref(),
                    specular_reflectance,
                    field,
                    file,
                    range,
                    warnings,
                )?,
                distribution: *distribution,
                alpha_u,
                alpha_v,
            }
        }
        MaterialConfig::Principled {
            base_color,
            metallic,
            roughness,
            ior,
            specular,
            specular_color,
            transmission,
        } => super::principled::from_config(
            super::principled::Config {
                base_color,
                metallic,
                roughness,
                ior: *ior,
                specular: *specular,
                specular_color,
                transmission,
            },
            field,
            file,
            range,
            warnings,
        )?,
        MaterialConfig::Conductor {
            material,
            eta,
            k,
            specular_reflectance,
        } => Material::Conductor(conductor(
            material.as_deref(),
            eta.as_ref(),
            k.as_ref(),
            specular_reflectance,
            field,
            file,
            range,
            warnings,
        )?),
        // Dielectrics.
        MaterialConfig::Dielectric {
            int_ior,
            ext_ior,
            specular_reflectance,
            specular_transmittance,
        } => {
            let (r, t) = specular(
                specular_reflectance,
                specular_transmittance,
                field,
                file,
                range,
                warnings,
            )?;
            Material::Dielectric {
                ior: relative_ior(int_ior, ext_ior, field, file, range)?,
                specular_reflectance: r,
                specular_transmittance: t,
            }
        }
        MaterialConfig::RoughDielectric {
            distribution,
            alpha,
            alpha_u,
            alpha_v,
            int_ior,
            ext_ior,
            specular_reflectance,
            specular_transmittance,
        } => {
            let ior = relative_ior(int_ior, ext_ior, field, file, range)?;
            if let (Ior::Constant(a), Ior::Constant(b)) = (&ior.int, &ior.ext) {
                if a == b {
                    return Err(InputError::new(file, format!("int_ior and ext_ior are both {a}: a rough interface needs different indices (as in Mitsuba)"))
                        .field(field)
                        .hint("an index-matched interface is invisible; leave the shape out, or use Mask(opacity: 0, ...)"));
                }
            }
            let (alpha_u, alpha_v) = roughnesses(alpha, alpha_u, alpha_v, field, file)?;
            let (r, t) = specular(
                specular_reflectance,
                specular_transmittance,
                field,
                file,
                range,
                warnings,
            )?;
            Material::RoughDielectric {
                ior,
                distribution: *distribution,
                alpha_u,
                alpha_v,
                specular_reflectance: r,
                specular_transmittance: t,
            }
        }
        MaterialConfig::ThinDielectric {
            int_ior,
            ext_ior,
            specular_reflectance,
            specular_transmittance,
        } => {
            let (r, t) = specular(
                specular_reflectance,
                specular_transmittance,
                field,
                file,
                range,
                warnings,
            )?;
            Material::ThinDielectric {
                ior: relative_ior(int_ior, ext_ior, field, file, range)?,
                specular_reflectance: r,
                specular_transmittance: t,
            }
        }
        // Plastics.
        MaterialConfig::Plastic {
            diffuse_reflectance,
            specular_reflectance,
            int_ior,
            ext_ior,
            nonlinear,
        } => {
            let eta = plastic_eta(int_ior, ext_ior, field, file, range)?;
            let diffuse = diffuse_reflectance.resolve_texture(
                Role::Reflectance,
                &spectrum_ctx(file, &ctx("diffuse_reflectance"), range),
                warnings,
            )?;
            let specular = specular_reflectance.resolve_texture(
                Role::Reflectance,
                &spectrum_ctx(file, &ctx("specular_reflectance"), range),
                warnings,
            )?;
            Material::Plastic {
                specular_weight: specular_weight(&diffuse, &specular, range),
                diffuse,
                specular,
                eta,
                internal: fresnel::dielectric_average(1.0 / eta),
                nonlinear: *nonlinear,
            }
        }
        MaterialConfig::RoughPlastic {
            distribution,
            alpha,
            diffuse_reflectance,
            specular_reflectance,
            int_ior,
            ext_ior,
            nonlinear,
        } => {
            let eta = plastic_eta(int_ior, ext_ior, field, file, range)?;
            check_alpha(*alpha, &ctx("alpha"), file)?;
            let microfacet = Microfacet::new(*distribution, *alpha, *alpha);
            let diffuse = diffuse_reflectance.resolve_texture(
                Role::Reflectance,
                &spectrum_ctx(file, &ctx("diffuse_reflectance"), range),
                warnings,
            )?;
            let specular = specular_reflectance.resolve_texture(
                Role::Reflectance,
                &spectrum_ctx(file, &ctx("specular_reflectance"), range),
                warnings,
            )?;
            Material::RoughPlastic {
                specular_weight: specular_weight(&diffuse, &specular, range),
                diffuse,
                specular,
                eta,
                transmittance: roughplastic::transmittance_table(&microfacet, eta),
                internal: roughplastic::internal_reflectance(&microfacet, eta),
                microfacet,
                nonlinear: *nonlinear,
            }
        }
    })
}

/// A conductor's index of refraction (a named metal, explicit `eta` and `k`, or Mitsuba's
/// default: η = 0, κ = 1, a perfect mirror) and its specular factor.
#[allow(clippy::too_many_arguments)]
fn conductor(
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
                .field(field));
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

/// The roughnesses along u and v: `alpha` for both, or `alpha_u` and `alpha_v` (Mitsuba's rules:
/// both or neither of those two, and not with `alpha`); default 0.1.
fn roughnesses(
    alpha: &Option<FloatConfig>,
    alpha_u: &Option<FloatConfig>,
    alpha_v: &Option<FloatConfig>,
    field: &str,
    file: &Path,
) -> Result<(FloatTexture, FloatTexture), InputError> {
    let ctx = |sub: &str| format!("{field}.{sub}");
    Ok(match (alpha, alpha_u, alpha_v) {
        (None, None, None) => (FloatTexture::Constant(0.1), FloatTexture::Constant(0.1)),
        (Some(a), None, None) => {
            let a = roughness(a, &ctx("alpha"), file)?;
            (a.clone(), a)
        }
        (None, Some(u), Some(v)) => (
            roughness(u, &ctx("alpha_u"), file)?,
            roughness(v, &ctx("alpha_v"), file)?,
        ),
        (Some(_), _, _) => {
            return Err(InputError::new(
                file,
                "give either `alpha` or `alpha_u` and `alpha_v`, not both",
            )
            .field(field))
        }
        (None, _, _) => {
            return Err(InputError::new(
                file,
                "an anisotropic roughness needs both `alpha_u` and `alpha_v`",
            )
            .field(field)
            .hint("or give one `alpha` for both directions"))
        }
    })
}

/// A microfacet roughness: a number in (0, 1] or a texture (values clamped to [0, 1]; 0 texels
/// become the smallest roughness the distributions represent, 1e-4, as in Mitsuba).
fn roughness(f: &FloatConfig, field: &str, file: &Path) -> Result<FloatTexture, InputError> {
    let check = |v: f32| {
        if v > 0.0 && v <= 1.0 {
            Ok(())
        } else {
            Err(InputError::new(file, format!("roughness {v} is not in (0, 1]"))
                .field(field)
                .hint("0 is a smooth surface (use Conductor or Dielectric); Mitsuba calls 0.1 relatively rough and 0.3–0.7 extremely rough"))
        }
    };
    match f {
        FloatConfig::Value(v) => {
            check(*v)?;
            Ok(FloatTexture::Constant(*v))
        }
        FloatConfig::Texture(FloatTextureConfig::Checkerboard { value0, value1, .. }) => {
            check(*value0)?;
            check(*value1)?;
            float(f, field, file)
        }
        // Texels are clamped (above), so only non-finite ones are refused.
        FloatConfig::Texture(FloatTextureConfig::Bitmap { .. }) => {
            float_in(f, field, file, TexelRange::Finite)
        }
    }
}

// Dielectrics.
/// n_int / n_ext of a dielectric, each checked over the render range.
fn relative_ior(
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
fn specular(
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

/// A scalar parameter in [0, 1] (a blend weight, an opacity).
pub(super) fn float(f: &FloatConfig, field: &str, file: &Path) -> Result<FloatTexture, InputError> {
    float_in(f, field, file, TexelRange::Fraction)
}

/// As `float`, with bitmap texels checked against `range`.
fn float_in(
    f: &FloatConfig,
    field: &str,
    file: &Path,
    range: TexelRange,
) -> Result<FloatTexture, InputError> {
    let ctx = spectrum_ctx(file, field, (0.0, 1.0));
    Ok(match f {
        FloatConfig::Value(v) => {
            if !(0.0..=1.0).contains(v) {
                return Err(InputError::new(file, format!("{v} is not in [0, 1]")).field(field));
            }
            FloatTexture::Constant(*v)
        }
        FloatConfig::Texture(FloatTextureConfig::Checkerboard {
            value0,
            value1,
            uv_scale,
            uv_offset,
        }) => {
            for v in [value0, value1] {
                if !(0.0..=1.0).contains(v) {
                    return Err(InputError::new(file, format!("{v} is not in [0, 1]")).field(field));
                }
            }
            FloatTexture::Checkerboard {
                value0: *value0,
                value1: *value1,
                map: uv_map(&ctx, *uv_scale, *uv_offset)?,
            }
        }
        FloatConfig::Texture(FloatTextureConfig::Bitmap {
            path,
            filter,
            wrap,
            raw,
            uv_scale,
            uv_offset,
        }) => {
            let full = file.parent().unwrap_or(Path::new(".")).join(path);
            let img = texture::load_rgb(&full, *raw).map_err(|m| {
                let err = InputError::new(file, m).field(field);
                let hint = "texture paths are relative to the scene file";
                super::inputs::missing_hint(err, &full, hint)
            })?;
            img.validate(range)
                .map_err(|m| InputError::new(file, m).field(field))?;
            FloatTexture::Bitmap(Box::new(img.to_luminance(
                *wrap,
                *filter,
                uv_map(&ctx, *uv_scale, *uv_offset)?,
            )))
        }
    })
}

// Plastics.
/// A plastic's relative index η = int / ext. Mitsuba's plastics take scalar indices, so a
/// dispersive one (a glass, Sellmeier, Cauchy, a varying table) is refused.
fn plastic_eta(
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

/// Microfacet roughness: Mitsuba accepts any positive value; above 1 the models leave their
/// range of validity, so prism refuses it.
pub fn check_alpha(alpha: f32, field: &str, file: &Path) -> Result<(), InputError> {
    if !(alpha.is_finite() && alpha > 0.0 && alpha <= 1.0) {
        return Err(
            InputError::new(file, format!("roughness {alpha} must lie in (0, 1]"))
                .field(field)
                .hint("use a smooth material for a perfectly specular surface"),
        );
    }
    Ok(())
}

/// Mitsuba's share of samples for the specular lobe: mean(specular) / (mean(diffuse) + mean(specular)).
fn specular_weight(
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
