//! A material's scalar parameters: microfacet roughnesses (numbers in (0, 1] or textures) and
//! [0, 1] weights and opacities.

use crate::config::{FloatConfig, FloatTextureConfig};
use crate::error::InputError;
use crate::load::spectrum::{spectrum_ctx, uv_map};
use crate::texture::{self, FloatTexture, TexelRange};
use std::path::Path;

/// The roughnesses along u and v: `alpha` for both, or `alpha_u` and `alpha_v` (Mitsuba's rules:
/// both or neither of those two, and not with `alpha`); default 0.1.
pub(super) fn roughnesses(
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

/// A scalar parameter in [0, 1] (a blend weight, an opacity).
pub(crate) fn float(f: &FloatConfig, field: &str, file: &Path) -> Result<FloatTexture, InputError> {
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
                return Err(InputError::new(file, format!("{v} is not in [0, 1]"))
                    .field(field)
                    .hint("give a value from 0 to 1"));
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
                    return Err(InputError::new(file, format!("{v} is not in [0, 1]"))
                        .field(field)
                        .hint("give a value from 0 to 1"));
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
                let err = InputError::new(file, m)
                    .field(field)
                    .hint("a texture is a PNG or EXR image prism reads");
                let hint = "texture paths are relative to the scene file";
                crate::io::inputs::missing_hint(err, &full, hint)
            })?;
            img.validate(range).map_err(|m| {
                InputError::new(file, m)
                    .field(field)
                    .hint("fix the texels the message names, or give another image")
            })?;
            FloatTexture::Bitmap(Box::new(img.to_luminance(
                *wrap,
                *filter,
                uv_map(&ctx, *uv_scale, *uv_offset)?,
            )))
        }
    })
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
