//! glTF materials → prism materials: the metallic-roughness model becomes `Principled` (with
//! KHR_materials_ior, _specular, _transmission), textures are read from the decoded images
//! (base colour sRGB-decoded and uplifted; metallic and roughness from the B and G channels),
//! KHR_texture_transform's offset and scale map the uvs, alpha MASK and BLEND wrap the material
//! in a `Mask`, emission (times KHR_materials_emissive_strength) makes the shape an area light,
//! and KHR_materials_dispersion (read from the raw JSON) makes a transmissive material a
//! dispersive dielectric.

use super::Model;
use crate::bsdf::microfacet::Distribution;
use crate::bsdf::{Material, PrincipledParams};
use crate::error::InputError;
use crate::scene::principled::{f0_from_ior, rgb_factor};
use crate::spectrum::{rgb2spec, Curve, Ior, RelativeIor};
use crate::texture::{srgb_decode, FloatTexture, Grid, SpectralTexture, TexFilter, UvMap, Wrap};
use glam::{Vec2, Vec3};
use std::collections::HashMap;
use std::sync::Arc;

/// Builds each glTF material once, on first use.
pub struct GltfMaterials<'a> {
    model: &'a Model,
    built: HashMap<Option<usize>, Built>,
    materials: Vec<Material>,
}

/// A built material: its index, its emission and its normal map.
pub type Built = (usize, Option<Curve>, Option<Arc<Grid<Vec3>>>);

/// An image's texels as RGBA floats in [0, 1] (8- and 16-bit channels; missing ones: G = B = R
/// for grey images, A = 1).
fn rgba(img: &gltf::image::Data) -> Vec<[f32; 4]> {
    use gltf::image::Format::*;
    let (ch, bytes) = match img.format {
        R8 => (1, 1),
        R8G8 => (2, 1),
        R8G8B8 => (3, 1),
        R8G8B8A8 => (4, 1),
        R16 => (1, 2),
        R16G16 => (2, 2),
        R16G16B16 => (3, 2),
        R16G16B16A16 => (4, 2),
        R32G32B32FLOAT => (3, 4),
        R32G32B32A32FLOAT => (4, 4),
    };
    let px = &img.pixels;
    let value = |i: usize| -> f32 {
        match bytes {
            1 => px[i] as f32 / 255.0,
            2 => u16::from_le_bytes([px[2 * i], px[2 * i + 1]]) as f32 / 65535.0,
            _ => f32::from_le_bytes([px[4 * i], px[4 * i + 1], px[4 * i + 2], px[4 * i + 3]]),
        }
    };
    (0..(img.width * img.height) as usize)
        .map(|p| {
            let c = |k: usize| value(p * ch + k);
            match ch {
                1 => [c(0), c(0), c(0), 1.0],
                2 => [c(0), c(0), c(0), c(1)],
                3 => [c(0), c(1), c(2), 1.0],
                _ => [c(0), c(1), c(2), c(3)],
            }
        })
        .collect()
}

/// Where a texture sits: KHR_texture_transform's offset and scale (a rotation is warned about
/// and left out: prism's uv maps have none).
fn uv_map(info: &gltf::texture::Info, model: &Model, what: &str, warn: &mut Vec<String>) -> UvMap {
    let mut map = UvMap {
        scale: Vec2::ONE,
        offset: Vec2::ZERO,
    };
    if info.tex_coord() != 0 {
        warn.push(format!(
            "{}: {what} uses TEXCOORD_{}; prism reads TEXCOORD_0 only",
            model.path.display(),
            info.tex_coord()
        ));
    }
    if let Some(t) = info.texture_transform() {
        if t.rotation() != 0.0 {
            warn.push(format!(
                "{}: {what}: KHR_texture_transform rotation {} is not supported and is ignored",
                model.path.display(),
                t.rotation()
            ));
        }
        map.scale = Vec2::from(t.scale());
        map.offset = Vec2::from(t.offset());
    }
    map
}

/// Wrap and filter from the texture's sampler (mirrored repeat is read as repeat).
fn sampling(tex: &gltf::Texture) -> (Wrap, TexFilter) {
    use gltf::texture::{MagFilter, WrappingMode};
    let s = tex.sampler();
    let wrap = match s.wrap_s() {
        WrappingMode::ClampToEdge => Wrap::Clamp,
        _ => Wrap::Repeat,
    };
    let filter = match s.mag_filter() {
        Some(MagFilter::Nearest) => TexFilter::Nearest,
        _ => TexFilter::Bilinear,
    };
    (wrap, filter)
}

fn grid<T>(img: &gltf::image::Data, texels: Vec<T>, tex: &gltf::Texture, map: UvMap) -> Grid<T> {
    let (wrap, filter) = sampling(tex);
    Grid {
        width: img.width as usize,
        height: img.height as usize,
        texels,
        wrap,
        filter,
        map,
        source: None,
    }
}

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

impl<'a> GltfMaterials<'a> {
    pub fn new(model: &'a Model) -> Self {
        Self {
            model,
            built: HashMap::new(),
            materials: Vec::new(),
        }
    }

    /// The index (into `into_materials`) of glTF material `index` (None: the default material)
    /// and its emission.
    pub fn get(
        &mut self,
        m: &gltf::Material,
        warnings: &mut Vec<String>,
    ) -> Result<Built, InputError> {
        let index = m.index();
        if let Some(r) = self.built.get(&index) {
            return Ok(r.clone());
        }
        let (mat, emission) = self.build(m, warnings)?;
        self.materials.push(mat);
        let r = (self.materials.len() - 1, emission, self.normal_map(m));
        self.built.insert(index, r.clone());
        Ok(r)
    }

    pub fn into_materials(self) -> Vec<Material> {
        self.materials
    }

    /// The tangent-space normals of the material's `normalTexture` (x and y times its `scale`;
    /// 8-bit values v map to 2v − 1).
    fn normal_map(&self, m: &gltf::Material) -> Option<Arc<Grid<Vec3>>> {
        let nt = m.normal_texture()?;
        let tex = nt.texture();
        let img = self.image(&tex);
        let s = nt.scale();
        let texels = rgba(img)
            .iter()
            .map(|p| {
                Vec3::new(
                    (2.0 * p[0] - 1.0) * s,
                    (2.0 * p[1] - 1.0) * s,
                    2.0 * p[2] - 1.0,
                )
            })
            .collect();
        let map = UvMap {
            scale: Vec2::ONE,
            offset: Vec2::ZERO,
        };
        Some(Arc::new(grid(img, texels, &tex, map)))
    }

    fn image(&self, tex: &gltf::Texture) -> &gltf::image::Data {
        &self.model.images[tex.source().index()]
    }

    fn build(
        &self,
        m: &gltf::Material,
        warn: &mut Vec<String>,
    ) -> Result<(Material, Option<Curve>), InputError> {
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
                let map = uv_map(
                    &info,
                    self.model,
                    &format!("{label} baseColorTexture"),
                    warn,
                );
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
        let (metal_f, rough_f) = (pbr.metallic_factor(), pbr.roughness_factor());
        let (metallic, roughness) = match pbr.metallic_roughness_texture() {
            Some(info) => {
                let tex = info.texture();
                let img = self.image(&tex);
                let map = uv_map(
                    &info,
                    self.model,
                    &format!("{label} metallicRoughnessTexture"),
                    warn,
                );
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
        let (specular, spec_rgb) = match m.specular() {
            Some(s) => {
                if s.specular_texture().is_some() || s.specular_color_texture().is_some() {
                    warn.push(format!("{}: {label}: KHR_materials_specular textures are not supported; their factors are used", self.model.path.display()));
                }
                (s.specular_factor(), s.specular_color_factor())
            }
            None => (1.0, [1.0; 3]),
        };
        let transmission = match m.transmission() {
            Some(t) => {
                if t.transmission_texture().is_some() {
                    warn.push(format!("{}: {label}: transmissionTexture is not supported; transmissionFactor is used", self.model.path.display()));
                }
                t.transmission_factor()
            }
            None => 0.0,
        };
        if m.volume().is_some_and(|v| v.thickness_factor() > 0.0) && transmission > 0.0 {
            warn.push(format!("{}: {label}: KHR_materials_volume is rendered thin-walled (no refraction or attenuation) unless the material has KHR_materials_dispersion", self.model.path.display()));
        }
        if m.emissive_texture().is_some() {
            warn.push(format!("{}: {label}: emissiveTexture is not supported; emissiveFactor is used as a uniform emission", self.model.path.display()));
        }
        let dispersion = m
            .extension_value("KHR_materials_dispersion")
            .and_then(|v| v.get("dispersion"))
            .and_then(|v| v.as_f64())
            .unwrap_or(0.0) as f32;
        let mut mat = if dispersion > 0.0 && transmission > 0.0 {
            // A dispersive glass: prism's dielectric with a Cauchy index of the same Abbe
            // number; base colour tints the transmission.
            let rel = RelativeIor::new(dispersion_abbe(ior, dispersion), Ior::Constant(1.0));
            let r = rough_f * rough_f;
            let tint = base_color.clone();
            if r > 1e-3 {
                Material::RoughDielectric {
                    ior: rel,
                    distribution: Distribution::Ggx,
                    alpha_u: FloatTexture::Constant(r),
                    alpha_v: FloatTexture::Constant(r),
                    specular_reflectance: SpectralTexture::Uniform(Curve::Constant(1.0)),
                    specular_transmittance: tint,
                }
            } else {
                Material::Dielectric {
                    ior: rel,
                    specular_reflectance: SpectralTexture::Uniform(Curve::Constant(1.0)),
                    specular_transmittance: tint,
                }
            }
        } else {
            Material::Principled(Box::new(PrincipledParams {
                base_color,
                metallic,
                roughness,
                f0_ior: f0_from_ior(ior),
                specular_color: rgb_factor(spec_rgb),
                specular_color_max: spec_rgb[0].max(spec_rgb[1]).max(spec_rgb[2]),
                specular: specular.clamp(0.0, 1.0),
                transmission: FloatTexture::Constant(transmission.clamp(0.0, 1.0)),
            }))
        };
        use gltf::material::AlphaMode;
        let opacity = match (m.alpha_mode(), alpha_tex) {
            (AlphaMode::Opaque, _) => None,
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
        let e = m.emissive_factor();
        let strength = m.emissive_strength().unwrap_or(1.0);
        let emission = (e.iter().any(|&c| c > 0.0) && strength > 0.0)
            .then(|| Curve::rgb_illuminant(e.map(|c| c * strength)));
        Ok((mat, emission))
    }
}
