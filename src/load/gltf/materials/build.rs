//! One glTF material built: the metallic-roughness model as `Principled` (with its extensions'
//! factors and textures), a dispersive glass as a dielectric (`dispersion_abbe`), alpha MASK
//! and BLEND as a `Mask`, and its emission.

use super::texels::{grid, rgba, texture_sets, uv_map};
use super::GltfMaterials;
use crate::bsdf::microfacet::Distribution;
use crate::bsdf::{
    DielectricParams, Material, PrincipledParams, RoughDielectricParams, SpecularColorTexture,
};
use crate::emitter::AreaRadiance;
use crate::error::InputError;
use crate::load::gltf::{colors, emission, unread};
use crate::load::principled::{f0_from_ior, rgb_factor};
use crate::spectrum::{rgb2spec, Curve, Ior, RelativeIor};
use crate::texture::{srgb_decode, FloatTexture, Grid, SpectralTexture, TexFilter};

/// Converts glTF's KHR_materials_dispersion (20 / V_d) and the index at the d line into a
/// Cauchy index n = A + B/λ² (λ in µm) with the same n_d and Abbe number
/// V_d = (n_d − 1)/(n_F − n_C), Fraunhofer lines d 587.56, F 486.13, C 656.27 nm.
pub fn dispersion_abbe(ior: f32, dispersion: f32) -> Ior {
    let abbe = 20.0 / dispersion;
    let (d, f, c) = (0.587_56f32, 0.486_13f32, 0.656_27f32);
    let b = (ior - 1.0) / (abbe * (1.0 / (f * f) - 1.0 / (c * c)));
    Ior::Cauchy {
        a: ior - b / (d * d),
        b,
    }
}

impl GltfMaterials<'_> {
    pub(super) fn build(
        &self,
        m: &gltf::Material,
        vertex: Option<(&[[[f32; 4]; 3]], bool)>,
        warn: &mut Vec<String>,
    ) -> Result<(Material, Option<AreaRadiance>), InputError> {
        let label = match (m.index(), m.name()) {
            (Some(i), Some(n)) => format!("materials[{i}] (\"{n}\")"),
            (Some(i), None) => format!("materials[{i}]"),
            _ => "the default material".to_string(),
        };
        let pbr = m.pbr_metallic_roughness();
        let bc = pbr.base_color_factor();
        let mut alpha_tex: Option<Grid<f32>> = None;
        let base_color = match pbr.base_color_texture() {
            Some(info) => {
                let tex = info.texture();
                let img = self.image(&tex);
                let map = uv_map(&info);
                let px = rgba(img);
                // The factor multiplies the decoded texel; the product is uplifted.
                let texels = px
                    .iter()
                    .map(|p| {
                        rgb2spec::fetch(
                            [0, 1, 2].map(|k| (srgb_decode(p[k]) * bc[k]).clamp(0.0, 1.0)),
                        )
                    })
                    .collect();
                alpha_tex = Some(grid(
                    img,
                    px.iter().map(|p| p[3] * bc[3]).collect(),
                    &tex,
                    map,
                ));
                SpectralTexture::Bitmap(Box::new(grid(img, texels, &tex, map)))
            }
            None => SpectralTexture::Uniform(rgb_factor(
                [bc[0], bc[1], bc[2]].map(|c| c.clamp(0.0, 1.0)),
            )),
        };
        let base_color = match vertex {
            Some((corners, _)) => colors::tint(base_color, bc, corners),
            None => base_color,
        };
        let (metal_f, rough_f) = (pbr.metallic_factor(), pbr.roughness_factor());
        let (metallic, roughness) = match pbr.metallic_roughness_texture() {
            Some(info) => {
                let tex = info.texture();
                let img = self.image(&tex);
                let map = uv_map(&info);
                let px = rgba(img);
                (
                    FloatTexture::Bitmap(Box::new(grid(
                        img,
                        px.iter().map(|p| p[2] * metal_f).collect(),
                        &tex,
                        map,
                    ))),
                    FloatTexture::Bitmap(Box::new(grid(
                        img,
                        px.iter().map(|p| p[1] * rough_f).collect(),
                        &tex,
                        map,
                    ))),
                )
            }
            None => (
                FloatTexture::Constant(metal_f),
                FloatTexture::Constant(rough_f),
            ),
        };
        let ior = m.ior().unwrap_or(1.5);
        let (specular, spec_rgb, spec_tex) = match m.specular() {
            Some(s) => {
                let f = s.specular_factor();
                let c = s.specular_color_factor();
                // specularTexture: A channel × factor; specularColorTexture: sRGB-decoded RGB,
                // times the factor (which may exceed 1: kept apart from the bounded texels).
                let weight = match s.specular_texture() {
                    Some(info) => self.float_map(&info, |p| p[3] * f),
                    None => FloatTexture::Constant(f),
                };
                let color = s.specular_color_texture().map(|info| {
                    let tex = info.texture();
                    let img = self.image(&tex);
                    let map = uv_map(&info);
                    let px = rgba(img);
                    let dec: Vec<[f32; 3]> = px
                        .iter()
                        .map(|p| [0, 1, 2].map(|k| srgb_decode(p[k]).clamp(0.0, 1.0)))
                        .collect();
                    let texels = dec.iter().map(|d| rgb2spec::fetch(*d)).collect();
                    let max = dec
                        .iter()
                        .map(|d| (0..3).map(|k| d[k] * c[k]).fold(0.0, f32::max))
                        .collect();
                    Box::new(SpecularColorTexture {
                        color: SpectralTexture::Bitmap(Box::new(grid(img, texels, &tex, map))),
                        max: FloatTexture::Bitmap(Box::new(grid(img, max, &tex, map))),
                    })
                });
                (weight, c, color)
            }
            None => (FloatTexture::Constant(1.0), [1.0; 3], None),
        };
        let (transmission, transmission_f) = match m.transmission() {
            Some(t) => {
                let f = t.transmission_factor();
                let tex = match t.transmission_texture() {
                    // The R channel × factor.
                    Some(info) => self.float_map(&info, |p| (p[0] * f).clamp(0.0, 1.0)),
                    None => FloatTexture::Constant(f.clamp(0.0, 1.0)),
                };
                (tex, f)
            }
            None => (FloatTexture::Constant(0.0), 0.0),
        };
        let sets = texture_sets(m);
        if let Some((first, k)) = sets.first() {
            let other: Vec<String> = sets
                .iter()
                .filter(|(_, j)| j != k)
                .map(|(n, j)| format!("{n} (TEXCOORD_{j})"))
                .collect();
            if !other.is_empty() {
                warn.push(format!(
                    "{}: {label}: {first} reads TEXCOORD_{k} but {} another set; prism keeps one uv set per mesh, so all of them read TEXCOORD_{k}",
                    self.model.path.display(),
                    other.join(", ")
                ));
            }
        }
        let dispersion = m
            .extension_value("KHR_materials_dispersion")
            .and_then(|v| v.get("dispersion"))
            .and_then(|v| v.as_f64())
            .unwrap_or(0.0) as f32;
        if dispersion <= 0.0
            && m.volume().is_some_and(|v| v.thickness_factor() > 0.0)
            && transmission_f > 0.0
        {
            warn.push(format!("{}: {label}: KHR_materials_volume is rendered thin-walled (no refraction or attenuation) unless the material has KHR_materials_dispersion", self.model.path.display()));
        }
        let dispersive = dispersion > 0.0 && transmission_f > 0.0;
        unread::material(self.model, m, &label, warn);
        let mut mat = if dispersive {
            // A dispersive glass: prism's dielectric with a Cauchy index of the same Abbe
            // number; base colour tints the transmission.
            let rel = RelativeIor::new(dispersion_abbe(ior, dispersion), Ior::Constant(1.0));
            let r = rough_f * rough_f;
            let tint = base_color.clone();
            // A roughness texture is honoured: α = (G × roughnessFactor)² per texel.
            let alpha = match &roughness {
                FloatTexture::Bitmap(g) => FloatTexture::Bitmap(Box::new(Grid {
                    texels: g.texels.iter().map(|v| v.clamp(0.0, 1.0).powi(2)).collect(),
                    ..Grid::clone(g)
                })),
                _ => FloatTexture::Constant(r),
            };
            if r > 1e-3 || matches!(alpha, FloatTexture::Bitmap(_)) {
                Material::RoughDielectric(RoughDielectricParams {
                    ior: rel,
                    distribution: Distribution::Ggx,
                    alpha_u: alpha.clone(),
                    alpha_v: alpha,
                    specular_reflectance: SpectralTexture::Uniform(Curve::Constant(1.0)),
                    specular_transmittance: tint,
                })
            } else {
                Material::Dielectric(DielectricParams {
                    ior: rel,
                    specular_reflectance: SpectralTexture::Uniform(Curve::Constant(1.0)),
                    specular_transmittance: tint,
                })
            }
        } else {
            Material::Principled(Box::new(PrincipledParams {
                base_color,
                metallic,
                roughness,
                f0_ior: f0_from_ior(ior),
                specular_color: rgb_factor(spec_rgb),
                specular_color_max: spec_rgb[0].max(spec_rgb[1]).max(spec_rgb[2]),
                specular,
                transmission,
                specular_color_texture: spec_tex,
            }))
        };
        use gltf::material::AlphaMode;
        let vertex_alpha = vertex.filter(|v| v.1).map(|v| v.0);
        let opacity = match (m.alpha_mode(), alpha_tex) {
            (AlphaMode::Opaque, _) => None,
            // Vertex alpha × texel alpha × factor, cut after the product for MASK.
            (mode, tex) if vertex_alpha.is_some() => {
                let base = tex.map_or(FloatTexture::Constant(bc[3].clamp(0.0, 1.0)), |g| {
                    FloatTexture::Bitmap(Box::new(g))
                });
                let cut = (mode == AlphaMode::Mask).then(|| m.alpha_cutoff().unwrap_or(0.5));
                vertex_alpha.map(|c| colors::alpha(base, cut, c))
            }
            (AlphaMode::Mask, tex) => {
                let cut = m.alpha_cutoff().unwrap_or(0.5);
                Some(match tex {
                    Some(mut g) => {
                        g.texels
                            .iter_mut()
                            .for_each(|a| *a = if *a >= cut { 1.0 } else { 0.0 });
                        // Nearest: a cut-out edge stays a hard edge.
                        g.filter = TexFilter::Nearest;
                        FloatTexture::Bitmap(Box::new(g))
                    }
                    None => FloatTexture::Constant(if bc[3] >= cut { 1.0 } else { 0.0 }),
                })
            }
            (AlphaMode::Blend, Some(g)) => Some(FloatTexture::Bitmap(Box::new(g))),
            (AlphaMode::Blend, None) => Some(FloatTexture::Constant(bc[3].clamp(0.0, 1.0))),
        };
        if let Some(opacity) = opacity {
            if opacity != FloatTexture::Constant(1.0) {
                mat = Material::Mask {
                    inner: Box::new(mat),
                    opacity,
                };
            }
        }
        let emission = emission::radiance(m, &self.model.images);
        Ok((mat, emission))
    }
}
