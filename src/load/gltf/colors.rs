//! glTF vertex colours (`COLOR_0`): read and checked per primitive, then laid on each shape's
//! triangles as `texture::VertexColors`. COLOR_0 is linear RGB(A) (glTF 2.0 §3.7.2.1: float,
//! or normalised unsigned byte or short, VEC3 or VEC4); it multiplies the base colour and its
//! alpha multiplies the alpha.
//!
//! The uplift follows the base colour: without a base-colour texture the factor × vertex colour
//! is uplifted per vertex; with one, the texture (factor × texel, uplifted per texel) is
//! multiplied by the vertex colour uplifted per vertex.

use super::Model;
use crate::error::InputError;
use crate::spectrum::rgb2spec;
use crate::texture::{FloatTexture, SpectralTexture, VertexAlpha, VertexColors};

/// A primitive's vertex colours, one per vertex (alpha 1 where the file gives RGB).
#[derive(Debug)]
pub struct Colors {
    pub rgba: Vec<[f32; 4]>,
    /// The accessor is VEC4: its alpha multiplies the material's.
    pub alpha: bool,
}

/// Reads `COLOR_0` of `prim` (None without it), checking what the gltf crate would otherwise
/// trip over: its type, component type and count, and non-finite values.
pub fn read(
    model: &Model,
    prim: &gltf::Primitive,
    field: &str,
    vertices: usize,
) -> Result<Option<Colors>, InputError> {
    use gltf::accessor::{DataType, Dimensions};
    let Some(acc) = prim.get(&gltf::Semantic::Colors(0)) else {
        return Ok(None);
    };
    let field = format!("{field}.attributes.COLOR_0");
    let bad = |m: String| {
        InputError::new(&model.path, m)
            .field(&field)
            .hint("COLOR_0 must be VEC3 or VEC4 of FLOAT, or of normalized UNSIGNED_BYTE or UNSIGNED_SHORT, one per vertex (glTF 2.0 §3.7.2.1)")
    };
    let (ty, dims) = (acc.data_type(), acc.dimensions());
    if !matches!(dims, Dimensions::Vec3 | Dimensions::Vec4)
        || !matches!(ty, DataType::F32 | DataType::U8 | DataType::U16)
    {
        return Err(bad(format!(
            "accessors[{}] is {dims:?} of {ty:?}",
            acc.index()
        )));
    }
    if acc.count() != vertices {
        return Err(bad(format!(
            "accessors[{}] has {} colours for {vertices} vertices",
            acc.index(),
            acc.count()
        )));
    }
    let reader = prim.reader(|b| model.buffers.get(b.index()).map(|d| &d.0[..]));
    // Integers divided by 255 or 65535 as §3.11 writes it (the crate's `into_rgba_f32`
    // multiplies by the reciprocal, which reads 255 as 0.99999994).
    use gltf::mesh::util::ReadColors::*;
    let (u8n, u16n) = (|v: u8| v as f32 / 255.0, |v: u16| v as f32 / 65535.0);
    let rgba: Vec<[f32; 4]> = match reader.read_colors(0) {
        Some(RgbF32(it)) => it.map(|[r, g, b]| [r, g, b, 1.0]).collect(),
        Some(RgbaF32(it)) => it.collect(),
        Some(RgbU8(it)) => it.map(|c| [u8n(c[0]), u8n(c[1]), u8n(c[2]), 1.0]).collect(),
        Some(RgbaU8(it)) => it.map(|c| c.map(u8n)).collect(),
        Some(RgbU16(it)) => it
            .map(|c| [u16n(c[0]), u16n(c[1]), u16n(c[2]), 1.0])
            .collect(),
        Some(RgbaU16(it)) => it.map(|c| c.map(u16n)).collect(),
        None => return Err(bad(format!("accessors[{}] has no data", acc.index()))),
    };
    if let Some(i) = rgba.iter().position(|c| c.iter().any(|v| !v.is_finite())) {
        return Err(bad(format!("colour {i} is not finite: {:?}", rgba[i])));
    }
    Ok(Some(Colors {
        rgba,
        alpha: dims == Dimensions::Vec4,
    }))
}

/// Each triangle's corner colours, in the order of `tris` (the shape's own winding, which its
/// barycentrics follow).
pub fn corners(c: &Colors, tris: &[[u32; 3]]) -> Vec<[[f32; 4]; 3]> {
    tris.iter().map(|t| t.map(|v| c.rgba[v as usize])).collect()
}

/// The base colour times the corners' colours. `factor` is folded into the corners when the
/// base colour has no texture (`base` is then uniform and replaced by 1).
pub fn tint(base: SpectralTexture, factor: [f32; 4], corners: &[[[f32; 4]; 3]]) -> SpectralTexture {
    let textured = !matches!(base, SpectralTexture::Uniform(_));
    let scale = if textured {
        [1.0; 3]
    } else {
        [factor[0], factor[1], factor[2]]
    };
    let corners = corners
        .iter()
        .map(|t| t.map(|c| rgb2spec::fetch([0, 1, 2].map(|k| (c[k] * scale[k]).clamp(0.0, 1.0)))))
        .collect();
    let base = if textured {
        base
    } else {
        SpectralTexture::Uniform(crate::spectrum::Curve::Constant(1.0))
    };
    SpectralTexture::Vertex(Box::new(VertexColors { corners, base }))
}

/// The opacity times the corners' alphas, cut at `cutoff` (MASK) after the product.
pub fn alpha(base: FloatTexture, cutoff: Option<f32>, corners: &[[[f32; 4]; 3]]) -> FloatTexture {
    FloatTexture::Vertex(Box::new(VertexAlpha {
        corners: corners
            .iter()
            .map(|t| t.map(|c| c[3].clamp(0.0, 1.0)))
            .collect(),
        base,
        cutoff,
    }))
}
