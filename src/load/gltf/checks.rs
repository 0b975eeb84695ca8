//! Range checks of a glTF file's numbers, on its JSON before the crate reads it: the crate checks
//! indices and enums but not values, and a factor outside the specification's range (a metallic
//! factor of 5, an emissive strength of 1e39 that is infinite in f32, an index of refraction of
//! 1e-45) would render nonsense or NaN. Each error names the JSON field, the value, the range
//! the glTF 2.0 specification (or the extension's) gives and the fix.
//! The forms of accessors and images, which the crate unwraps or asserts, are checked in
//! `checks/forms.rs`.

mod forms;

use super::err;
use crate::config::{MAX_EMISSION, MAX_IOR};
use crate::error::InputError;
use forms::check_forms;
use serde_json::Value;
use std::path::Path;

/// A closed or half-open range of a number.
#[derive(Clone, Copy)]
enum Range {
    /// lo ≤ x ≤ hi.
    Closed(f32, f32),
    /// lo < x ≤ hi.
    AboveTo(f32, f32),
}

const UNIT: Range = Range::Closed(0.0, 1.0);
/// Non-negative, and small enough that products with radiance stay finite in f32.
const NON_NEG: Range = Range::Closed(0.0, MAX_EMISSION);
const POSITIVE: Range = Range::AboveTo(0.0, MAX_EMISSION);

impl Range {
    fn holds(self, x: f32) -> bool {
        match self {
            Range::Closed(lo, hi) => (lo..=hi).contains(&x),
            Range::AboveTo(lo, hi) => x > lo && x <= hi,
        }
    }
    fn describe(self) -> String {
        match self {
            Range::Closed(lo, hi) if hi == MAX_EMISSION => format!("≥ {lo}"),
            Range::AboveTo(lo, hi) if hi == MAX_EMISSION => format!("> {lo}"),
            Range::Closed(lo, hi) => format!("in [{lo}, {hi}]"),
            Range::AboveTo(lo, hi) => format!("in ({lo}, {hi}]"),
        }
    }
}

struct Checker<'a> {
    path: &'a Path,
}

impl Checker<'_> {
    /// The number at `field` of `obj` (absent: fine, the default applies), or each number of
    /// the array there, within `range`.
    fn number(&self, obj: &Value, at: &str, key: &str, range: Range) -> Result<(), InputError> {
        let Some(v) = obj.get(key) else {
            return Ok(());
        };
        let values: Vec<(String, &Value)> = match v {
            Value::Array(a) => a
                .iter()
                .enumerate()
                .map(|(i, x)| (format!("{at}.{key}[{i}]"), x))
                .collect(),
            x => vec![(format!("{at}.{key}"), x)],
        };
        for (field, x) in values {
            // Not a number: the crate's own parse reports it with its type.
            let Some(f) = x.as_f64() else { continue };
            let single = f as f32;
            if !single.is_finite() || !range.holds(single) {
                return Err(err(
                    self.path,
                    field,
                    format!(
                        "{f} is out of range: glTF 2.0 wants a value {}",
                        range.describe()
                    ),
                )
                .hint("fix the value in the file (the exporter wrote an invalid one), or check the file with the Khronos glTF validator"));
            }
        }
        Ok(())
    }

    /// A texture reference's scale/strength and its KHR_texture_transform.
    fn texture(&self, obj: &Value, at: &str, key: &str) -> Result<(), InputError> {
        let Some(t) = obj.get(key) else {
            return Ok(());
        };
        let at = format!("{at}.{key}");
        self.number(t, &at, "scale", Range::Closed(-MAX_EMISSION, MAX_EMISSION))?;
        self.number(t, &at, "strength", UNIT)?;
        if let Some(tt) = t.pointer("/extensions/KHR_texture_transform") {
            let at = format!("{at}.extensions.KHR_texture_transform");
            let any = Range::Closed(-1e6, 1e6);
            for k in ["offset", "rotation", "scale"] {
                self.number(tt, &at, k, any)?;
            }
        }
        Ok(())
    }

    fn material(&self, m: &Value, at: &str) -> Result<(), InputError> {
        if let Some(pbr) = m.get("pbrMetallicRoughness") {
            let p = format!("{at}.pbrMetallicRoughness");
            self.number(pbr, &p, "baseColorFactor", UNIT)?;
            self.number(pbr, &p, "metallicFactor", UNIT)?;
            self.number(pbr, &p, "roughnessFactor", UNIT)?;
            self.texture(pbr, &p, "baseColorTexture")?;
            self.texture(pbr, &p, "metallicRoughnessTexture")?;
        }
        self.number(m, at, "emissiveFactor", UNIT)?;
        self.number(m, at, "alphaCutoff", NON_NEG)?;
        for t in ["normalTexture", "occlusionTexture", "emissiveTexture"] {
            self.texture(m, at, t)?;
        }
        let Some(ext) = m.get("extensions") else {
            return Ok(());
        };
        let x = |name: &str| (ext.get(name), format!("{at}.extensions.{name}"));
        if let (Some(e), p) = x("KHR_materials_emissive_strength") {
            self.number(e, &p, "emissiveStrength", NON_NEG)?;
        }
        if let (Some(e), p) = x("KHR_materials_ior") {
            // 0 is the specification's "F0 = 1"; otherwise ≥ 1, and within prism's bound.
            if e.get("ior").and_then(Value::as_f64) != Some(0.0) {
                self.number(e, &p, "ior", Range::Closed(1.0, MAX_IOR))?;
            }
        }
        if let (Some(e), p) = x("KHR_materials_transmission") {
            self.number(e, &p, "transmissionFactor", UNIT)?;
            self.texture(e, &p, "transmissionTexture")?;
        }
        if let (Some(e), p) = x("KHR_materials_specular") {
            self.number(e, &p, "specularFactor", UNIT)?;
            self.number(e, &p, "specularColorFactor", NON_NEG)?;
            self.texture(e, &p, "specularTexture")?;
            self.texture(e, &p, "specularColorTexture")?;
        }
        if let (Some(e), p) = x("KHR_materials_volume") {
            self.number(e, &p, "thicknessFactor", NON_NEG)?;
            self.number(e, &p, "attenuationDistance", POSITIVE)?;
            self.number(e, &p, "attenuationColor", UNIT)?;
        }
        if let (Some(e), p) = x("KHR_materials_dispersion") {
            // 20 / Abbe number: 0 (none) to 20 / 5 = 4, past the most dispersive glasses
            // (V_d ≈ 17); beyond, the Cauchy fit's index leaves the physical range.
            self.number(e, &p, "dispersion", Range::Closed(0.0, 4.0))?;
        }
        Ok(())
    }

    fn camera(&self, c: &Value, at: &str) -> Result<(), InputError> {
        if let Some(p) = c.get("perspective") {
            let at = format!("{at}.perspective");
            // Below π: tan(yfov / 2) must be finite.
            self.number(
                p,
                &at,
                "yfov",
                Range::AboveTo(0.0, std::f32::consts::PI - 1e-3),
            )?;
            self.number(p, &at, "aspectRatio", POSITIVE)?;
            self.number(p, &at, "znear", POSITIVE)?;
            self.number(p, &at, "zfar", POSITIVE)?;
        }
        if let Some(o) = c.get("orthographic") {
            let at = format!("{at}.orthographic");
            // The specification forbids 0; a negative magnification mirrors (allowed).
            for k in ["xmag", "ymag"] {
                self.number(o, &at, k, Range::Closed(-MAX_EMISSION, MAX_EMISSION))?;
                if o.get(k).and_then(Value::as_f64) == Some(0.0) {
                    return Err(err(self.path, format!("{at}.{k}"), "an orthographic magnification of 0 shows nothing")
                        .hint("give the half-width (xmag) and half-height (ymag) of the view, in scene units"));
                }
            }
            self.number(o, &at, "znear", NON_NEG)?;
            self.number(o, &at, "zfar", POSITIVE)?;
        }
        Ok(())
    }

    fn light(&self, l: &Value, at: &str) -> Result<(), InputError> {
        self.number(l, at, "color", UNIT)?;
        self.number(l, at, "intensity", NON_NEG)?;
        self.number(l, at, "range", POSITIVE)?;
        if let Some(s) = l.get("spot") {
            let p = format!("{at}.spot");
            let half_pi = std::f32::consts::FRAC_PI_2;
            self.number(s, &p, "innerConeAngle", Range::Closed(0.0, half_pi))?;
            self.number(s, &p, "outerConeAngle", Range::AboveTo(0.0, half_pi))?;
            let inner = s
                .get("innerConeAngle")
                .and_then(Value::as_f64)
                .unwrap_or(0.0);
            let outer = s
                .get("outerConeAngle")
                .and_then(Value::as_f64)
                .unwrap_or(std::f64::consts::FRAC_PI_4);
            if inner >= outer {
                return Err(err(
                    self.path,
                    format!("{p}.innerConeAngle"),
                    format!("the inner cone angle {inner} is not below the outer one {outer}"),
                )
                .hint(
                    "glTF spot lights need 0 ≤ innerConeAngle < outerConeAngle ≤ π/2 (radians)",
                ));
            }
        }
        Ok(())
    }
}

/// Checks every material, camera and punctual light of the glTF JSON `json` read from `path`,
/// and the forms of its accessors and images.
pub fn check_values(path: &Path, json: &Value) -> Result<(), InputError> {
    check_forms(path, json)?;
    let c = Checker { path };
    let each = |key: &str| -> Vec<(String, &Value)> {
        json.get(key)
            .and_then(Value::as_array)
            .map(|a| {
                a.iter()
                    .enumerate()
                    .map(|(i, v)| (format!("{key}[{i}]"), v))
                    .collect()
            })
            .unwrap_or_default()
    };
    for (at, m) in each("materials") {
        c.material(m, &at)?;
    }
    for (at, cam) in each("cameras") {
        c.camera(cam, &at)?;
    }
    let lights = json
        .pointer("/extensions/KHR_lights_punctual/lights")
        .and_then(Value::as_array);
    for (i, l) in lights.into_iter().flatten().enumerate() {
        c.light(l, &format!("extensions.KHR_lights_punctual.lights[{i}]"))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(doc: &str) -> Result<(), String> {
        let v: Value = serde_json::from_str(doc).unwrap();
        check_values(Path::new("m.gltf"), &v).map_err(|e| e.to_string())
    }

    /// Values inside the ranges pass; each kind of value outside fails naming its field.
    #[test]
    fn out_of_range_values_are_named() {
        check(r#"{"materials": [{"pbrMetallicRoughness": {"baseColorFactor": [1, 0.5, 0, 1], "metallicFactor": 1}, "extensions": {"KHR_materials_ior": {"ior": 0}, "KHR_materials_dispersion": {"dispersion": 1}}}],
                  "cameras": [{"type": "orthographic", "orthographic": {"xmag": -1, "ymag": 1, "znear": 0, "zfar": 10}}],
                  "extensions": {"KHR_lights_punctual": {"lights": [{"type": "spot", "intensity": 5, "spot": {"innerConeAngle": 0.1}}]}}}"#).unwrap();
        for (doc, field) in [
            (
                r#"{"materials": [{}, {"pbrMetallicRoughness": {"metallicFactor": 5}}]}"#,
                "materials[1].pbrMetallicRoughness.metallicFactor",
            ),
            (
                r#"{"materials": [{"pbrMetallicRoughness": {"baseColorFactor": [1, 1, -0.1, 1]}}]}"#,
                "baseColorFactor[2]",
            ),
            (
                r#"{"materials": [{"extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 1e39}}}]}"#,
                "emissiveStrength",
            ),
            (
                r#"{"materials": [{"extensions": {"KHR_materials_ior": {"ior": 1e-45}}}]}"#,
                "KHR_materials_ior.ior",
            ),
            (
                r#"{"materials": [{"extensions": {"KHR_materials_dispersion": {"dispersion": 1e6}}}]}"#,
                "dispersion",
            ),
            (
                r#"{"materials": [{"normalTexture": {"index": 0, "extensions": {"KHR_texture_transform": {"scale": [1e39, 1]}}}}]}"#,
                "normalTexture.extensions.KHR_texture_transform.scale[0]",
            ),
            (
                r#"{"cameras": [{"perspective": {"yfov": 0, "znear": 0.1}}]}"#,
                "cameras[0].perspective.yfov",
            ),
            (
                r#"{"cameras": [{"orthographic": {"xmag": 0, "ymag": 1}}]}"#,
                "cameras[0].orthographic.xmag",
            ),
            (
                r#"{"extensions": {"KHR_lights_punctual": {"lights": [{"intensity": -1}]}}}"#,
                "lights[0].intensity",
            ),
            (
                r#"{"extensions": {"KHR_lights_punctual": {"lights": [{"spot": {"innerConeAngle": 0.5, "outerConeAngle": 0.4}}]}}}"#,
                "lights[0].spot.innerConeAngle",
            ),
        ] {
            let e = check(doc).unwrap_err();
            assert!(e.contains(field) && e.contains("m.gltf"), "{field}: {e}");
        }
    }
}
