//! The names of `scene.params`: a scene's changeable values, named as the dataset config
//! targets them (configs/README.md), read from and written into its parsed config.
//!
//! - `materials.<name>.reflectance` (a spectrum), `.roughness` (α), `.ior` (interior index);
//! - `lights.<shape name>.radiance` (a named shape's area light), `lights.emitters[i].<field>`
//!   (the scene's i-th emitter: `intensity`, `radiance`, `irradiance`, or an envmap's `scale`);
//! - `camera.fov`, `camera.to_world` (a list of transform steps);
//! - `sensor.exposure`: stops e, the sensor's channels scaled by 2^e as a dataset frame's.
//!
//! Values are the RON schema in serde's JSON form, as `load_dict` takes them.

use prism_core::config::{EmitterConfig, MaterialConfig, Roughness, SceneConfig};
use prism_core::dataset::apply;
use prism_core::error::InputError;
use serde_json::{json, Value};
use std::path::Path;

/// The largest exposure in stops: 2^49 stays inside the exposure factor's range [1e-15, 1e15].
const MAX_STOPS: f32 = 49.0;

/// Every parameter of `cfg`, in a stable order.
pub fn names(cfg: &SceneConfig) -> Vec<String> {
    let mut out = Vec::new();
    for (name, m) in &cfg.materials {
        let mut m = m.clone();
        if apply::reflectance_slot(&mut m).is_some() {
            out.push(format!("materials.{name}.reflectance"));
        }
        if roughness(&m).is_some() {
            out.push(format!("materials.{name}.roughness"));
        }
        if ior(&m).is_some() {
            out.push(format!("materials.{name}.ior"));
        }
    }
    for s in &cfg.shapes {
        if let (Some(name), Some(_)) = (&s.name, &s.emitter) {
            out.push(format!("lights.{name}.radiance"));
        }
    }
    for (i, e) in cfg.emitters.iter().enumerate() {
        out.push(format!("lights.emitters[{i}].{}", emitter_field(e)));
    }
    out.extend(["camera.fov", "camera.to_world", "sensor.exposure"].map(String::from));
    out
}

/// The value of parameter `name` (`exposure`: the scene's current stops).
pub fn get(cfg: &SceneConfig, exposure: f32, name: &str, file: &Path) -> Result<Value, InputError> {
    let v = match slot(cfg, name, file)? {
        Slot::Reflectance(m) => {
            let mut m = cfg.materials[&m].clone();
            json!(apply::reflectance_slot(&mut m))
        }
        Slot::Roughness(m) => json!(roughness(&cfg.materials[&m])),
        Slot::Ior(m) => json!(ior(&cfg.materials[&m])),
        Slot::AreaLight(i) => json!(cfg.shapes[i].emitter.as_ref().map(|e| &e.radiance)),
        Slot::Emitter(i) => match &cfg.emitters[i] {
            EmitterConfig::Point { intensity: s, .. }
            | EmitterConfig::Spot { intensity: s, .. }
            | EmitterConfig::Constant { radiance: s }
            | EmitterConfig::Directional { irradiance: s, .. } => json!(s),
            EmitterConfig::Envmap { scale, .. } => json!(scale),
        },
        Slot::Fov => json!(cfg.camera.fov),
        Slot::ToWorld => json!(cfg.camera.to_world),
        Slot::Exposure => json!(exposure),
    };
    Ok(v)
}

/// Writes `value` into parameter `name` of `cfg` (or `exposure`). The range checks are the
/// scene build's, which the caller runs next.
pub fn set(
    cfg: &mut SceneConfig,
    exposure: &mut f32,
    name: &str,
    value: Value,
    file: &Path,
) -> Result<(), InputError> {
    let slot = slot(cfg, name, file)?;
    let bad = |e: serde_json::Error, what: &str| {
        let msg = e.to_string();
        let msg = msg.split(" at line ").next().unwrap_or(&msg).to_string();
        InputError::new(file, msg)
            .field(format!("params[\"{name}\"]"))
            .hint(format!("give {what}"))
    };
    const SPECTRUM: &str = "a spectrum as load_dict takes it, e.g. {\"Rgb\": [0.8, 0.2, 0.1]}, \
                            {\"Constant\": 0.5} or {\"Named\": \"D65\"}";
    let spectrum = |v| serde_json::from_value(v).map_err(|e| bad(e, SPECTRUM));
    let number = |v: Value| -> Result<f32, InputError> {
        serde_json::from_value(v).map_err(|e| bad(e, "a number"))
    };
    match slot {
        Slot::Reflectance(m) => {
            let m = cfg.materials.get_mut(&m).expect("slot checked");
            *apply::reflectance_slot(m).expect("slot checked") = spectrum(value)?;
        }
        Slot::Roughness(m) => {
            let a = number(value)?;
            apply::set_roughness(cfg.materials.get_mut(&m).expect("slot checked"), a);
        }
        Slot::Ior(m) => {
            let n = number(value)?;
            apply::set_ior(cfg.materials.get_mut(&m).expect("slot checked"), n);
        }
        Slot::AreaLight(i) => {
            cfg.shapes[i].emitter.as_mut().expect("slot checked").radiance = spectrum(value)?;
        }
        Slot::Emitter(i) => match apply::emitter_slot(&mut cfg.emitters[i]) {
            apply::EmitterSlot::Spectrum(s) => *s = spectrum(value)?,
            apply::EmitterSlot::Scale(s) => *s = number(value)?,
        },
        Slot::Fov => cfg.camera.fov = number(value)?,
        Slot::ToWorld => {
            cfg.camera.to_world = serde_json::from_value(value).map_err(|e| {
                bad(e, "a list of transform steps, e.g. [{\"LookAt\": {\"origin\": [0, 1, 4], \"target\": [0, 0, 0], \"up\": [0, 1, 0]}}]")
            })?
        }
        Slot::Exposure => {
            let e = number(value)?;
            if !(e.is_finite() && e.abs() <= MAX_STOPS) {
                return Err(InputError::new(
                    file,
                    format!("exposure {e} stops lies outside [-{MAX_STOPS}, {MAX_STOPS}]"),
                )
                .field(format!("params[\"{name}\"]"))
                .hint("give a finite number of stops such as -1.5; 0 leaves the channels as rendered"));
            }
            *exposure = e;
        }
    }
    Ok(())
}

/// Where a parameter lives in the config.
enum Slot {
    Reflectance(String),
    Roughness(String),
    Ior(String),
    /// shapes[i]'s area light.
    AreaLight(usize),
    /// emitters[i].
    Emitter(usize),
    Fov,
    ToWorld,
    Exposure,
}

/// The slot `name` names in `cfg`, or an error listing the names there are.
fn slot(cfg: &SceneConfig, name: &str, file: &Path) -> Result<Slot, InputError> {
    let found = match name {
        "camera.fov" => Some(Slot::Fov),
        "camera.to_world" => Some(Slot::ToWorld),
        "sensor.exposure" => Some(Slot::Exposure),
        _ => None,
    };
    let found = found.or_else(|| {
        let (mat, field) = name.strip_prefix("materials.")?.rsplit_once('.')?;
        let m = cfg.materials.get(mat)?;
        let s = match field {
            "reflectance" => apply::reflectance_slot(&mut m.clone()).map(|_| ()),
            "roughness" => roughness(m).map(|_| ()),
            "ior" => ior(m).map(|_| ()),
            _ => None,
        };
        s?;
        Some(match field {
            "reflectance" => Slot::Reflectance(mat.into()),
            "roughness" => Slot::Roughness(mat.into()),
            _ => Slot::Ior(mat.into()),
        })
    });
    let found = found.or_else(|| {
        let (target, field) = name.strip_prefix("lights.")?.rsplit_once('.')?;
        if let Some(i) = target.strip_prefix("emitters[")?.strip_suffix(']') {
            let i: usize = i.parse().ok()?;
            return (field == emitter_field(cfg.emitters.get(i)?)).then_some(Slot::Emitter(i));
        }
        None
    });
    let found = found.or_else(|| {
        let (target, field) = name.strip_prefix("lights.")?.rsplit_once('.')?;
        let i = cfg
            .shapes
            .iter()
            .position(|s| s.name.as_deref() == Some(target) && s.emitter.is_some())?;
        (field == "radiance").then_some(Slot::AreaLight(i))
    });
    found.ok_or_else(|| {
        InputError::new(file, format!("the scene has no parameter \"{name}\""))
            .field("params")
            .hint(format!("the parameters are: {}", names(cfg).join(", ")))
    })
}

/// The field a dataset's light `intensity` scales in emitter `e`.
fn emitter_field(e: &EmitterConfig) -> &'static str {
    match e {
        EmitterConfig::Point { .. } | EmitterConfig::Spot { .. } => "intensity",
        EmitterConfig::Constant { .. } => "radiance",
        EmitterConfig::Directional { .. } => "irradiance",
        EmitterConfig::Envmap { .. } => "scale",
    }
}

/// A material's roughness α as its config says it (None: it has none).
fn roughness(m: &MaterialConfig) -> Option<Value> {
    m.roughness().map(|r| match r {
        Roughness::Value(a) => json!(a),
        Roughness::Float(a) => json!(a),
        Roughness::Anisotropic(u, v) => json!({"alpha_u": u, "alpha_v": v}),
    })
}

/// A material's interior IOR as its config says it (None: it has none).
fn ior(m: &MaterialConfig) -> Option<Value> {
    m.int_ior().map(|n| json!(n))
}
