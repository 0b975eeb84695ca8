//! A RON shape's `emitter` radiance: a spectrum (uniform over the shape), or a `Bitmap`
//! texture over the shape's uv (optionally inside `Scaled(k, ..)` and `ColourSpace(name, ..)`):
//!
//! ```ron
//! emitter: (radiance: Scaled(5, Bitmap(path: "textures/panel.exr", filter: Nearest)))
//! ```
//!
//! The image's linear RGB (PNG/JPEG sRGB-decoded unless `raw`; EXR and HDR as they are) times
//! the scale is uplifted texel by texel as an illuminant, as an `Rgb` radiance is
//! (`emitter::radiance`). Textured lights must be triangle meshes (Rectangle, Cube, Mesh).

use crate::config::{SpectrumConfig, MAX_EMISSION};
use crate::emitter::{AreaRadiance, EmissionTexture};
use crate::error::InputError;
use crate::load::spectrum::{spectrum_ctx, uv_map, Role};
use crate::shape::Shape;
use crate::spectrum::gamut::Gamut;
use crate::texture;
use std::path::Path;

/// The radiance `s` describes, called `field` in errors (paths relative to the scene `file`,
/// spectra checked over `range`).
pub fn area_radiance(
    s: &SpectrumConfig,
    file: &Path,
    field: &str,
    range: (f32, f32),
    warnings: &mut Vec<String>,
) -> Result<AreaRadiance, InputError> {
    // Peel `Scaled` and `ColourSpace` off a bitmap; anything else is a plain spectrum.
    let (mut scale, mut gamut, mut inner) = (1.0f32, None, s);
    loop {
        match inner {
            SpectrumConfig::Scaled(k, i) => {
                scale *= *k;
                inner = &**i;
            }
            SpectrumConfig::ColourSpace(name, i) if gamut.is_none() => {
                gamut = Some(name.as_str());
                inner = &**i;
            }
            _ => break,
        }
    }
    let SpectrumConfig::Bitmap {
        path,
        filter,
        wrap,
        raw,
        uv_scale,
        uv_offset,
    } = inner
    else {
        let ctx = spectrum_ctx(file, field, range);
        return Ok(AreaRadiance::Uniform(s.resolve(
            Role::Emission,
            &ctx,
            warnings,
        )?));
    };
    let err = |m: String| {
        InputError::new(file, m)
            .field(field.to_string())
            .hint("scenes/README.md documents emission textures (a bitmap, its scale and gamut)")
    };
    if !(scale.is_finite() && scale >= 0.0) {
        return Err(err(format!("the scale {scale} must be finite and ≥ 0")));
    }
    let gamut = match gamut {
        Some(name) => crate::load::colour_space::by_name(file, field, name)?,
        None => Gamut::Srgb,
    };
    let full = file.parent().unwrap_or(Path::new(".")).join(path);
    let img = texture::load_rgb(&full, *raw).map_err(|m| {
        super::inputs::missing_hint(
            err(m),
            &full,
            "texture paths are relative to the scene file",
        )
    })?;
    img.validate(texture::TexelRange::Radiance).map_err(err)?;
    let peak = img.pixels.iter().flatten().fold(0.0f32, |m, &c| m.max(c));
    if peak * scale > MAX_EMISSION {
        return Err(err(format!(
            "`{}`'s brightest texel, {peak:e}, times the scale {scale} exceeds the {MAX_EMISSION:e} prism accepts",
            full.display()
        ))
        .hint("the radiance would overflow 32-bit floats along a path; scale it down"));
    }
    let ctx = spectrum_ctx(file, field, range);
    let map = uv_map(&ctx, *uv_scale, *uv_offset)?;
    Ok(AreaRadiance::Textured(Box::new(EmissionTexture::new(
        gamut, &img, [scale; 3], [*wrap; 2], *filter, map,
    ))))
}

/// Refuses a textured radiance on a sphere or a disk (their emitter sampling has no uv).
pub fn check_shape(
    radiance: &AreaRadiance,
    shape: &Shape,
    file: &Path,
    field: &str,
) -> Result<(), InputError> {
    match (radiance, shape) {
        (AreaRadiance::Textured(_), Shape::Sphere(_) | Shape::Disk(_)) => Err(InputError::new(
            file,
            "a textured (Bitmap) emitter radiance needs a triangle mesh",
        )
        .field(field.to_string())
        .hint("use a Rectangle, Cube or Mesh shape, or a plain spectrum on a sphere or disk")),
        _ => Ok(()),
    }
}
