//! `textures: [(target: "paint", folder: "textures/wood")]`: a material's base reflectance
//! becomes a bitmap texture drawn per frame, uniformly, from the image files in a folder
//! (PNG, JPEG, OpenEXR, Radiance HDR, as `Bitmap` reads; sorted by name, so the list does not
//! depend on the file system's order). Listed and checked at load (a missing or empty folder,
//! an image whose header cannot be read, a material without a base reflectance: exit 2), hashed
//! into `dataset.json` like every input, and named in the frame's JSON relative to the config.

use super::apply;
use super::base::Base;
use super::vary::{Rng, Stream};
use crate::config::{SceneConfig, SpectrumConfig};
use crate::error::InputError;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// The image extensions a folder's files are taken by (lower case).
pub const EXTENSIONS: [&str; 5] = ["png", "jpg", "jpeg", "exr", "hdr"];

/// Each texture variation's files: (as the frame's JSON names it, absolute path).
pub type Listed = Vec<Vec<(String, PathBuf)>>;

/// Lists and checks every texture variation's folder.
pub fn load(base: &Base) -> Result<Listed, InputError> {
    let dir = base.file.parent().unwrap_or(Path::new("."));
    let mut all = Vec::new();
    for (k, t) in base.config.textures.iter().enumerate() {
        let field = format!("textures[{k}]");
        let mut m = base
            .scene
            .materials
            .get(&t.target)
            .cloned()
            .ok_or_else(|| {
                let known: Vec<&String> = base.scene.materials.keys().collect();
                base.err(
                    &format!("{field}.target"),
                    format!("the scene has no material \"{}\"", t.target),
                )
                .hint(format!("the materials are: {known:?}"))
            })?;
        if apply::reflectance_slot(&mut m).is_none() {
            return Err(base
                .err(
                    &format!("{field}.target"),
                    format!(
                        "material \"{}\" has no base reflectance to texture",
                        t.target
                    ),
                )
                .hint("texture a diffuse, plastic or conductor material"));
        }
        let folder = dir.join(&t.folder);
        let f = format!("{field}.folder");
        let listed =
            super::files::list_files(&folder, &EXTENSIONS, "PNG, JPEG, EXR or HDR image", |m| {
                base.err(&f, m)
            })?;
        let files: Vec<(String, PathBuf)> = listed
            .into_iter()
            .map(|(name, p)| {
                let shown = Path::new(&t.folder).join(name);
                (shown.to_string_lossy().into_owned(), p)
            })
            .collect();
        for (j, (name, p)) in files.iter().enumerate() {
            header(p).map_err(|e| {
                base.err(&f, format!("image {j} `{name}`: {e}"))
                    .hint("remove or re-export the file; every image in the folder is drawn")
            })?;
        }
        all.push(files);
    }
    Ok(all)
}

/// Reads the image's header only (its size), as a cheap check that the frame can load it.
fn header(p: &Path) -> Result<(), String> {
    let is_exr = p.extension().is_some_and(|e| e.eq_ignore_ascii_case("exr"));
    if is_exr {
        let f = std::fs::File::open(p).map_err(|e| e.to_string())?;
        exr::meta::MetaData::read_from_buffered(std::io::BufReader::new(f), false)
            .map(|_| ())
            .map_err(|e| format!("cannot read OpenEXR: {e}"))
    } else {
        image::ImageReader::open(p)
            .and_then(|r| r.with_guessed_format())
            .map_err(|e| e.to_string())?
            .into_dimensions()
            .map(|_| ())
            .map_err(|e| format!("cannot read image: {e}"))
    }
}

/// Every texture file, for `dataset.json`'s hashes.
pub fn paths(listed: &Listed) -> Vec<PathBuf> {
    listed.iter().flatten().map(|(_, p)| p.clone()).collect()
}

/// Frame `i`'s draws into `scene`; the JSON of what was drawn (None without textures).
pub fn draw(base: &Base, i: u32, scene: &mut SceneConfig) -> Option<Value> {
    let mut out = Vec::new();
    for (k, t) in base.config.textures.iter().enumerate() {
        let files = &base.textures[k];
        let mut r = Rng::new(base.config.seed, i, Stream::Texture(k));
        let (name, path) = &files[r.index(files.len())];
        let mat = scene.materials.get_mut(&t.target).expect("checked at load");
        *apply::reflectance_slot(mat).expect("checked at load") = SpectrumConfig::Bitmap {
            path: super::plan::absolute(path),
            filter: Default::default(),
            wrap: Default::default(),
            raw: false,
            uv_scale: (1.0, 1.0),
            uv_offset: (0.0, 0.0),
        };
        out.push(json!({"target": t.target, "file": name}));
    }
    (!out.is_empty()).then_some(Value::Array(out))
}
