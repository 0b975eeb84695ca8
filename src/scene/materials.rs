//! Materials from the config.

use crate::bsdf::{Material, MAX_LOBES};
use crate::config::{
    spectrum::uv_map, spectrum_ctx, FloatConfig, FloatTextureConfig, MaterialConfig, Role,
};
use crate::error::InputError;
use crate::texture::{self, FloatTexture};
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
