//! Materials from the config.

use crate::bsdf::{Material, MAX_LOBES};
use crate::config::{
    spectrum::uv_map, spectrum_ctx, FloatConfig, FloatTextureConfig, IorConfig, MaterialConfig,
    Role, SpectrumConfig,
};
use crate::error::InputError;
use crate::spectrum::{Ior, RelativeIor};
use crate::texture::{self, FloatTexture, SpectralTexture};
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
            let (alpha_u, alpha_v) = roughness(alpha, alpha_u, alpha_v, field, file, warnings)?;
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
        } // Plastics.
    })
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

/// Microfacet roughness as Mitsuba reads it: `alpha` (default 0.1) or both `alpha_u` and
/// `alpha_v`, never both forms. Values must be finite and ≥ 0; 0 is raised to 1e-4 (with a
/// warning, as Mitsuba), where the smooth BSDF is the better choice.
fn roughness(
    alpha: &Option<FloatConfig>,
    alpha_u: &Option<FloatConfig>,
    alpha_v: &Option<FloatConfig>,
    field: &str,
    file: &Path,
    warnings: &mut Vec<String>,
) -> Result<(FloatTexture, FloatTexture), InputError> {
    let one = |f: &FloatConfig, name: &str, warnings: &mut Vec<String>| {
        let sub = format!("{field}.{name}");
        match f {
            FloatConfig::Value(v) => {
                if !(v.is_finite() && *v >= 0.0) {
                    return Err(InputError::new(file, format!("roughness {v} must be a finite number ≥ 0"))
                        .field(sub)
                        .hint("0.001–0.01: slightly imperfect finish, 0.1: rough, 0.3–0.7: etched or ground"));
                }
                if *v == 0.0 {
                    warnings.push(format!("{}: {sub}: roughness 0 is raised to 1e-4; use the smooth Dielectric for a perfectly smooth surface", file.display()));
                }
                Ok(FloatTexture::Constant(*v))
            }
            // Textured roughness takes values in [0, 1], like other scalar textures.
            _ => float(f, &sub, file),
        }
    };
    match (alpha, alpha_u, alpha_v) {
        (Some(_), Some(_), _) | (Some(_), _, Some(_)) => Err(InputError::new(
            file,
            "give either alpha or alpha_u and alpha_v, not both",
        )
        .field(field)),
        (None, Some(u), Some(v)) => {
            Ok((one(u, "alpha_u", warnings)?, one(v, "alpha_v", warnings)?))
        }
        (None, Some(_), None) | (None, None, Some(_)) => Err(InputError::new(
            file,
            "an anisotropic roughness needs both alpha_u and alpha_v",
        )
        .field(field)),
        (Some(a), None, None) => {
            let a = one(a, "alpha", warnings)?;
            Ok((a.clone(), a))
        }
        (None, None, None) => Ok((FloatTexture::Constant(0.1), FloatTexture::Constant(0.1))),
    }
}

/// A scalar parameter in [0, 1] (a blend weight, an opacity).
fn float(f: &FloatConfig, field: &str, file: &Path) -> Result<FloatTexture, InputError> {
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
                InputError::new(file, m)
                    .field(field)
                    .hint("texture paths are relative to the scene file")
            })?;
            // Values outside [0, 1] (HDR images) are clamped when evaluated.
            FloatTexture::Bitmap(Box::new(img.to_luminance(
                *wrap,
                *filter,
                uv_map(&ctx, *uv_scale, *uv_offset)?,
            )))
        }
    })
}
