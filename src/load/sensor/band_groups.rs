//! `sensor.bands`: the even grid, boxes and filter curves, checked against the spectral range,
//! as responses and channel names.

use super::At;
use crate::config::sensor::BandConfig;
use crate::error::InputError;
use crate::load::{spectrum_ctx, Role};
use crate::sensor::bands::{Response, Shape};
use crate::sensor::{Bands, ChannelName};

/// The bands of `sensor.bands`.
pub(super) struct SpectralBands {
    /// The even grid, if one is given.
    pub even: Option<Bands>,
    /// The responses of the boxes and filters, in order, and their channel names.
    pub responses: Vec<Response>,
    pub names: Vec<ChannelName>,
}

/// The most Box, Boxes and Filter bands a sensor may list (an `Even` grid has its own 4096).
const MAX_LISTED: usize = 1024;

/// The bands of `groups`, each checked against the spectral `range`.
pub(super) fn spectral_bands(
    groups: &[BandConfig],
    at: &At,
    range: (f32, f32),
    warnings: &mut Vec<String>,
) -> Result<SpectralBands, InputError> {
    let (lo, hi) = range;
    let mut even: Option<Bands> = None;
    let mut responses = Vec::new();
    let mut names = Vec::new();
    let check_box = |field: &str, blo: f32, bhi: f32| -> Result<(), InputError> {
        if !(blo.is_finite() && bhi.is_finite() && blo < bhi) {
            return Err(at
                .err(
                    field,
                    format!("the band [{blo}, {bhi}) nm has zero or negative width"),
                )
                .hint("write (lo, hi) with lo < hi"));
        }
        if blo < lo || bhi > hi {
            return Err(at
                .err(field, format!("the band [{blo}, {bhi}) nm lies outside the spectral range ({lo}, {hi}) nm"))
                .hint("widen spectral.range or move the band inside it"));
        }
        Ok(())
    };
    // Boxes and filters together, counted before any is set up: each band's work grows with the
    // number of channels (20,000 boxes ran for minutes).
    let listed: usize = groups
        .iter()
        .map(|g| match g {
            BandConfig::Boxes(list) => list.len(),
            BandConfig::Even { .. } => 0,
            _ => 1,
        })
        .sum();
    if listed > MAX_LISTED {
        return Err(at
            .err(
                "bands",
                format!("{listed} Box, Boxes and Filter bands: more than {MAX_LISTED}"),
            )
            .hint("use an Even group for a fine grid of bands (up to 4096)"));
    }
    for (g, group) in groups.iter().enumerate() {
        let field = format!("bands[{g}]");
        match group {
            BandConfig::Even { count, range: r } => {
                let (blo, bhi) = r.unwrap_or(range);
                if even.is_some() {
                    return Err(at
                        .err(&field, "more than one `Even` group")
                        .hint("give one Even group; add others as Boxes([...])"));
                }
                let n = match count {
                    Some(0) => {
                        continue;
                    }
                    Some(n) => *n,
                    None => (((bhi - blo) / 10.0).round() as u32).max(1),
                };
                // The old `outputs` wording for its two fields.
                let (rf, cf) = if at.prefix == "outputs" {
                    ("band_range".to_string(), "bands".to_string())
                } else {
                    (format!("{field}.range"), format!("{field}.count"))
                };
                if !(blo.is_finite() && bhi.is_finite() && blo < bhi && blo >= lo && bhi <= hi) {
                    return Err(at.err(&rf, format!("the band range ({blo}, {bhi}) nm must be increasing and inside the spectral range ({lo}, {hi}) nm")));
                }
                if n > 4096 {
                    return Err(at.err(&cf, "more than 4096 spectral bands").hint(
                        "give at most 4096 bands, e.g. count: 471 for 1 nm over 360–830 nm",
                    ));
                }
                even = Some(Bands {
                    lo: blo,
                    hi: bhi,
                    count: n,
                });
            }
            BandConfig::Boxes(list) => {
                for (i, &(blo, bhi)) in list.iter().enumerate() {
                    check_box(&format!("{field}[{i}]"), blo, bhi)?;
                    responses.push(Response {
                        shape: Shape::Box { lo: blo, hi: bhi },
                        scale: 1.0 / (bhi - blo),
                    });
                    names.push(ChannelName::Spectral(0.5 * (blo + bhi)));
                }
            }
            BandConfig::Box {
                lo: blo,
                hi: bhi,
                name,
            } => {
                check_box(&field, *blo, *bhi)?;
                responses.push(Response {
                    shape: Shape::Box { lo: *blo, hi: *bhi },
                    scale: 1.0 / (bhi - blo),
                });
                names.push(match name {
                    Some(n) => ChannelName::Layer(layer_name(at, &format!("{field}.name"), n)?),
                    None => ChannelName::Spectral(0.5 * (blo + bhi)),
                });
            }
            BandConfig::Filter { name, curve } => {
                let f = format!("{field}.curve");
                let full = at.field(&f);
                let c = curve.resolve(
                    Role::Response,
                    &spectrum_ctx(at.file, &full, range),
                    warnings,
                )?;
                let mut r = Response {
                    shape: Shape::Curve(c),
                    scale: 1.0,
                };
                let (slo, shi) = r.support(range);
                let integral = r.integral(slo.max(lo), shi.min(hi));
                if integral.is_nan() || integral <= 0.0 {
                    return Err(at
                        .err(
                            &f,
                            format!(
                                "the filter curve is zero over the spectral range ({lo}, {hi}) nm"
                            ),
                        )
                        .hint(
                            "a filter needs a positive response somewhere inside spectral.range",
                        ));
                }
                if slo < lo || shi > hi {
                    let total = r.integral(slo, shi);
                    if integral < 0.999 * total {
                        warnings.push(format!(
                            "{}: {full}: the filter responds over {slo}–{shi} nm, beyond the spectral range ({lo}, {hi}) nm; its channel integrates the rendered part only ({:.1}% of its area)",
                            at.file.display(),
                            100.0 * integral / total
                        ));
                    }
                }
                r.scale = (1.0 / integral) as f32;
                names.push(match name {
                    Some(n) => ChannelName::Layer(layer_name(at, &format!("{field}.name"), n)?),
                    // The centroid to 0.001 nm, so a symmetric curve is named after its centre.
                    None => ChannelName::Spectral(
                        (r.centre(slo.max(lo), shi.min(hi)) * 1000.0).round() / 1000.0,
                    ),
                });
                responses.push(r);
            }
        }
    }
    Ok(SpectralBands {
        even,
        responses,
        names,
    })
}

/// A user's layer name (`nir` → channel `nir.Y`): letters, digits, `_` and `-` only.
fn layer_name(at: &At, field: &str, n: &str) -> Result<String, InputError> {
    let ok = !n.is_empty()
        && n.chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
        && !n.starts_with("S0")
        && !["camera", "corrected", "raw"].contains(&n);
    if !ok {
        return Err(at.err(field, format!("`{n}` is not a usable layer name"))
            .hint("use ASCII letters, digits, `_` or `-`, not starting with S0 and not `camera`, `corrected` or `raw`"));
    }
    Ok(format!("{n}.Y"))
}
