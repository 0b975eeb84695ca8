//! From a glTF file's checked JSON to the crate's document, with its buffers and images loaded:
//! each external URI checked (inside the model's folder unless the shape allows otherwise) and
//! recorded as an input, and each load failure an error naming the JSON field.

use super::{accessors, err, uris};
use crate::error::InputError;
use crate::io::input_file::Kind;
use serde_json::Value;
use std::path::Path;

/// The crate's document, its buffers and its images.
type Loaded = (
    gltf::Document,
    Vec<gltf::buffer::Data>,
    Vec<gltf::image::Data>,
);

/// The document, its buffers and its images; `blob` is a GLB's BIN chunk.
pub(super) fn load(
    path: &Path,
    json: Value,
    blob: Option<Vec<u8>>,
    allow_outside: bool,
) -> Result<Loaded, InputError> {
    let root: gltf::json::Root = serde_json::from_value(json).map_err(|e| {
        InputError::new(path, format!("not a valid glTF 2.0 document: {e}"))
            .hint("check the file with the Khronos glTF validator")
    })?;
    let doc = gltf::Document::from_json(root).map_err(|e| match e {
        gltf::Error::Validation(errs) => {
            let (p, first) = &errs[0];
            err(
                path,
                p.to_string(),
                format!(
                    "invalid glTF: {first}{}",
                    if errs.len() > 1 {
                        format!(" (and {} more problems)", errs.len() - 1)
                    } else {
                        String::new()
                    }
                ),
            )
            .hint("check the file with the Khronos glTF validator")
        }
        e => InputError::new(path, format!("invalid glTF: {e}"))
            .hint("check the file with the Khronos glTF validator"),
    })?;
    let base = path.parent().unwrap_or(Path::new("."));
    let mut blob = blob;
    let mut buffers = Vec::new();
    for b in doc.buffers() {
        let field = format!("buffers[{}]", b.index());
        let what = match b.source() {
            gltf::buffer::Source::Uri(u) if u.starts_with("data:") => "its data URI".to_string(),
            gltf::buffer::Source::Uri(u) => {
                crate::io::inputs::record(&base.join(u));
                uris::check_external(
                    path,
                    base,
                    u,
                    Kind::Gltf,
                    &format!("{field}.uri"),
                    allow_outside,
                )?;
                format!("\"{u}\"")
            }
            gltf::buffer::Source::Bin => "the GLB's BIN chunk".to_string(),
        };
        let data =
            gltf::buffer::Data::from_source_and_blob(b.source(), Some(base), &mut blob).map_err(
                |e| {
                    err(path, format!("{field}.uri"), format!("cannot load {what}: {e}")).hint(
                    "external buffers (.bin) are relative to the glTF file: keep them beside it",
                )
                },
            )?;
        if data.len() < b.length() {
            return Err(err(
                path,
                format!("{field}.byteLength"),
                format!(
                    "{what} holds {} bytes but byteLength says {}",
                    data.len(),
                    b.length()
                ),
            )
            .hint("the buffer file is truncated or is not this model's; re-export the model"));
        }
        buffers.push(data);
    }
    accessors::check_sparse(path, &doc, &buffers)?;
    let mut images = Vec::new();
    for im in doc.images() {
        let field = format!("images[{}]", im.index());
        let what = match im.source() {
            gltf::image::Source::Uri { uri, .. } if uri.starts_with("data:") => {
                "its data URI".to_string()
            }
            gltf::image::Source::Uri { uri, .. } => {
                crate::io::inputs::record(&base.join(uri));
                uris::check_external(
                    path,
                    base,
                    uri,
                    Kind::Texture,
                    &format!("{field}.uri"),
                    allow_outside,
                )?;
                format!("\"{uri}\"")
            }
            gltf::image::Source::View { view, .. } => format!("bufferViews[{}]", view.index()),
        };
        let data =
            gltf::image::Data::from_source(im.source(), Some(base), &buffers).map_err(|e| {
                err(
                    path,
                    field.clone(),
                    format!("cannot load the image {what}: {e}"),
                )
                .hint("images are PNG or JPEG, relative to the glTF file: keep them beside it")
            })?;
        images.push(data);
    }
    Ok((doc, buffers, images))
}
