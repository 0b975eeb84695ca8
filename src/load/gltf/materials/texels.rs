//! A glTF texture reference read for a material: its texels as RGBA floats, its placement
//! (KHR_texture_transform), the TEXCOORD set it reads, its sampler's wrap and filter, and the
//! grids and scalar maps built from them (the normal map among them).

use super::GltfMaterials;
use crate::math::portable;
use crate::texture::{FloatTexture, Grid, TexFilter, UvMap, Wrap};
use glam::{Vec2, Vec3};
use std::sync::Arc;

/// An image's texels as RGBA floats in [0, 1] (8- and 16-bit channels; missing ones: G = B = R
/// for grey images, A = 1).
pub(in crate::load::gltf) fn rgba(img: &gltf::image::Data) -> Vec<[f32; 4]> {
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
                rotation: Vec2::new(portable::cos(t.rotation), portable::sin(t.rotation)),
            },
        }
    }
}

/// Where a texture sits (KHR_texture_transform, rotation included).
pub(in crate::load::gltf) fn uv_map(info: &gltf::texture::Info) -> UvMap {
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
pub(super) fn texture_sets(m: &gltf::Material) -> Vec<(&'static str, u32)> {
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
pub(in crate::load::gltf) fn sampling(tex: &gltf::Texture) -> ([Wrap; 2], TexFilter) {
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

/// A grid of `texels` of `img`'s size, wrapped and filtered as `tex`'s sampler says, placed
/// by `map`.
pub(super) fn grid<T>(
    img: &gltf::image::Data,
    texels: Vec<T>,
    tex: &gltf::Texture,
    map: UvMap,
) -> Grid<T> {
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

impl GltfMaterials<'_> {
    /// The tangent-space normals of the material's `normalTexture` (x and y times its `scale`;
    /// 8-bit values v map to 2v − 1).
    pub(super) fn normal_map(&self, m: &gltf::Material) -> Option<Arc<Grid<Vec3>>> {
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

    pub(super) fn image(&self, tex: &gltf::Texture) -> &gltf::image::Data {
        &self.model.images[tex.source().index()]
    }

    /// A scalar texture: `f` of each texel's RGBA, placed as `info` says.
    pub(super) fn float_map(
        &self,
        info: &gltf::texture::Info,
        f: impl Fn(&[f32; 4]) -> f32,
    ) -> FloatTexture {
        let tex = info.texture();
        let img = self.image(&tex);
        let texels = rgba(img).iter().map(f).collect();
        FloatTexture::Bitmap(Box::new(grid(img, texels, &tex, uv_map(info))))
    }
}
