//! `objects: (assets: (folder: "assets", classes: "classes.csv", material: "plastic", size: 0.3,
//! shown: (1, 3)))`: objects drawn per frame from a folder of OBJ/PLY meshes and glTF models.
//!
//! Every file of the folder (sorted by name) joins the base scene as a shape named
//! `asset:<file name>`, labelled with the class of the first line of `classes` whose pattern
//! matches its file name, scaled about the origin so its bounding box's longest side is `size`.
//! A mesh takes `material`; a glTF model (`.gltf`, `.glb`) keeps its own materials and, however
//! many meshes, nodes and materials it has, is one object (`one_object`): one class, one
//! instance id, placed and scaled as a whole. Its punctual lights are left out (an asset is an
//! object, not a light rig).
//! So its instance id and its class id are fixed per dataset in `dataset.json`, as the base
//! scene's are; each frame shows a uniform number in `shown` of them (a uniform subset; the rest
//! are hidden, keeping their ids) and stands them on the support with the `objects.place` code.
//!
//! `classes` is a text file of `pattern,class` lines (`#` comments); a pattern is a file name
//! with `*` (any run of characters) and `?` (one character). Hand-written matching: those two
//! wildcards on one file name need no glob crate.

use super::base::Base;
use super::config::{AssetFolder, DatasetConfig, Placement};
use super::vary::{Rng, Stream};
use crate::config::{SceneConfig, ShapeConfig, ShapeKind, TransformOp};
use crate::error::InputError;
use glam::Vec3;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// The extensions of the files an asset folder takes (lower case).
pub const EXTENSIONS: [&str; 4] = ["obj", "ply", "gltf", "glb"];

/// One file of the folder: its shape name, absolute path and class.
#[derive(Clone, Debug)]
pub struct Asset {
    pub name: String,
    pub path: PathBuf,
    pub class: String,
    /// A glTF model (one object of many parts), else an OBJ or PLY mesh.
    pub gltf: bool,
}

/// The folder's meshes with their classes, checked (folder, mapping file, every file matched).
pub fn list(config: &DatasetConfig, file: &Path) -> Result<Vec<Asset>, InputError> {
    let Some(a) = &config.objects.assets else {
        return Ok(Vec::new());
    };
    let dir = file.parent().unwrap_or(Path::new("."));
    let err = |field: &str, m: String| {
        // Each caller replaces this hint with its own.
        InputError::new(file, m)
            .field(format!("objects.assets.{field}"))
            .hint("configs/README.md documents objects.assets")
    };
    if config.objects.place.is_none() {
        return Err(err("folder", "assets need `objects.place` to stand them on a support".into())
            .hint("add `place: (support: \"table\", shapes: [])`: the drawn assets are placed with the listed shapes"));
    }
    if !(a.size.is_finite() && a.size > 0.0) {
        return Err(
            err("size", format!("size {} must be a positive length", a.size)).hint(
                "the longest side of each asset's bounding box after scaling, in scene units",
            ),
        );
    }
    let csv = dir.join(&a.classes);
    let text = crate::io::input_file::read(&csv, crate::io::input_file::Kind::Asset)
        .and_then(|b| String::from_utf8(b).map_err(|_| "is not UTF-8 text".to_string()))
        .map_err(|m| {
            err("classes", format!("`{}`: {m}", csv.display()))
                .hint("give a text file of `pattern,class` lines, relative to the dataset config")
        })?;
    let mut rules = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let Some((p, c)) = line
            .split_once(',')
            .filter(|(p, c)| !p.trim().is_empty() && !c.trim().is_empty())
        else {
            return Err(err(
                "classes",
                format!(
                    "`{}` line {}: `{line}` is not `pattern,class`",
                    csv.display(),
                    n + 1
                ),
            )
            .hint("write one `pattern,class` per line, e.g. `mug_*.obj,mug`"));
        };
        rules.push((p.trim().to_string(), c.trim().to_string()));
    }
    let folder = dir.join(&a.folder);
    let files = super::files::list_files(&folder, &EXTENSIONS, "OBJ, PLY or glTF", |m| {
        err("folder", m)
    })?;
    let mut out = Vec::new();
    for (name, p) in files {
        let Some((_, class)) = rules.iter().find(|(pat, _)| matches(pat, &name)) else {
            return Err(err(
                "classes",
                format!("no line of `{}` matches `{name}`", csv.display()),
            )
            .hint(
                "add a pattern for it, or a last line `*,other` for every file not matched before",
            ));
        };
        let path = std::path::absolute(&p).unwrap_or(p);
        let gltf = crate::load::gltf::is_gltf(&path);
        if gltf {
            // Checked here, so a broken model is refused naming the folder's file and the
            // field (the base scene's build would name a shape the user never wrote).
            crate::load::gltf::open(&path).map_err(|e| {
                err("folder", format!("`{name}`: {}", e.message)).hint(format!(
                    "{}; or remove the file from the folder",
                    e.hint
                        .unwrap_or_else(|| "re-export the model as glTF 2.0".into())
                ))
            })?;
        }
        out.push(Asset {
            name: format!("asset:{name}"),
            path,
            class: class.clone(),
            gltf,
        });
    }
    if a.shown.0 > a.shown.1 || a.shown.1 as usize > out.len() {
        return Err(err(
            "shown",
            format!(
                "shown ({}, {}) must lie in 0..={} (the folder's files), lo ≤ hi",
                a.shown.0,
                a.shown.1,
                out.len()
            ),
        )
        .hint(format!("write shown: (lo, hi) with hi ≤ {}", out.len())));
    }
    Ok(out)
}

/// Whether `name` matches `pattern` (`*`: any run, `?`: one character).
pub fn matches(pattern: &str, name: &str) -> bool {
    let (p, n): (Vec<char>, Vec<char>) = (pattern.chars().collect(), name.chars().collect());
    // Backtracking to the last `*`: linear in practice, quadratic at worst on file names.
    let (mut i, mut j, mut star, mut mark) = (0, 0, None, 0);
    while j < n.len() {
        if i < p.len() && (p[i] == '?' || p[i] == n[j]) {
            i += 1;
            j += 1;
        } else if i < p.len() && p[i] == '*' {
            star = Some(i);
            mark = j;
            i += 1;
        } else if let Some(s) = star {
            i = s + 1;
            mark += 1;
            j = mark;
        } else {
            return false;
        }
    }
    p[i..].iter().all(|&c| c == '*')
}

/// Appends the assets to the base scene as shapes (before it is built).
pub fn append(assets: &[Asset], material: Option<&AssetFolder>, scene: &mut SceneConfig) {
    let Some(a) = material else { return };
    for x in assets {
        let path = x.path.to_string_lossy().into_owned();
        let shape = if x.gltf {
            ShapeKind::Gltf {
                path,
                materials: Default::default(),
                lights: false,
                allow_outside: false,
                animation: None,
            }
        } else {
            ShapeKind::Mesh { path }
        };
        scene.shapes.push(ShapeConfig {
            shape,
            // A model keeps its own materials; `material` would replace them all.
            material: (!x.gltf).then(|| a.material.clone()),
            emitter: None,
            to_world: Vec::new(),
            animation: None,
            flip_normals: false,
            name: Some(x.name.clone()),
            label: Some(x.class.clone()),
            id: None,
            one_object: x.gltf,
        });
    }
}

/// Scales each asset (the last `assets.len()` shapes) about the origin so its box's longest
/// side is `size`, and its bounds with it (a glTF model's box: all its parts', after its node
/// transforms, which `to_world` follows).
pub fn normalise(
    assets: &[Asset],
    size: f32,
    scene: &mut SceneConfig,
    bounds: &mut [(Vec3, Vec3)],
) {
    let first = scene.shapes.len() - assets.len();
    let shapes = scene.shapes[first..].iter_mut();
    for (shape, b) in shapes.zip(&mut bounds[first..]) {
        let (lo, hi) = *b;
        let s = size / (hi - lo).max_element().max(f32::MIN_POSITIVE);
        shape.to_world = vec![TransformOp::Scale([s; 3])];
        *b = (lo * s, hi * s);
    }
}

/// Frame `i`'s assets: which show (the rest hidden in `shown`), the placement extended by them,
/// and what was drawn.
pub fn draw(base: &Base, i: u32, shown: &mut [bool]) -> Option<(Placement, Value)> {
    let a = base.config.objects.assets.as_ref()?;
    let n = base.assets.len();
    let first = shown.len() - n;
    let mut r = Rng::new(base.config.seed, i, Stream::Assets);
    let k = r.int(a.shown.0, a.shown.1) as usize;
    let pick = r.subset(n, k);
    for j in 0..n {
        shown[first + j] = pick.contains(&j);
    }
    let mut p = base.config.objects.place.clone().expect("checked at load");
    let names: Vec<&String> = pick.iter().map(|&j| &base.assets[j].name).collect();
    p.shapes.extend(names.iter().map(|s| s.to_string()));
    Some((p, json!(names)))
}

#[cfg(test)]
mod tests {
    use super::matches;

    #[test]
    fn patterns_match_file_names() {
        assert!(matches("mug_*.obj", "mug_01.obj"));
        assert!(matches("*", "anything.ply"));
        assert!(matches("chair_??.ply", "chair_12.ply"));
        assert!(!matches("chair_??.ply", "chair_123.ply"));
        assert!(matches("*a*b*", "xxaxxbxx"));
        assert!(!matches("mug_*.obj", "mug_01.ply"));
        assert!(matches("*.obj", ".obj"));
    }
}
