//! glTF emission → an area light's radiance: emissiveFactor × KHR_materials_emissive_strength,
//! times the emissiveTexture's RGB where the material has one (glTF 2.0 §3.9.2: the texture is
//! sRGB-encoded, its RGB multiplies the factor, its alpha is ignored), read through the
//! texture's sampler and KHR_texture_transform like every other texture (`materials`). Each
//! texel's product is uplifted as an illuminant exactly as a uniform emissiveFactor is.

use super::materials::{rgba, sampling, uv_map};
use crate::emitter::{AreaRadiance, EmissionTexture};
use crate::spectrum::gamut::Gamut;
use crate::spectrum::Curve;
use crate::texture::{srgb_decode, RgbImage};

/// The radiance of material `m` (its images decoded in `images`); None when it emits nothing
/// (a zero factor or strength, or a texture that is black wherever the factor is not zero).
pub fn radiance(m: &gltf::Material, images: &[gltf::image::Data]) -> Option<AreaRadiance> {
    let e = m.emissive_factor();
    let strength = m.emissive_strength().unwrap_or(1.0);
    if !(e.iter().any(|&c| c > 0.0) && strength > 0.0) {
        return None;
    }
    let factor = e.map(|c| c * strength);
    let Some(info) = m.emissive_texture() else {
        return Some(AreaRadiance::Uniform(Curve::rgb_illuminant(factor)));
    };
    let tex = info.texture();
    let img = &images[tex.source().index()];
    let pixels: Vec<[f32; 3]> = rgba(img)
        .iter()
        .map(|p| [0, 1, 2].map(|k| srgb_decode(p[k])))
        .collect();
    if pixels
        .iter()
        .all(|p| (0..3).all(|k| p[k] * factor[k] <= 0.0))
    {
        return None;
    }
    let image = RgbImage {
        width: img.width as usize,
        height: img.height as usize,
        pixels,
        source: None,
    };
    let (wrap, filter) = sampling(&tex);
    Some(AreaRadiance::Textured(Box::new(EmissionTexture::new(
        Gamut::Srgb,
        &image,
        factor,
        wrap,
        filter,
        uv_map(&info),
    ))))
}
