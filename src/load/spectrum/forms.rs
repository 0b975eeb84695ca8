//! The plain (untextured) forms of a spectrum resolved to a `Curve`, each with the checks of its
//! own values (increasing wavelengths, finite numbers, names that exist, RGB in range).

use super::{check_finite, Context, Role, SpectrumConfig};
use crate::error::InputError;
use crate::math::portable;
use crate::spectrum::gamut::Gamut;
use crate::spectrum::{data, table, Curve};
use std::path::Path;

impl SpectrumConfig {
    pub(super) fn resolve_inner(&self, role: Role, ctx: &Context) -> Result<Curve, InputError> {
        Ok(match self {
            SpectrumConfig::Constant(v) => {
                check_finite(ctx, "the value", *v)?;
                Curve::Constant(*v)
            }
            SpectrumConfig::Rgb(r, g, b) => rgb_curve([*r, *g, *b], Gamut::Srgb, role, ctx)?,
            SpectrumConfig::ColourSpace(name, inner) => {
                let gamut = crate::load::colour_space::gamut(ctx, name)?;
                match **inner {
                    SpectrumConfig::Rgb(r, g, b) => rgb_curve([r, g, b], gamut, role, ctx)?,
                    SpectrumConfig::Bitmap { .. } => {
                        return Err(ctx
                            .err("a texture is not allowed here")
                            .hint("textures vary over a surface; emitters and indices of refraction take a plain spectrum"))
                    }
                    _ => {
                        return Err(ctx
                            .err(format!("ColourSpace(\"{name}\", …) wraps an Rgb value or a Bitmap texture, not this spectrum"))
                            .hint(format!("e.g. ColourSpace(\"{name}\", Rgb(0.7, 0.4, 0.2))")))
                    }
                }
            }
            SpectrumConfig::Tabulated(pairs) => {
                if pairs.is_empty() {
                    return Err(ctx.err("a tabulated spectrum needs at least one (nm, value) pair"));
                }
                for (i, w) in pairs.windows(2).enumerate() {
                    if w[1].0 <= w[0].0 {
                        return Err(ctx.err(format!(
                            "wavelengths must increase: pair {} ({} nm) follows {} nm",
                            i + 1,
                            w[1].0,
                            w[0].0
                        )));
                    }
                }
                for (i, (nm, v)) in pairs.iter().enumerate() {
                    check_finite(ctx, &format!("pair {i}'s wavelength"), *nm)?;
                    check_finite(ctx, &format!("pair {i}'s value"), *v)?;
                    if *nm <= 0.0 {
                        return Err(
                            ctx.err(format!("pair {i}: wavelength {nm} nm is not positive"))
                        );
                    }
                }
                let nm: Vec<f64> = pairs.iter().map(|p| p.0 as f64).collect();
                let v: Vec<f64> = pairs.iter().map(|p| p.1 as f64).collect();
                Curve::from_samples(&nm, &v)
            }
            SpectrumConfig::File { path, column } => {
                let full = ctx.file.parent().unwrap_or(Path::new(".")).join(path);
                crate::io::inputs::record(&full);
                let bytes = crate::io::input_file::read(&full, crate::io::input_file::Kind::Spectrum)
                    .map_err(|m| {
                        let hint = "paths are relative to the scene file";
                        crate::io::inputs::missing_hint(ctx.err(m), &full, hint)
                    })?;
                let text = crate::config::utf8(bytes, &full)?;
                let t = table::parse(&text).map_err(|e| {
                    InputError::new(&full, e.message.clone())
                        .at(e.line, 1)
                        .hint(format!(
                            "referenced from {}: {}",
                            ctx.file.display(),
                            ctx.field
                        ))
                })?;
                let c = match column {
                    None => 0,
                    Some(name) => t.columns.iter().position(|c| c == name).ok_or_else(|| {
                        ctx.err(format!("`{}` has no column `{name}`", full.display()))
                            .hint(format!("its columns are: {}", t.columns.join(", ")))
                    })?,
                };
                Curve::from_samples(&t.wavelengths, &t.values[c])
            }
            SpectrumConfig::Named(name) => {
                match role {
                    Role::Reflectance => {
                        return Err(ctx
                            .err(format!(
                                "`Named(\"{name}\")` is an illuminant, not a reflectance"
                            ))
                            .hint("use Constant, Rgb, Tabulated or File for reflectances"))
                    }
                    Role::Ior => {
                        return Err(ctx
                            .err(format!(
                                "`Named(\"{name}\")` is an illuminant, not an index of refraction"
                            ))
                            .hint("name a metal with the material's `material` field instead, e.g. material: \"Au\""))
                    }
                    Role::Response => {
                        return Err(ctx
                            .err(format!("`Named(\"{name}\")` is an illuminant, not a spectral response"))
                            .hint("write it as Tabulated, File (nm, value) or Gaussian(centre, fwhm)"))
                    }
                    Role::Emission => {}
                }
                data::named_illuminant(name).ok_or_else(|| {
                    ctx.err(format!("unknown spectrum name `{name}`"))
                        .hint(format!(
                            "the named spectra are: {}",
                            data::illuminant_names().join(", ")
                        ))
                })?
            }
            SpectrumConfig::Blackbody(kelvin) => {
                check_finite(ctx, "the temperature", *kelvin)?;
                if *kelvin <= 0.0 {
                    return Err(ctx.err(format!("blackbody temperature {kelvin} K must be > 0")));
                }
                if role != Role::Emission {
                    return Err(ctx.err("a blackbody is an emission spectrum, not a reflectance or an index of refraction"));
                }
                Curve::blackbody(*kelvin)
            }
            SpectrumConfig::Gaussian { centre, fwhm } => {
                check_finite(ctx, "the centre", *centre)?;
                check_finite(ctx, "the fwhm", *fwhm)?;
                // Below 0.001 nm the table's steps vanish next to the centre in f64.
                if *centre <= 0.0 || *fwhm < 1e-3 {
                    return Err(ctx
                        .err(format!("Gaussian(centre: {centre}, fwhm: {fwhm}): the centre must be > 0 nm and the fwhm at least 0.001 nm"))
                        .hint("e.g. Gaussian(centre: 850, fwhm: 40)"));
                }
                if role == Role::Ior {
                    return Err(ctx
                        .err("a Gaussian is not an index of refraction")
                        .hint("give the index as a number, a Tabulated or File spectrum, or a Sellmeier form"));
                }
                gaussian(*centre, *fwhm, ctx.range)
            }
            SpectrumConfig::Checkerboard { .. } | SpectrumConfig::Bitmap { .. } => {
                return Err(ctx
                    .err("a texture is not allowed here")
                    .hint("textures vary over a surface; emitters and indices of refraction take a plain spectrum"))
            }
            SpectrumConfig::Scaled(k, inner) => {
                check_finite(ctx, "the scale factor", *k)?;
                if *k < 0.0 {
                    return Err(ctx.err(format!("the scale factor {k} must be ≥ 0")));
                }
                inner.resolve_inner(role, ctx)?.scaled(*k)
            }
        })
    }
}

/// The curve of the RGB value `rgb` of the space `gamut`, checked for `role`.
fn rgb_curve(rgb: [f32; 3], gamut: Gamut, role: Role, ctx: &Context) -> Result<Curve, InputError> {
    let [r, g, b] = rgb;

    for (c, name) in rgb.iter().zip(["red", "green", "blue"]) {
        check_finite(ctx, &format!("the {name} component"), *c)?;
        if *c < 0.0 {
            return Err(ctx.err(format!(
                "the {name} component is {c}; RGB components must be ≥ 0"
            )));
        }
    }
    Ok(match role {
        Role::Reflectance => {
            if rgb.iter().any(|&c| c > 1.0) {
                return Err(ctx
                    .err(format!(
                        "a reflectance RGB must lie in [0, 1], got ({r}, {g}, {b})"
                    ))
                    .hint(
                        "reflectances above 1 would create energy; divide by the largest component",
                    ));
            }
            Curve::rgb_reflectance_in(gamut, rgb)
        }
        Role::Emission => Curve::rgb_illuminant_in(gamut, rgb),
        Role::Response => {
            return Err(ctx
                .err("a spectral response cannot be given as RGB")
                .hint("write it as Tabulated, File (nm, value) or Gaussian(centre, fwhm)"))
        }
        Role::Ior => return Err(ctx
            .err("an index of refraction cannot be given as RGB")
            .hint(
            "write it as Constant, Tabulated or File (nm, value), or name a metal with `material`",
        )),
    })
}

/// A Gaussian tabulated finely enough for linear interpolation (step ≤ σ/20: relative error
/// < 1e-3 at the peak) over ±6σ around the centre (beyond which it is < 1e-7 of its peak; the
/// curve is 0 outside its table), cut to the render range widened by its own width on each
/// side (enough for a filter to see how much of it lies beyond the range). The table thus
/// holds at most 241 samples or three times the range's width in nm, whatever the fwhm: a
/// fwhm of 1e30 (or 1e-30) asked for more than 2^64 samples, which wrapped to none (a panic).
fn gaussian(centre: f32, fwhm: f32, range: (f32, f32)) -> Curve {
    let sigma = fwhm as f64 / (8.0 * std::f64::consts::LN_2).sqrt();
    let span = (range.1 - range.0) as f64;
    let lo = (centre as f64 - 6.0 * sigma)
        .max(range.0 as f64 - span)
        .max(1.0);
    let hi = (centre as f64 + 6.0 * sigma).min(range.1 as f64 + span);
    if hi <= lo {
        // The Gaussian is below 1e-7 of its peak over the whole widened range.
        return Curve::Constant(0.0);
    }
    let step = (sigma / 20.0).min(1.0);
    let n = ((hi - lo) / step).ceil() as usize + 1;
    let nm: Vec<f64> = (0..n).map(|i| lo + i as f64 * step).collect();
    let v: Vec<f64> = nm
        .iter()
        .map(|&l| portable::exp(-0.5 * ((l - centre as f64) / sigma).powi(2)))
        .collect();
    Curve::from_samples(&nm, &v)
}
