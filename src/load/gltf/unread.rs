//! What prism does not read from a glTF file, said at load rather than rendered silently
//! wrong: vertex colour sets past COLOR_0, MIRRORED_REPEAT samplers (read as REPEAT).
//! scenes/README.md ("glTF") lists the same.

use super::Model;

/// A warning for each vertex colour set past COLOR_0 (COLOR_1, …), which no material reads.
pub fn primitive(model: &Model, prim: &gltf::Primitive, field: &str, warn: &mut Vec<String>) {
    for (sem, _) in prim.attributes() {
        if let gltf::Semantic::Colors(k) = sem {
            let w = format!(
                "{}: {field}.attributes.COLOR_{k}: a vertex colour set after the first, which no material reads",
                model.path.display()
            );
            // The file is walked more than once (camera, shapes): say it once.
            if k > 0 && !warn.contains(&w) {
                warn.push(w);
            }
        }
    }
}

/// Warnings for the parts of material `m` (called `label`) that prism does not read.
pub fn material(model: &Model, m: &gltf::Material, label: &str, warn: &mut Vec<String>) {
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
}
