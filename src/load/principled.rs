//! `Principled` materials from the config (RON); glTF materials are built in `load::gltf`.

use super::materials::float;
use crate::bsdf::{Material, PrincipledParams};
use crate::config::{FloatConfig, SpectrumConfig};
use crate::error::InputError;
use crate::load::{spectrum_ctx, Role};
use crate::spectrum::Curve;
use std::path::Path;

/// The fields of `MaterialConfig::Principled`.
pub struct Config<'a> {
    pub base_color: &'a SpectrumConfig,
    pub metallic: &'a FloatConfig,
    pub roughness: &'a FloatConfig,
    pub ior: f32,
    pub specular: f32,
    pub specular_color: &'a SpectrumConfig,
    pub transmission: &'a FloatConfig,
}

/// ((ior − 1)/(ior + 1))², the dielectric's reflectance at normal incidence.
pub fn f0_from_ior(ior: f32) -> f32 {
    let r = (ior - 1.0) / (ior + 1.0);
    r * r
}

pub fn from_config(
    c: Config,
    field: &str,
    file: &Path,
    range: (f32, f32),
    warnings: &mut Vec<String>,
) -> Result<Material, InputError> {
    let sub = |s: &str| format!("{field}.{s}");
    if !(c.ior.is_finite() && c.ior >= 1.0) {
        return Err(InputError::new(file, format!("ior {} must be ≥ 1", c.ior))
            .field(sub("ior"))
            .hint("glTF's default is 1.5"));
    }
    if !(c.specular.is_finite() && (0.0..=1.0).contains(&c.specular)) {
        return Err(
            InputError::new(file, format!("specular {} is not in [0, 1]", c.specular))
                .field(sub("specular"))
                .hint("give a value from 0 to 1 (KHR_materials_specular's default is 1)"),
        );
    }
    let base_color = c.base_color.resolve_texture(
        Role::Reflectance,
        &spectrum_ctx(file, &sub("base_color"), range),
        warnings,
    )?;
    // glTF's specularColorFactor may exceed 1 (f0 is clamped to 1 afterwards), so it is read as
    // an emission-like non-negative spectrum without uplifting as an illuminant: an RGB is
    // uplifted as a (scaled) reflectance.
    let (specular_color, specular_color_max) = match c.specular_color {
        SpectrumConfig::Rgb(r, g, b) => {
            let rgb = [*r, *g, *b];
            if rgb.iter().any(|v| !(v.is_finite() && *v >= 0.0)) {
                return Err(InputError::new(
                    file,
                    format!("specular_color {rgb:?} must be finite and ≥ 0"),
                )
                .field(sub("specular_color"))
                .hint(
                    "give finite components ≥ 0 (KHR_materials_specular's default is (1, 1, 1))",
                ));
            }
            (rgb_factor(rgb), r.max(*g).max(*b))
        }
        s => {
            let curve = s.resolve(
                Role::Reflectance,
                &spectrum_ctx(file, &sub("specular_color"), range),
                warnings,
            )?;
            let max = curve.min_max(range.0, range.1).1;
            (curve, max)
        }
    };
    Ok(Material::Principled(Box::new(PrincipledParams {
        base_color,
        metallic: float(c.metallic, &sub("metallic"), file)?,
        roughness: float(c.roughness, &sub("roughness"), file)?,
        f0_ior: f0_from_ior(c.ior),
        specular_color,
        specular_color_max,
        specular: crate::texture::FloatTexture::Constant(c.specular),
        transmission: float(c.transmission, &sub("transmission"), file)?,
        specular_color_texture: None,
    })))
}

/// A non-negative RGB factor as a spectrum: uplifted as a reflectance of rgb / max, times max
/// (so factors above 1 keep their ratio).
pub fn rgb_factor(rgb: [f32; 3]) -> Curve {
    let m = rgb[0].max(rgb[1]).max(rgb[2]);
    if m <= 0.0 {
        return Curve::Constant(0.0);
    }
    if rgb[0] == rgb[1] && rgb[1] == rgb[2] {
        return Curve::Constant(m);
    }
    let scale = m.max(1.0);
    Curve::rgb_reflectance(rgb.map(|c| c / scale)).scaled(scale)
}
