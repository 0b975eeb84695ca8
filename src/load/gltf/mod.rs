//! glTF 2.0 scenes (`.gltf`, `.glb`), read with the `gltf` crate: a RON scene includes one as a
//! shape (`shape: Gltf(path: "car.glb")`), and `prism render model.gltf` renders one directly
//! (`scene_config`). The node tree is walked with its transforms composed; every mesh
//! primitive under a node becomes one world-space shape named after the node; materials become
//! `Principled` materials (or the scene's materials, replaced by name); emissive materials
//! become area lights; KHR_lights_punctual lights and the cameras come out as config entries.
//!
//! Every problem a user can fix (bad JSON, a missing buffer or image, an extension prism cannot
//! decode) is an `InputError` naming the glTF file and the JSON field.

mod accessors;
mod animation;
mod camera;
mod checks;
mod colors;
mod document;
mod emission;
mod expand;
mod lights;
mod materials;
mod nodes;
mod unread;
mod uris;

use crate::error::InputError;
use crate::io::input_file::{self, Kind};
use serde_json::Value;
use std::cell::RefCell;
use std::path::{Path, PathBuf};

pub use camera::animate as animate_camera;
pub use expand::{expand, Expanded, ExpandedShape, MatRef, When};
pub use lights::{photometric_scale, scene_config, scene_for, GltfCamera, GltfLight};
pub use materials::dispersion_abbe;
pub use nodes::{walk, Primitive, Walk};

/// Extensions prism reads (or can safely ignore when a file requires them).
pub const SUPPORTED_EXTENSIONS: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_materials_ior",
    "KHR_materials_transmission",
    "KHR_materials_emissive_strength",
    "KHR_materials_specular",
    "KHR_materials_volume",
    "KHR_materials_dispersion",
    "KHR_texture_transform",
];

/// A glTF file with its buffers and images loaded.
pub struct Model {
    pub doc: gltf::Document,
    pub buffers: Vec<gltf::buffer::Data>,
    pub images: Vec<gltf::image::Data>,
    /// The file (for errors).
    pub path: PathBuf,
    /// Extensions the file uses that prism ignores (reported as warnings).
    pub ignored_extensions: Vec<String>,
}

/// How to fix a file that requires an extension prism cannot decode.
fn extension_hint(ext: &str) -> String {
    let list = SUPPORTED_EXTENSIONS.join(", ");
    match ext {
        "KHR_draco_mesh_compression" | "EXT_meshopt_compression" => format!(
            "prism reads uncompressed geometry only: re-export the model without mesh \
             compression (Blender: untick Compression), or decompress it with a glTF tool \
             (e.g. `gltf-transform copy in.glb out.glb` after `gltf-transform` decodes {ext}); \
             supported extensions: {list}"
        ),
        "KHR_texture_basisu" | "EXT_texture_webp" | "EXT_texture_avif" => format!(
            "prism reads PNG and JPEG textures only: re-export the model with PNG/JPEG textures \
             (e.g. convert {ext} images with `gltf-transform`); supported extensions: {list}"
        ),
        _ => format!("supported extensions: {list}"),
    }
}

fn err(path: &Path, field: impl Into<String>, message: impl Into<String>) -> InputError {
    // A caller's own hint replaces this one.
    let field = field.into();
    let hint = format!("the glTF 2.0 specification gives the values `{field}` may take; scenes/README.md lists what prism reads");
    InputError::new(path, message).field(field).hint(hint)
}

thread_local! {
    /// The model `prism render model.gltf` read for its config, handed on to the build of that
    /// config (`with_model`) so that the file, its buffers and images are read once.
    static PRELOADED: RefCell<Option<Model>> = const { RefCell::new(None) };
    /// Files read by `open` on this thread (for the test that the model is read once).
    #[cfg(test)]
    static OPENED: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

/// Runs `f` (building the config `scene_for(&model)` returned) with `model` ready for the
/// `Gltf` shape that names its file.
pub fn with_model<R>(model: Model, f: impl FnOnce() -> R) -> R {
    PRELOADED.with(|p| *p.borrow_mut() = Some(model));
    let r = f();
    PRELOADED.with(|p| p.borrow_mut().take());
    r
}

/// The model at `path`: the one `with_model` holds if it is that file, else read now
/// (`allow_outside`: as `open_with`).
fn take_or_open(path: &Path, allow_outside: bool) -> Result<Model, InputError> {
    let pre = PRELOADED.with(|p| {
        let mut p = p.borrow_mut();
        if p.as_ref().is_some_and(|m| m.path == path) {
            p.take()
        } else {
            None
        }
    });
    match pre {
        Some(m) => Ok(m),
        None => open_with(path, allow_outside),
    }
}

/// Reads and checks a `.gltf` or `.glb` file, its buffers and images, which must lie in its
/// folder (`open_with`).
pub fn open(path: &Path) -> Result<Model, InputError> {
    open_with(path, false)
}

/// As `open`; with `allow_outside` (the shape's `allow_outside: true`) its buffer and image
/// URIs may name files outside the model's folder.
pub fn open_with(path: &Path, allow_outside: bool) -> Result<Model, InputError> {
    #[cfg(test)]
    OPENED.with(|n| n.set(n.get() + 1));
    crate::io::inputs::record(path);
    let bytes = input_file::read(path, Kind::Gltf).map_err(|e| {
        InputError::new(path, e).hint("glTF paths in a scene are relative to the scene file")
    })?;
    let (json_bytes, blob): (Vec<u8>, Option<Vec<u8>>) = if bytes.starts_with(b"glTF") {
        let glb = gltf::Glb::from_slice(&bytes).map_err(|e| {
            InputError::new(path, format!("not a valid binary glTF (GLB) file: {e}"))
                .hint("re-export the file; a .glb starts with a 12-byte header and a JSON chunk")
        })?;
        (glb.json.into_owned(), glb.bin.map(|b| b.into_owned()))
    } else {
        (bytes, None)
    };
    let mut json: Value = serde_json::from_slice(&json_bytes).map_err(|e| {
        InputError::new(path, format!("not valid glTF JSON: {e}"))
            .at(e.line(), e.column())
            .hint("a .gltf file is JSON (glTF 2.0); check it with the Khronos glTF validator")
    })?;
    let version = json
        .pointer("/asset/version")
        .and_then(Value::as_str)
        .map(str::to_owned);
    match version.as_deref() {
        Some(v) if v.starts_with("2.") => {}
        Some(v) => {
            return Err(
                err(path, "asset.version", format!("glTF {v} is not supported"))
                    .hint("prism reads glTF 2.0; convert older files (e.g. with gltf-pipeline)"),
            )
        }
        None => {
            return Err(err(path, "asset.version", "the file has no asset.version")
                .hint("a glTF 2.0 file starts with \"asset\": {\"version\": \"2.0\"}"))
        }
    }
    // Required extensions prism cannot decode stop the load; used-but-optional ones are noted.
    let list = |key: &str| -> Vec<String> {
        json.get(key)
            .and_then(Value::as_array)
            .map(|a| {
                a.iter()
                    .filter_map(|v| v.as_str().map(str::to_owned))
                    .collect()
            })
            .unwrap_or_default()
    };
    let required = list("extensionsRequired");
    for (i, ext) in required.iter().enumerate() {
        if !SUPPORTED_EXTENSIONS.contains(&ext.as_str()) {
            return Err(err(
                path,
                format!("extensionsRequired[{i}]"),
                format!("the file requires the extension {ext}, which prism does not support"),
            )
            .hint(extension_hint(ext)));
        }
    }
    let ignored_extensions = list("extensionsUsed")
        .into_iter()
        .filter(|e| !SUPPORTED_EXTENSIONS.contains(&e.as_str()))
        .collect();
    // The crate does not know every extension prism reads from the raw JSON (dispersion):
    // it would refuse a file that requires one, so those are taken off its list.
    if let Some(Value::Array(a)) = json.get_mut("extensionsRequired") {
        a.retain(|v| v.as_str().is_some_and(|s| s != "KHR_materials_dispersion"));
    }
    check_position_indices(path, &json)?;
    checks::check_values(path, &json)?;
    animation::check_json(path, &json)?;
    accessors::check_extents(path, &json)?;
    let (doc, buffers, images) = document::load(path, json, blob, allow_outside)?;
    Ok(Model {
        doc,
        buffers,
        images,
        path: path.to_path_buf(),
        ignored_extensions,
    })
}

/// The crate's validator indexes `accessors` with each POSITION attribute unchecked (it would
/// panic on a bad index), so those indices are checked here first.
fn check_position_indices(path: &Path, json: &Value) -> Result<(), InputError> {
    let accessors = json
        .get("accessors")
        .and_then(Value::as_array)
        .map_or(0, Vec::len);
    let meshes = json.get("meshes").and_then(Value::as_array);
    for (i, m) in meshes.into_iter().flatten().enumerate() {
        let prims = m.get("primitives").and_then(Value::as_array);
        for (j, p) in prims.into_iter().flatten().enumerate() {
            if let Some(v) = p.pointer("/attributes/POSITION") {
                if v.as_u64().is_none_or(|k| k as usize >= accessors) {
                    return Err(err(
                        path,
                        format!("meshes[{i}].primitives[{j}].attributes.POSITION"),
                        format!(
                            "invalid glTF: accessor {v} does not exist (the file has {accessors})"
                        ),
                    )
                    .hint("check the file with the Khronos glTF validator"));
                }
            }
        }
    }
    Ok(())
}

/// True if `path` names a glTF file (by its extension).
pub fn is_gltf(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("gltf") || e.eq_ignore_ascii_case("glb"))
}

/// Appends an expanded glTF shape to the scene being built (`load::build`).
#[allow(clippy::too_many_arguments)]
pub(super) fn add_shapes(
    ex: Expanded,
    materials: &mut Vec<crate::bsdf::Material>,
    shapes: &mut Vec<crate::shape::Shape>,
    shape_material: &mut Vec<u32>,
    shape_emitter: &mut Vec<Option<u32>>,
    emitters: &mut Vec<crate::emitter::Emitter>,
    shape_name: &mut Vec<Option<String>>,
    material_names: &mut Vec<String>,
    punctual: &mut Vec<(
        String,
        crate::config::EmitterConfig,
        Option<crate::motion::Motion>,
    )>,
    moving: &mut Vec<(u32, crate::motion::Motion)>,
) {
    let first = materials.len() as u32;
    materials.extend(ex.materials);
    material_names.extend(ex.material_names);
    for s in ex.shapes {
        let mat = match s.material {
            MatRef::Scene(k) => k,
            MatRef::New(k) => first + k as u32,
        };
        let emitter = s.emission.map(|radiance| {
            let light =
                crate::emitter::AreaEmitter::with_radiance(shapes.len() as u32, &s.shape, radiance);
            // A moving node's shape is in object space: its light moves with it.
            emitters.push(match &s.motion {
                Some(m) => {
                    crate::emitter::Emitter::MovingArea(Box::new(crate::emitter::MovingArea {
                        area: light,
                        motion: m.clone(),
                        shape: s.shape.clone(),
                    }))
                }
                None => crate::emitter::Emitter::Area(light),
            });
            (emitters.len() - 1) as u32
        });
        if let Some(m) = s.motion {
            moving.push((shapes.len() as u32, m));
        }
        shapes.push(s.shape);
        shape_material.push(mat);
        shape_emitter.push(emitter);
        shape_name.push(s.name);
    }
    punctual.extend(ex.emitters);
}

#[cfg(test)]
mod tests {
    /// `prism render model.gltf` (`load::load` of a glTF file) reads the file once: the model
    /// read for its config is the one the build uses. A RON scene that includes it reads it
    /// once too.
    #[test]
    fn a_direct_render_reads_the_file_once() {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/gltf/Box.gltf");
        let opened = || super::OPENED.with(|n| n.get());
        let before = opened();
        let job = crate::load::load(&path, |_| {}).unwrap();
        assert_eq!(opened() - before, 1);
        assert_eq!(job.scene.primitive_count(), 12);
        assert!(job.inputs.contains(&path), "{:?}", job.inputs);
        // The model is used up: a second load reads it again (once).
        crate::load::load(&path, |_| {}).unwrap();
        assert_eq!(opened() - before, 2);
    }

    /// A device or FIFO as the glTF file or as one of its buffers or images, and a URI whose
    /// percent-decoding is not UTF-8, are errors naming the file and field, not a read that
    /// never ends (the fuzzer's `Gltf(path: "/dev/zero")` took 23 GB) or the crate's panic.
    #[test]
    fn devices_and_bad_uris_are_refused() {
        let dir = std::env::temp_dir().join(format!("prism-gltf-uris-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let e = super::open(std::path::Path::new("/dev/zero"))
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains("`/dev/zero` is a device"), "{e}");
        let doc = |buffer: &str, image: &str| {
            format!(
                r#"{{"asset": {{"version": "2.0"}}, "buffers": [{{"byteLength": 4, "uri": "{buffer}"}}], "images": [{{"uri": "{image}"}}]}}"#
            )
        };
        let ok_buf = "data:application/octet-stream;base64,AAAAAA==";
        for (buffer, image, want) in [
            ("/dev/zero", "a.png", "buffers[0].uri"),
            ("file:///dev/zero", "a.png", "buffers[0].uri"),
            ("%ff.bin", "a.png", "does not decode to UTF-8"),
            (ok_buf, "/dev/zero", "images[0].uri"),
        ] {
            let p = dir.join("m.gltf");
            std::fs::write(&p, doc(buffer, image)).unwrap();
            let e = super::open(&p).err().unwrap().to_string();
            assert!(
                e.contains(want) && e.contains("m.gltf"),
                "{buffer} {image}: {e}"
            );
            assert!(buffer == ok_buf || !e.contains("images"), "{e}");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
