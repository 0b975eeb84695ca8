//! Materials from the config.

mod interfaces;
mod scalars;

use crate::bsdf::microfacet::Microfacet;
use crate::bsdf::{
    fresnel, roughplastic, DielectricParams, DiffuseParams, Material, PlasticParams,
    RoughConductorParams, RoughDielectricParams, RoughPlasticParams, ThinDielectricParams,
    MAX_LOBES,
};
use crate::config::MaterialConfig;
use crate::error::InputError;
use crate::load::{spectrum_ctx, Role};
use crate::spectrum::Ior;
use interfaces::{conductor, plastic_eta, relative_ior, specular, specular_weight};
pub(super) use scalars::float;
use scalars::{check_alpha, roughnesses};
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
    let mat = build(m, &field, file, range, warnings)?;
    if mat.max_lobes() > MAX_LOBES {
        return Err(InputError::new(file, format!("this material combines {} BSDFs; at most {MAX_LOBES} can be blended or masked together", mat.max_lobes()))
            .field(field)
            .hint("flatten nested Blend/Mask materials"));
    }
    Ok(mat)
}

fn build(
    m: &MaterialConfig,
    field: &str,
    file: &Path,
    range: (f32, f32),
    warnings: &mut Vec<String>,
) -> Result<Material, InputError> {
    let ctx = |sub: &str| format!("{field}.{sub}");
    Ok(match m {
        MaterialConfig::Diffuse { reflectance } => Material::Diffuse(DiffuseParams {
            reflectance: reflectance.resolve_texture(
                Role::Reflectance,
                &spectrum_ctx(file, &ctx("reflectance"), range),
                warnings,
            )?,
        }),
        MaterialConfig::Twosided { bsdf, back } => {
            let front = build(bsdf, &ctx("bsdf"), file, range, warnings)?;
            let back = match back {
                Some(b) => build(b, &ctx("back"), file, range, warnings)?,
                None => front.clone(),
            };
            Material::Twosided {
                front: Box::new(front),
                back: Box::new(back),
            }
        }
        MaterialConfig::Blend {
            weight,
            bsdf0,
            bsdf1,
        } => Material::Blend {
            a: Box::new(build(bsdf0, &ctx("bsdf0"), file, range, warnings)?),
            b: Box::new(build(bsdf1, &ctx("bsdf1"), file, range, warnings)?),
            weight: float(weight, &ctx("weight"), file)?,
        },
        MaterialConfig::Mask { opacity, bsdf } => Material::Mask {
            inner: Box::new(build(bsdf, &ctx("bsdf"), file, range, warnings)?),
            opacity: float(opacity, &ctx("opacity"), file)?,
        },
        // Conductors.
        MaterialConfig::RoughConductor {
            distribution,
            alpha,
            alpha_u,
            alpha_v,
            material,
            eta,
            k,
            specular_reflectance,
        } => {
            let (alpha_u, alpha_v) = roughnesses(alpha, alpha_u, alpha_v, field, file)?;
            Material::RoughConductor(RoughConductorParams {
                params: conductor(
                    material.as_deref(),
                    eta.as_ref(),
                    k.as_ref(),
                    specular_reflectance,
                    field,
                    file,
                    range,
                    warnings,
                )?,
                distribution: *distribution,
                alpha_u,
                alpha_v,
            })
        }
        MaterialConfig::Principled {
            base_color,
            metallic,
            roughness,
            ior,
            specular,
            specular_color,
            transmission,
        } => super::principled::from_config(
            super::principled::Config {
                base_color,
                metallic,
                roughness,
                ior: *ior,
                specular: *specular,
                specular_color,
                transmission,
            },
            field,
            file,
            range,
            warnings,
        )?,
        MaterialConfig::Conductor {
            material,
            eta,
            k,
            specular_reflectance,
        } => Material::Conductor(conductor(
            material.as_deref(),
            eta.as_ref(),
            k.as_ref(),
            specular_reflectance,
            field,
            file,
            range,
            warnings,
        )?),
        // Dielectrics.
        MaterialConfig::Dielectric {
            int_ior,
            ext_ior,
            specular_reflectance,
            specular_transmittance,
        } => {
            let (r, t) = specular(
                specular_reflectance,
                specular_transmittance,
                field,
                file,
                range,
                warnings,
            )?;
            Material::Dielectric(DielectricParams {
                ior: relative_ior(int_ior, ext_ior, field, file, range)?,
                specular_reflectance: r,
                specular_transmittance: t,
            })
        }
        MaterialConfig::RoughDielectric {
            distribution,
            alpha,
            alpha_u,
            alpha_v,
            int_ior,
            ext_ior,
            specular_reflectance,
            specular_transmittance,
        } => {
            let ior = relative_ior(int_ior, ext_ior, field, file, range)?;
            if let (Ior::Constant(a), Ior::Constant(b)) = (&ior.int, &ior.ext) {
                if a == b {
                    return Err(InputError::new(file, format!("int_ior and ext_ior are both {a}: a rough interface needs different indices (as in Mitsuba)"))
                        .field(field)
                        .hint("an index-matched interface is invisible; leave the shape out, or use Mask(opacity: 0, ...)"));
                }
            }
            let (alpha_u, alpha_v) = roughnesses(alpha, alpha_u, alpha_v, field, file)?;
            let (r, t) = specular(
                specular_reflectance,
                specular_transmittance,
                field,
                file,
                range,
                warnings,
            )?;
            Material::RoughDielectric(RoughDielectricParams {
                ior,
                distribution: *distribution,
                alpha_u,
                alpha_v,
                specular_reflectance: r,
                specular_transmittance: t,
            })
        }
        MaterialConfig::ThinDielectric {
            int_ior,
            ext_ior,
            specular_reflectance,
            specular_transmittance,
        } => {
            let (r, t) = specular(
                specular_reflectance,
                specular_transmittance,
                field,
                file,
                range,
                warnings,
            )?;
            Material::ThinDielectric(ThinDielectricParams {
                ior: relative_ior(int_ior, ext_ior, field, file, range)?,
                specular_reflectance: r,
                specular_transmittance: t,
            })
        }
        // Plastics.
        MaterialConfig::Plastic {
            diffuse_reflectance,
            specular_reflectance,
            int_ior,
            ext_ior,
            nonlinear,
        } => {
            let eta = plastic_eta(int_ior, ext_ior, field, file, range)?;
            let diffuse = diffuse_reflectance.resolve_texture(
                Role::Reflectance,
                &spectrum_ctx(file, &ctx("diffuse_reflectance"), range),
                warnings,
            )?;
            let specular = specular_reflectance.resolve_texture(
                Role::Reflectance,
                &spectrum_ctx(file, &ctx("specular_reflectance"), range),
                warnings,
            )?;
            Material::Plastic(PlasticParams {
                specular_weight: specular_weight(&diffuse, &specular, range),
                diffuse,
                specular,
                eta,
                internal: fresnel::dielectric_average(1.0 / eta),
                nonlinear: *nonlinear,
            })
        }
        MaterialConfig::RoughPlastic {
            distribution,
            alpha,
            diffuse_reflectance,
            specular_reflectance,
            int_ior,
            ext_ior,
            nonlinear,
        } => {
            let eta = plastic_eta(int_ior, ext_ior, field, file, range)?;
            check_alpha(*alpha, &ctx("alpha"), file)?;
            let microfacet = Microfacet::new(*distribution, *alpha, *alpha);
            let diffuse = diffuse_reflectance.resolve_texture(
                Role::Reflectance,
                &spectrum_ctx(file, &ctx("diffuse_reflectance"), range),
                warnings,
            )?;
            let specular = specular_reflectance.resolve_texture(
                Role::Reflectance,
                &spectrum_ctx(file, &ctx("specular_reflectance"), range),
                warnings,
            )?;
            Material::RoughPlastic(RoughPlasticParams {
                specular_weight: specular_weight(&diffuse, &specular, range),
                diffuse,
                specular,
                eta,
                transmittance: roughplastic::transmittance_table(&microfacet, eta),
                internal: roughplastic::internal_reflectance(&microfacet, eta),
                microfacet,
                nonlinear: *nonlinear,
            })
        }
    })
}
