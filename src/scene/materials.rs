//! Materials from the config.

use crate::bsdf::Material;
use crate::config::{spectrum_ctx, MaterialConfig, Role};
use crate::error::InputError;
use std::path::Path;

/// Builds material `name`; its spectra are checked over the render's wavelength `range`.
pub fn material(
    name: &str,
    m: &MaterialConfig,
    file: &Path,
    range: (f32, f32),
    warnings: &mut Vec<String>,
) -> Result<Material, InputError> {
    let field = format!("materials.\"{name}\"");
    Ok(match m {
        MaterialConfig::Diffuse { reflectance } => Material::Diffuse {
            reflectance: reflectance.resolve(
                Role::Reflectance,
                &spectrum_ctx(file, &format!("{field}.reflectance"), range),
                warnings,
            )?,
        },
    })
}
