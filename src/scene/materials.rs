//! Materials from the config.

use crate::bsdf::microfacet::Microfacet;
use crate::bsdf::{fresnel, roughplastic, Material, MAX_LOBES};
use crate::config::{
    spectrum::uv_map, spectrum_ctx, FloatConfig, FloatTextureConfig, MaterialConfig, Role,
};
use crate::error::InputError;
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
        // Plastics.
        MaterialConfig::Plastic {
            diffuse_reflectance,
            specular_reflectance,
            int_ior,
            ext_ior,
            nonlinear,
        } => {
            let eta = relative_ior(*int_ior, *ext_ior, field, file)?;
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
            let eta = relative_ior(*int_ior, *ext_ior, field, file)?;
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

/// η = int / ext, both positive and finite.
fn relative_ior(int: f32, ext: f32, field: &str, file: &Path) -> Result<f32, InputError> {
    for (v, name) in [(int, "int_ior"), (ext, "ext_ior")] {
        if !(v.is_finite() && v > 0.0) {
            return Err(
                InputError::new(file, format!("{name} {v} must be a positive number"))
                    .field(format!("{field}.{name}")),
            );
        }
    }
    Ok(int / ext)
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
