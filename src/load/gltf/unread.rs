//! What prism does not read from a glTF file, said at load rather than rendered silently
//! wrong: vertex colours (COLOR_0), MIRRORED_REPEAT samplers (read as REPEAT) and a
//! dispersive glass's roughness texture (the glass takes roughnessFactor alone).
//! scenes/README.md ("glTF") lists the same.

use super::Model;

/// A warning for a primitive with vertex colours.
pub fn primitive(model: &Model, prim: &gltf::Primitive, field: &str, warn: &mut Vec<String>) {
    if prim.get(&gltf::Semantic::Colors(0)).is_some() {
        warn.push(format!(
            "{}: {field}.attributes.COLOR_0: vertex colours are not read; the base colour renders without them",
            model.path.display()
        ));
    }
}

/// Warnings for the parts of material `m` (called `label`) that prism does not read.
pub fn material(
    model: &Model,
    m: &gltf::Material,
    label: &str,
    dispersive: bool,
    warn: &mut Vec<String>,
) {
    let path = model.path.display();
    let pbr = m.pbr_metallic_roughness();
    let mut textures: Vec<gltf::Texture> = [
        pbr.base_color_texture(),
        pbr.metallic_roughness_texture(),
        m.emissive_texture(),
    ]
    .into_iter()
    .flatten()
    .map(|i| i.texture())
    .collect();
    textures.extend(m.normal_texture().map(|n| n.texture()));
    if let Some(s) = m.specular() {
        textures.extend(s.specular_texture().map(|i| i.texture()));
        textures.extend(s.specular_color_texture().map(|i| i.texture()));
    }
    if let Some(t) = m.transmission() {
        textures.extend(t.transmission_texture().map(|i| i.texture()));
    }
    use gltf::texture::WrappingMode::MirroredRepeat;
    if textures.iter().any(|t| {
        let s = t.sampler();
        s.wrap_s() == MirroredRepeat || s.wrap_t() == MirroredRepeat
    }) {
        warn.push(format!(
            "{path}: {label}: a texture's sampler uses MIRRORED_REPEAT, read as REPEAT"
        ));
    }
    if dispersive && pbr.metallic_roughness_texture().is_some() {
        warn.push(format!(
            "{path}: {label}: the dispersive glass takes roughnessFactor alone; its metallicRoughnessTexture is not read"
        ));
    }
}
