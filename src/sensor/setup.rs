//! From the scene's `sensor:` (or its older `outputs:`) to a `Sensor`, with every check a
//! user's mistake can trip reported against the file and the field.

use super::bands::{Response, Shape};
use super::camera::{self, CameraModel, CAMERAS};
use super::{Bands, ChannelName, Layers, Observer, RgbSpace, Sensor};
use crate::config::sensor::{
    BandConfig, CameraConfig, CameraCurves, SensorConfig, SensorField, SensorFile, WhiteBalance,
};
use crate::config::{spectrum_ctx, OutputConfig, Role};
use crate::error::InputError;
use crate::spectrum::{data, Curve};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// Where a sensor's fields are reported: the file and the prefix of its field paths.
struct At<'a> {
    file: &'a Path,
    prefix: &'a str,
}

impl At<'_> {
    fn field(&self, f: &str) -> String {
        if self.prefix.is_empty() || f.is_empty() {
            format!("{}{f}", if f.is_empty() { self.prefix } else { "" })
        } else {
            format!("{}.{f}", self.prefix)
        }
    }

    fn err(&self, field: &str, message: impl Into<String>) -> InputError {
        InputError::new(self.file, message).field(self.field(field))
    }
}

/// Reads a sensor file (RON, a `SensorConfig`).
pub fn read_file(path: &Path) -> Result<SensorConfig, InputError> {
    crate::scene::inputs::record(path);
    let text = std::fs::read_to_string(path).map_err(|e| {
        InputError::new(path, format!("cannot read the sensor file: {e}"))
            .hint("sensor files are relative to the scene file (`--sensor` paths to the current directory)")
    })?;
    let opts =
        ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
    opts.from_str::<SensorConfig>(&text).map_err(|e| {
        InputError::new(path, e.code.to_string())
            .at(e.span.start.line, e.span.start.col)
            .hint("configs/README.md documents the sensor format")
    })
}

/// The scene's sensor: `sensor` if given (inline or a file), else today's `outputs`.
pub fn build(
    sensor: Option<&SensorField>,
    outputs: &OutputConfig,
    scene: &Path,
    range: (f32, f32),
    warnings: &mut Vec<String>,
) -> Result<Sensor, InputError> {
    match sensor {
        None => from_outputs(outputs, scene, range, warnings),
        Some(s) => {
            if *outputs != OutputConfig::default() {
                return Err(InputError::new(scene, "both `sensor` and `outputs` are given")
                    .field("outputs")
                    .hint("`sensor` replaces `outputs`: move rgb/xyz/bands into the sensor (configs/README.md)"));
            }
            match s {
                SensorField::Inline(cfg) => from_config(
                    cfg,
                    &At {
                        file: scene,
                        prefix: "sensor",
                    },
                    range,
                    warnings,
                ),
                SensorField::Empty(()) => from_config(
                    &SensorConfig::default(),
                    &At {
                        file: scene,
                        prefix: "sensor",
                    },
                    range,
                    warnings,
                ),
                SensorField::File(SensorFile::File(p)) => {
                    let path = scene.parent().unwrap_or(Path::new(".")).join(p);
                    let cfg = read_file(&path)?;
                    from_config(
                        &cfg,
                        &At {
                            file: &path,
                            prefix: "",
                        },
                        range,
                        warnings,
                    )
                }
            }
        }
    }
}

/// `--sensor FILE` on the command line (relative to the current directory).
pub fn cli_override(path: &Path) -> SensorField {
    let abs: PathBuf = std::env::current_dir()
        .map(|d| d.join(path))
        .unwrap_or_else(|_| path.to_path_buf());
    SensorField::File(SensorFile::File(abs.to_string_lossy().into_owned()))
}

/// Today's `outputs: (rgb, xyz, bands, band_range)` as a sensor (the same channels, bit for bit).
fn from_outputs(
    o: &OutputConfig,
    file: &Path,
    range: (f32, f32),
    warnings: &mut Vec<String>,
) -> Result<Sensor, InputError> {
    let bands = match o.bands {
        Some(0) => vec![],
        count => vec![BandConfig::Even {
            count,
            range: o.band_range,
        }],
    };
    let cfg = SensorConfig {
        rgb: if o.rgb { vec![RgbSpace::Srgb] } else { vec![] },
        xyz: o.xyz,
        bands: Some(bands),
        ..SensorConfig::default()
    };
    from_config(
        &cfg,
        &At {
            file,
            prefix: "outputs",
        },
        range,
        warnings,
    )
}

fn from_config(
    cfg: &SensorConfig,
    at: &At,
    range: (f32, f32),
    warnings: &mut Vec<String>,
) -> Result<Sensor, InputError> {
    let (lo, hi) = range;
    let mut even: Option<Bands> = None;
    let mut responses = Vec::new();
    let mut names = Vec::new();
    let default_bands = [BandConfig::Even {
        count: None,
        range: None,
    }];
    let groups = cfg.bands.as_deref().unwrap_or(&default_bands);
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
                    return Err(at.err(&cf, "more than 4096 spectral bands"));
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
    let mut layers = Layers {
        rgb: cfg.rgb.clone(),
        xyz: cfg.xyz,
        responses: names,
        camera: None,
        header: vec![("prism:observer".into(), cfg.observer.label().into())],
    };
    let mut raw = None;
    if let (Some(_), None) = (&cfg.raw, &cfg.camera) {
        return Err(at
            .err("raw", "the raw sensor needs a camera: its mosaic samples the camera's R, G, B curves")
            .hint("add camera: (curves: Named(\"sony_ilce_7m3\"), exposure: (iso: 100, shutter: 0.01, f_number: 4)), or see configs/sensors/raw_rggb.ron"));
    }
    if let Some(cam) = &cfg.camera {
        let (curves, model) = camera_model(cam, at, range, cfg.observer, warnings)?;
        if let Some(r) = &cfg.raw {
            let err = |f: &str, m: String, fix: &str| {
                let field = if f.is_empty() {
                    "raw".to_string()
                } else {
                    format!("raw.{f}")
                };
                at.err(&field, m).hint(fix)
            };
            raw = Some(super::raw::build(r, &curves, cam.exposure, range, &err)?);
        }
        let (glo, ghi) = curves[1].support().unwrap_or(range);
        let g = Response {
            shape: Shape::Curve(curves[1].clone()),
            scale: 1.0,
        };
        let g_integral = g.integral(glo.max(lo), ghi.min(hi));
        if g_integral.is_nan() || g_integral <= 0.0 {
            return Err(at.err(
                "camera.curves",
                "the camera's green curve is zero over the spectral range",
            ));
        }
        for c in curves {
            responses.push(Response {
                shape: Shape::Curve(c),
                scale: (1.0 / g_integral) as f32,
            });
        }
        layers.header.extend(model.header());
        layers.camera = Some(model);
    }
    // The raw sensor's photon slots come last, after the camera's.
    let raw = raw.map(|r: super::raw::RawSetup| {
        responses.extend(r.photons);
        layers.header.extend(r.header);
        r.model
    });
    // Channel names must be unique (the EXR format requires it).
    for (i, s) in layers.rgb.iter().enumerate() {
        if layers.rgb[..i].contains(s) {
            return Err(at
                .err(&format!("rgb[{i}]"), format!("{s:?} is listed twice"))
                .hint("list each RGB space once"));
        }
    }
    let mut seen = BTreeSet::new();
    let mut all: Vec<String> = Vec::new();
    if layers.rgb.contains(&RgbSpace::Srgb) {
        all.extend(["R", "G", "B"].map(String::from));
    }
    if layers.xyz {
        all.extend(["X", "Y", "Z"].map(String::from));
    }
    for s in &layers.rgb {
        if let Some(p) = s.layer() {
            all.extend(["R", "G", "B"].map(|c| format!("{p}.{c}")));
        }
    }
    if let Some(b) = even {
        all.extend((0..b.count).map(|k| crate::film::spectral_channel_name(b.center(k))));
    }
    all.extend(layers.responses.iter().map(|n| n.text()));
    if layers.camera.is_some() {
        all.extend(
            ["camera", "corrected"]
                .iter()
                .flat_map(|p| ["R", "G", "B"].map(|c| format!("{p}.{c}"))),
        );
    }
    for n in &all {
        if !seen.insert(n.clone()) {
            return Err(at
                .err("bands", format!("two channels are both named `{n}`"))
                .hint("give each band a distinct range or name, and list each RGB space once"));
        }
    }
    if all.is_empty() {
        return Err(at
            .err("", "no output channels")
            .hint("enable rgb, xyz or bands"));
    }
    let cmf_range = (360.0, 830.0);
    if (layers.xyz || !layers.rgb.is_empty()) && (lo > cmf_range.0 || hi < cmf_range.1) {
        warnings.push(format!(
            "{}: spectral.range: ({lo}, {hi}) nm does not cover the CIE observer's 360–830 nm; XYZ and RGB integrate only the rendered part",
            at.file.display()
        ));
    }
    if cfg.observer != Observer::Cie1931 && !layers.rgb.is_empty() {
        warnings.push(format!(
            "{}: {}: the RGB spaces are defined on the CIE 1931 observer; here they are computed from {} XYZ",
            at.file.display(),
            at.field("rgb"),
            cfg.observer.label()
        ));
    }
    let mut sensor = Sensor::with(cfg.observer, even, responses, layers);
    sensor.raw = raw.map(|m| super::raw::RawModel {
        slot: sensor.slots() - 3,
        ..m
    });
    Ok(sensor)
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

fn camera_model(
    cam: &CameraConfig,
    at: &At,
    range: (f32, f32),
    observer: Observer,
    warnings: &mut Vec<String>,
) -> Result<([Curve; 3], CameraModel), InputError> {
    let (curves, name) = match &cam.curves {
        CameraCurves::Named(n) => (
            camera::named(n).ok_or_else(|| {
                at.err("camera.curves", format!("unknown camera `{n}`"))
                    .hint(format!("the named cameras are: {}", CAMERAS.join(", ")))
            })?,
            n.clone(),
        ),
        CameraCurves::Curves { r, g, b } => {
            let mut out = Vec::new();
            for (c, s) in [("r", r), ("g", g), ("b", b)] {
                let f = at.field(&format!("camera.curves.{c}"));
                out.push(s.resolve(Role::Response, &spectrum_ctx(at.file, &f, range), warnings)?);
            }
            let [r, g, b]: [Curve; 3] = out.try_into().expect("three curves");
            ([r, g, b], "user curves".to_string())
        }
    };
    let d65 = data::named_illuminant("D65").expect("D65 is embedded");
    let wb_illum = match &cam.white_balance {
        WhiteBalance::Off => None,
        WhiteBalance::Illuminant(n) => Some(data::named_illuminant(n).ok_or_else(|| {
            at.err("camera.white_balance", format!("unknown illuminant `{n}`"))
                .hint(format!(
                    "the named illuminants are: {}",
                    data::illuminant_names().join(", ")
                ))
        })?),
        WhiteBalance::Temperature(k) => {
            if !(k.is_finite() && *k >= 1000.0 && *k <= 40000.0) {
                return Err(at.err(
                    "camera.white_balance",
                    format!("colour temperature {k} K is outside 1000–40000 K"),
                ));
            }
            Some(Curve::Blackbody {
                kelvin: *k,
                scale: 1.0,
            })
        }
    };
    let m = match &wb_illum {
        Some(w) => camera::white_balance(&curves, w),
        None => glam::DVec3::ONE,
    };
    if !m.is_finite() || m.min_element() <= 0.0 {
        return Err(at.err(
            "camera.white_balance",
            "a camera channel does not respond to the white-balance illuminant",
        ));
    }
    let fit = camera::fit_matrix(
        &curves,
        m,
        wb_illum.as_ref().unwrap_or(&d65),
        &d65,
        observer.cmf(),
    );
    let exposure = match cam.exposure {
        None => 1.0,
        Some(e) => {
            for (v, f) in [
                (e.iso, "iso"),
                (e.shutter, "shutter"),
                (e.f_number, "f_number"),
            ] {
                if !(v.is_finite() && v > 0.0) {
                    return Err(at
                        .err(
                            &format!("camera.exposure.{f}"),
                            format!("{f} is {v}; it must be a positive number"),
                        )
                        .hint("e.g. exposure: (iso: 100, shutter: 0.01, f_number: 8)"));
                }
            }
            camera::exposure_scale(e.iso as f64, e.shutter as f64, e.f_number as f64)
        }
    };
    let model = CameraModel {
        name,
        white_balance: m.as_vec3(),
        exposure: exposure as f32,
        to_xyz: fit.as_mat3(),
        corrected: cam.corrected,
    };
    Ok((curves, model))
}
