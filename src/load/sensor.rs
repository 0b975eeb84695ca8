//! From the scene's `sensor:` (or its older `outputs:`) to a `Sensor`, with every check a
//! user's mistake can trip reported against the file and the field.

mod band_groups;
mod camera_model;
mod raw;

use crate::config::sensor::{BandConfig, NamedSensor, SensorConfig, SensorField, SensorFile};
use crate::config::OutputConfig;
use crate::error::InputError;
use crate::sensor::bands::{Response, Shape};
use crate::sensor::{Layers, Observer, RgbSpace, Sensor};
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
        // A caller's own hint replaces this pointer to the documentation.
        let field = self.field(field);
        let hint = format!("configs/README.md documents `{field}` (sensors)");
        InputError::new(self.file, message).field(field).hint(hint)
    }
}

/// Reads a sensor file (RON, a `SensorConfig`).
pub fn read_file(path: &Path) -> Result<SensorConfig, InputError> {
    crate::io::inputs::record(path);
    use crate::io::input_file::{self, Kind};
    let hint =
        "sensor files are relative to the scene file (`--sensor` paths to the current directory)";
    let bytes = input_file::read(path, Kind::Sensor).map_err(|e| {
        InputError::new(path, format!("cannot read the sensor file: {e}")).hint(hint)
    })?;
    let text = String::from_utf8(bytes).map_err(|e| {
        InputError::new(
            path,
            format!(
                "the sensor file is not UTF-8 text (byte {})",
                e.utf8_error().valid_up_to()
            ),
        )
        .hint("save the sensor file as UTF-8 text")
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
            field(s, scene, "sensor", range, warnings)
        }
    }
}

/// A sensor field of `scene` at `prefix` (`sensor`, `sensors[1].sensor`): inline or a file.
fn field(
    s: &SensorField,
    scene: &Path,
    prefix: &str,
    range: (f32, f32),
    warnings: &mut Vec<String>,
) -> Result<Sensor, InputError> {
    match s {
        SensorField::Inline(cfg) => from_config(
            cfg,
            &At {
                file: scene,
                prefix,
            },
            range,
            warnings,
        ),
        SensorField::Empty(()) => from_config(
            &SensorConfig::default(),
            &At {
                file: scene,
                prefix,
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

/// `main` with the scene's further `sensors` on the same samples (src/sensor/multi.rs), each
/// name checked: a lowercase word, listed once, and no prefix the main sensor's channels or
/// the AOV layers use (so every EXR channel name stays unique).
pub fn with_extras(
    main: Sensor,
    list: &[NamedSensor],
    scene: &Path,
    range: (f32, f32),
    warnings: &mut Vec<String>,
) -> Result<Sensor, InputError> {
    let mut taken: BTreeSet<String> = main
        .own_channel_names()
        .iter()
        .map(|n| n.split('.').next().unwrap_or(n).to_string())
        .collect();
    taken.extend(["raw", "camera", "corrected"].map(String::from));
    let mut extras = Vec::new();
    for (i, ns) in list.iter().enumerate() {
        let at = format!("sensors[{i}]");
        let n = &ns.name;
        let word = n.starts_with(|c: char| c.is_ascii_lowercase())
            && n.chars()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_');
        let problem = if !word {
            Some(format!("the sensor name \"{n}\" is not a lowercase word"))
        } else if crate::film::Aov::parse(n).is_some() || taken.contains(n) {
            Some(format!(
                "the sensor name \"{n}\" is already a channel prefix of this render"
            ))
        } else if list[..i].iter().any(|o| o.name == *n) {
            Some(format!("two sensors are named \"{n}\""))
        } else {
            None
        };
        if let Some(m) = problem {
            return Err(InputError::new(scene, m)
                .field(format!("{at}.name"))
                .hint("name each sensor with a distinct lowercase word such as \"nikon\" or \"hsi\" (a-z, 0-9, _), not an AOV's or a channel layer's name"));
        }
        let sensor = field(&ns.sensor, scene, &format!("{at}.sensor"), range, warnings)?;
        extras.push((n.clone(), sensor));
    }
    Ok(main.with_extras(extras))
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
    let default_bands = [BandConfig::Even {
        count: None,
        range: None,
    }];
    let groups = cfg.bands.as_deref().unwrap_or(&default_bands);
    let band_groups::SpectralBands {
        even,
        mut responses,
        names,
    } = band_groups::spectral_bands(groups, at, range, warnings)?;
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
        let (curves, model) = camera_model::camera_model(cam, at, range, cfg.observer, warnings)?;
        if let Some(r) = &cfg.raw {
            let err = |f: &str, m: String, fix: &str| {
                let field = if f.is_empty() {
                    "raw".to_string()
                } else {
                    format!("raw.{f}")
                };
                at.err(&field, m).hint(fix)
            };
            raw = Some(raw::build(r, &curves, cam.exposure, range, &err)?);
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
    let raw = raw.map(|r: raw::RawSetup| {
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
    sensor.raw = raw.map(|m| crate::sensor::raw::RawModel {
        slot: sensor.slots() - 3,
        ..m
    });
    Ok(sensor)
}
