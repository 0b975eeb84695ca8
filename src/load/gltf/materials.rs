//! glTF materials → prism materials: the metallic-roughness model becomes `Principled` (with
//! KHR_materials_ior, _specular, _transmission and their textures), textures are read from the
//! decoded images (base colour and specular colour sRGB-decoded and uplifted; metallic and
//! roughness from the B and G channels, specular from A, transmission from R),
//! KHR_texture_transform (offset, scale, rotation, texCoord) maps the uvs, a primitive carries
//! the TEXCOORD set its textures read, alpha MASK and BLEND wrap the material in a `Mask`,
//! emission (times KHR_materials_emissive_strength, textured or not: `emission`) makes the
//! shape an area light, and
//! KHR_materials_dispersion (read from the raw JSON) makes a transmissive material a dispersive
//! dielectric. The occlusion texture is ignored on purpose (see `texture_sets`).

use super::Model;
use crate::bsdf::microfacet::Distribution;
use crate::bsdf::{
    DielectricParams, Material, PrincipledParams, RoughDielectricParams, SpecularColorTexture,
};
use crate::emitter::AreaRadiance;
use crate::error::InputError;
use crate::load::principled::{f0_from_ior, rgb_factor};
use crate::spectrum::{rgb2spec, Curve, Ior, RelativeIor};
use crate::texture::{srgb_decode, FloatTexture, Grid, SpectralTexture, TexFilter, UvMap, Wrap};
use glam::{Vec2, Vec3};
use std::collections::HashMap;
use std::sync::Arc;

/// Builds each glTF material once, on first use.
pub struct GltfMaterials<'a> {
    model: &'a Model,
    built: HashMap<Option<usize>, Built>,
    /// Materials with vertex colours, one per primitive and winding (`tinted`), with their
    /// glTF material index.
    tinted: HashMap<TintKey, (Option<usize>, Built)>,
    materials: Vec<Material>,
}

/// A primitive (mesh, primitive) and whether its shape's winding is the file's reversed.
pub type TintKey = ((usize, usize), bool);

/// A built material: its index, its emission and its normal map.
pub type Built = (usize, Option<AreaRadiance>, Option<Arc<Grid<Vec3>>>);

/// An image's texels as RGBA floats in [0, 1] (8- and 16-bit channels; missing ones: G = B = R
/// for grey images, A = 1).
pub(super) fn rgba(img: &gltf::image::Data) -> Vec<[f32; 4]> {
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

/// KHR_texture_transform on one texture reference: offset, scale, rotation (radians) and the
/// texCoord override.
struct Xform {
    offset: [f32; 2],
    scale: [f32; 2],
    rotation: f32,
    tex_coord: Option<u32>,
}

impl Xform {
    fn of(info: &gltf::texture::Info) -> Option<Xform> {
        info.texture_transform().map(|t| Xform {
            offset: t.offset(),
            scale: t.scale(),
            rotation: t.rotation(),
            tex_coord: t.tex_coord(),
        })
    }

    /// From the raw JSON (the crate carries the extension on `textureInfo` only, not on
    /// `normalTexture`); missing fields take the extension's defaults.
    fn of_json(v: Option<&serde_json::Value>) -> Option<Xform> {
        let v = v?;
        let pair = |k: &str, d: [f32; 2]| -> [f32; 2] {
            v.get(k)
                .and_then(|a| a.as_array())
                .filter(|a| a.len() == 2)
                .and_then(|a| Some([a[0].as_f64()? as f32, a[1].as_f64()? as f32]))
                .unwrap_or(d)
        };
        Some(Xform {
            offset: pair("offset", [0.0, 0.0]),
            scale: pair("scale", [1.0, 1.0]),
            rotation: v.get("rotation").and_then(|r| r.as_f64()).unwrap_or(0.0) as f32,
            tex_coord: v.get("texCoord").and_then(|t| t.as_u64()).map(|t| t as u32),
        })
    }

    fn map(t: Option<&Xform>) -> UvMap {
        match t {
            None => UvMap::IDENTITY,
            Some(t) => UvMap {
                scale: Vec2::from(t.scale),
                offset: Vec2::from(t.offset),
                rotation: Vec2::new(t.rotation.cos(), t.rotation.sin()),
            },
        }
    }
}

/// Where a texture sits (KHR_texture_transform, rotation included).
pub(super) fn uv_map(info: &gltf::texture::Info) -> UvMap {
    Xform::map(Xform::of(info).as_ref())
}

/// The TEXCOORD set a texture reads: KHR_texture_transform's `texCoord` overrides the
/// textureInfo's.
fn tex_set(info: &gltf::texture::Info) -> u32 {
    Xform::of(info)
        .and_then(|t| t.tex_coord)
        .unwrap_or(info.tex_coord())
}

/// Every texture of `m` that prism reads, with its TEXCOORD set. The occlusion texture is not
/// among them: a path tracer computes the occlusion of indirect light by tracing it, so
/// applying a baked ambient-occlusion map as well would darken crevices twice; it is read
/// (its indices are validated with the file) and ignored on purpose, as Blender's Cycles does.
fn texture_sets(m: &gltf::Material) -> Vec<(&'static str, u32)> {
    let pbr = m.pbr_metallic_roughness();
    let mut v = Vec::new();
    let mut push = |name, info: Option<gltf::texture::Info>| {
        if let Some(i) = info {
            v.push((name, tex_set(&i)));
        }
    };
    push("baseColorTexture", pbr.base_color_texture());
    push("metallicRoughnessTexture", pbr.metallic_roughness_texture());
    if let Some(s) = m.specular() {
        push("specularTexture", s.specular_texture());
        push("specularColorTexture", s.specular_color_texture());
    }
    if let Some(t) = m.transmission() {
        push("transmissionTexture", t.transmission_texture());
    }
    push("emissiveTexture", m.emissive_texture());
    if let Some(n) = m.normal_texture() {
        let x = Xform::of_json(n.extension_value("KHR_texture_transform"));
        v.push((
            "normalTexture",
            x.and_then(|x| x.tex_coord).unwrap_or(n.tex_coord()),
        ));
    }
    v
}

/// The TEXCOORD set a primitive of material `m` carries as its uvs: the one its textures read
/// (prism keeps one uv set per mesh; when the textures disagree, the first one's, and
/// `GltfMaterials` warns); 0 without textures.
pub fn uv_set(m: &gltf::Material) -> u32 {
    texture_sets(m).first().map_or(0, |t| t.1)
}

/// Wrap along u (wrapS) and v (wrapT), and filter, from the texture's sampler (mirrored
/// repeat is read as repeat: `unread` warns).
pub(super) fn sampling(tex: &gltf::Texture) -> ([Wrap; 2], TexFilter) {
    use gltf::texture::{MagFilter, WrappingMode};
    let s = tex.sampler();
    let mode = |m: WrappingMode| match m {
        WrappingMode::ClampToEdge => Wrap::Clamp,
        _ => Wrap::Repeat,
    };
    let wrap = [mode(s.wrap_s()), mode(s.wrap_t())];
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
        wrap: wrap[0],
        wrap_v: wrap[1],
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
            tinted: HashMap::new(),
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
        let said = self.tinted.values().any(|(i, _)| *i == index);
        let mut quiet = Vec::new();
        let warn = if said { &mut quiet } else { warnings };
        let (mat, emission) = self.build(m, None, warn)?;
        self.materials.push(mat);
        let r = (self.materials.len() - 1, emission, self.normal_map(m));
        self.built.insert(index, r.clone());
        Ok(r)
    }

    /// As `get`, for a primitive with vertex colours: each triangle's `corners` (RGBA; `alpha`:
    /// the file gives A) multiply the base colour and alpha, in a material of its own per `key`.
    pub fn tinted(
        &mut self,
        m: &gltf::Material,
        key: TintKey,
        corners: &[[[f32; 4]; 3]],
        alpha: bool,
        warnings: &mut Vec<String>,
    ) -> Result<Built, InputError> {
        if let Some(r) = self.tinted.get(&key) {
            return Ok(r.1.clone());
        }
        // Warnings about the material itself are given once per glTF material.
        let said = self.built.contains_key(&m.index())
            || self.tinted.values().any(|(i, _)| *i == m.index());
        let mut quiet = Vec::new();
        let warn = if said { &mut quiet } else { warnings };
        let (mat, emission) = self.build(m, Some((corners, alpha)), warn)?;
        self.materials.push(mat);
        let r = (self.materials.len() - 1, emission, self.normal_map(m));
        self.tinted.insert(key, (m.index(), r.clone()));
        Ok(r)
    }

    /// The name of each built material, in `into_materials` order: the glTF material's name,
    /// else `materials[i]` of the file, or `(glTF default)`.
    pub fn names(&self) -> Vec<String> {
        let mut names = vec![String::new(); self.materials.len()];
        let tinted = self.tinted.values().map(|(i, b)| (i, b));
        for (index, built) in self.built.iter().chain(tinted) {
            names[built.0] = match index {
                Some(i) => self
                    .model
                    .doc
                    .materials()
                    .nth(*i)
                    .and_then(|m| m.name().map(str::to_owned))
                    .unwrap_or_else(|| format!("materials[{i}]")),
                None => "(glTF default)".into(),
            };
        }
        names
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
        let map = Xform::map(Xform::of_json(nt.extension_value("KHR_texture_transform")).as_ref());
        Some(Arc::new(grid(img, texels, &tex, map)))
    }

    fn image(&self, tex: &gltf::Texture) -> &gltf::image::Data {
        &self.model.images[tex.source().index()]
    }

    /// A scalar texture: `f` of each texel's RGBA, placed as `info` says.
    fn float_map(&self, info: &gltf::texture::Info, f: impl Fn(&[f32; 4]) -> f32) -> FloatTexture {
        let tex = info.texture();
        let img = self.image(&tex);
        let texels = rgba(img).iter().map(f).collect();
        FloatTexture::Bitmap(Box::new(grid(img, texels, &tex, uv_map(info))))
    }

    fn build(
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
            Some((corners, _)) => super::colors::tint(base_color, bc, corners),
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
        super::unread::material(self.model, m, &label, warn);
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
                vertex_alpha.map(|c| super::colors::alpha(base, cut, c))
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
        let emission = super::emission::radiance(m, &self.model.images);
        Ok((mat, emission))
    }
}
