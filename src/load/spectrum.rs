//! A scene's spectrum (`config::SpectrumConfig`) resolved into a `Curve` or a texture, with
//! checks that depend on what the spectrum means (a reflectance must stay within [0, 1], an
//! emission must be ≥ 0).

mod forms;

use crate::config::{SpectrumConfig, MAX_EMISSION};
use crate::error::InputError;
use crate::spectrum::gamut::Gamut;
use crate::spectrum::Curve;
use crate::texture::{self, SpectralTexture, UvMap};
use glam::Vec2;
use std::path::Path;

/// What a spectrum stands for, which decides how RGB is uplifted and which values are valid.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// A reflectance or transmittance: values in [0, 1]; RGB uplifted bounded.
    Reflectance,
    /// Emitted radiance or intensity: values ≥ 0; RGB uplifted unbounded, times D65.
    Emission,
    /// A part of a complex index of refraction (a conductor's η or κ): values ≥ 0, no upper
    /// bound; RGB and illuminants are refused (they have no meaning as an index).
    Ior,
    /// A sensor's or filter's spectral response: values ≥ 0, no upper bound; RGB and
    /// illuminants are refused.
    Response,
}

/// Where a spectrum sits: for error messages and relative paths.
pub struct Context<'a> {
    /// The scene file.
    pub file: &'a Path,
    /// The field path, e.g. `materials."red".reflectance`.
    pub field: &'a str,
    /// The render's wavelength range (values are checked over it).
    pub range: (f32, f32),
}

/// The context in which a spectrum field is resolved (for errors and relative paths).
pub fn spectrum_ctx<'a>(file: &'a Path, field: &'a str, range: (f32, f32)) -> Context<'a> {
    Context { file, field, range }
}

impl Context<'_> {
    fn err(&self, message: impl Into<String>) -> InputError {
        InputError::new(self.file, message).field(self.field)
    }
}

fn check_finite(ctx: &Context, what: &str, v: f32) -> Result<(), InputError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(ctx
            .err(format!("{what} is {v}, not a finite number"))
            .hint("write a finite value"))
    }
}

impl SpectrumConfig {
    /// Resolves to a curve; `warnings` receives notes that do not stop the render.
    pub fn resolve(
        &self,
        role: Role,
        ctx: &Context,
        warnings: &mut Vec<String>,
    ) -> Result<Curve, InputError> {
        let curve = self.resolve_inner(role, ctx)?;
        let (lo, hi) = ctx.range;
        let (min, max) = curve.min_max(lo, hi);
        if !(min.is_finite() && max.is_finite()) {
            return Err(ctx.err("the spectrum takes non-finite values over the render range"));
        }
        if min < 0.0 {
            return Err(ctx
                .err(format!(
                    "the spectrum is negative ({min}) somewhere in {lo}–{hi} nm"
                ))
                .hint("spectral values must be ≥ 0"));
        }
        if role == Role::Emission && max > MAX_EMISSION {
            return Err(ctx
                .err(format!("the emission reaches {max:e} in {lo}–{hi} nm, above the {MAX_EMISSION:e} prism accepts"))
                .hint("a path multiplies it by its throughput, pdfs and the sensor's weights in 32-bit floats, which would overflow to infinity; the sun's spectral radiance is about 2e4 W m⁻² sr⁻¹ nm⁻¹: scale the value down"));
        }
        if role == Role::Reflectance && max > 1.0 + 1e-4 {
            return Err(ctx
                .err(format!("a reflectance must lie in [0, 1], but this one reaches {max} in {lo}–{hi} nm"))
                .hint("a surface cannot reflect more light than it receives; scale the values to at most 1"));
        }
        let rgb = matches!(self, SpectrumConfig::Rgb(..))
            || matches!(self, SpectrumConfig::ColourSpace(_, inner) if matches!(**inner, SpectrumConfig::Rgb(..)));
        if rgb && role == Role::Reflectance {
            warn_rgb_reflectance_range(ctx, warnings);
        }
        if let Some((a, b)) = curve.support().filter(|_| role != Role::Response) {
            if a > lo || b < hi {
                warnings.push(format!(
                    "{}: {}: the spectrum is defined over {a}–{b} nm only and is 0 elsewhere in the render range {lo}–{hi} nm",
                    ctx.file.display(),
                    ctx.field
                ));
            }
        }
        Ok(curve)
    }

    /// Resolves a spectrum that may also be a texture (material parameters).
    pub fn resolve_texture(
        &self,
        role: Role,
        ctx: &Context,
        warnings: &mut Vec<String>,
    ) -> Result<SpectralTexture, InputError> {
        Ok(match self {
            SpectrumConfig::Checkerboard {
                color0,
                color1,
                uv_scale,
                uv_offset,
            } => SpectralTexture::Checkerboard {
                color0: color0.resolve(role, ctx, warnings)?,
                color1: color1.resolve(role, ctx, warnings)?,
                map: uv_map(ctx, *uv_scale, *uv_offset)?,
            },
            SpectrumConfig::ColourSpace(name, inner)
                if matches!(**inner, SpectrumConfig::Bitmap { .. }) =>
            {
                let gamut = super::colour_space::gamut(ctx, name)?;
                return inner.bitmap(gamut, role, ctx, warnings);
            }
            SpectrumConfig::Bitmap { .. } => return self.bitmap(Gamut::Srgb, role, ctx, warnings),
            _ => SpectralTexture::Uniform(self.resolve(role, ctx, warnings)?),
        })
    }

    /// A `Bitmap`'s texture, its texels in the RGB space `gamut`.
    fn bitmap(
        &self,
        gamut: Gamut,
        role: Role,
        ctx: &Context,
        warnings: &mut Vec<String>,
    ) -> Result<SpectralTexture, InputError> {
        warn_rgb_reflectance_range(ctx, warnings);
        Ok(match self {
            SpectrumConfig::Bitmap {
                path,
                filter,
                wrap,
                raw,
                uv_scale,
                uv_offset,
            } => {
                if role != Role::Reflectance {
                    return Err(ctx.err("a bitmap here would be uplifted as a reflectance; this parameter is not one"));
                }
                let full = ctx.file.parent().unwrap_or(Path::new(".")).join(path);
                let img = texture::load_rgb(&full, *raw).map_err(|m| {
                    let err = ctx.err(m);
                    let hint = "texture paths are relative to the scene file";
                    crate::io::inputs::missing_hint(err, &full, hint)
                })?;
                img.validate(texture::TexelRange::Reflectance)
                    .map_err(|m| ctx.err(m))?;
                SpectralTexture::Bitmap(Box::new(img.to_reflectance_in(
                    gamut,
                    *wrap,
                    *filter,
                    uv_map(ctx, *uv_scale, *uv_offset)?,
                )))
            }
            _ => unreachable!("only called on a Bitmap"),
        })
    }
}

/// An RGB reflectance (value or texture) is a sigmoid fitted to its colour over the CIE 1931
/// observer's 360–830 nm; past that range it is the sigmoid's extrapolation, not data: say so
/// when the render range reaches beyond it (issue 15: never a silent guess in the NIR or UV).
fn warn_rgb_reflectance_range(ctx: &Context, warnings: &mut Vec<String>) {
    use crate::spectrum::rgb2spec_fit::{LAMBDA_MAX, LAMBDA_MIN};
    let (lo, hi) = ctx.range;
    if (lo as f64) < LAMBDA_MIN || (hi as f64) > LAMBDA_MAX {
        warnings.push(format!(
            "{}: {}: an RGB reflectance is uplifted to a spectrum fitted over {LAMBDA_MIN}–{LAMBDA_MAX} nm; in the rest of the render range {lo}–{hi} nm it is extrapolated, not measured (give a Tabulated or File reflectance that covers the range)",
            ctx.file.display(),
            ctx.field
        ));
    }
}

/// Checks a texture placement.
pub fn uv_map(ctx: &Context, scale: (f32, f32), offset: (f32, f32)) -> Result<UvMap, InputError> {
    let ok = [scale.0, scale.1, offset.0, offset.1]
        .iter()
        .all(|v| v.is_finite())
        && scale.0 != 0.0
        && scale.1 != 0.0;
    if !ok {
        return Err(ctx.err(format!(
            "uv_scale {scale:?} must be finite and non-zero, uv_offset {offset:?} finite"
        )));
    }
    Ok(UvMap {
        scale: Vec2::new(scale.0, scale.1),
        offset: Vec2::new(offset.0, offset.1),
        rotation: Vec2::X,
    })
}
