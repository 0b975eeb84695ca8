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
//!
//! This file holds the cache of built materials; `materials/texels.rs` reads a texture
//! reference's texels, placement, TEXCOORD set and sampler, and `materials/build.rs` builds one
//! material.

mod build;
mod texels;

pub use build::dispersion_abbe;
pub use texels::uv_set;
pub(super) use texels::{rgba, sampling, uv_map};

use super::Model;
use crate::bsdf::Material;
use crate::emitter::AreaRadiance;
use crate::error::InputError;
use crate::texture::Grid;
use glam::Vec3;
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
}
