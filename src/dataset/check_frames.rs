//! Bad input refused before the first frame (exit 2, nothing written): every selected frame is
//! planned, and the scene of each frame whose structure is new (which shapes, which of them and
//! of the camera and lights move, the shutter open or not, the layers) is built as its render
//! would build it. A structure is built once, so a video dataset builds one scene per distinct
//! set of shapes, not one per frame, and `--check` stays fast. An error names the dataset
//! field that made the frame's scene (`motion.objects[i]`, `objects.assets`, `motion.shutter`,
//! ...), with the scene's own file, field and fix inside it.

use super::base::Base;
use super::plan;
use crate::config::SceneConfig;
use crate::error::InputError;
use serde_json::{json, Value};
use std::collections::HashSet;
use std::path::Path;

/// Plans every frame of `frames` and builds the scene of each new structure; the number of
/// scenes built.
pub fn check(base: &Base, frames: &[u32]) -> Result<usize, InputError> {
    let mut seen = HashSet::new();
    for &i in frames {
        let p = plan::plan(base, i)?;
        if !seen.insert(structure(&p.scene)) {
            continue;
        }
        let cause = |e: InputError| refused(base, i, &p.scene, e, true);
        crate::load::build(p.scene.clone(), &base.scene_file).map_err(cause)?;
    }
    Ok(seen.len())
}

/// What decides which of the loader's checks a frame's scene meets: its shapes (kind and file,
/// moving or not, emitting or not), whether the camera and each light move, whether the shutter
/// stays open, and the layers. Drawn numbers are left out (the variations' extremes are checked
/// at load: `base::extremes`).
fn structure(s: &SceneConfig) -> String {
    let shapes: Vec<Value> = s
        .shapes
        .iter()
        .map(|x| {
            json!([
                x.shape,
                x.animation.is_some(),
                x.emitter.is_some(),
                x.flip_normals
            ])
        })
        .collect();
    let lights: Vec<Value> = s
        .emitters
        .iter()
        .map(|e| {
            let v = serde_json::to_value(e).unwrap_or(Value::Null);
            let kind = v.as_object().and_then(|o| o.keys().next().cloned());
            let moving = v.pointer(&format!("/{}/animation", kind.as_deref().unwrap_or("")));
            json!([kind, moving.is_some_and(|m| !m.is_null())])
        })
        .collect();
    let open = s
        .camera
        .shutter
        .is_some_and(|sh| sh.close > sh.open || sh.readout > 0.0);
    let camera = (s.camera.animation.is_some(), s.camera.fps.is_some());
    json!([
        shapes,
        lights,
        open,
        camera,
        s.aovs,
        s.integrator.caustics.is_some()
    ])
    .to_string()
}

/// The error of frame `i`'s scene `scene` as the dataset's: the field of the config that made
/// it, the scene's own words inside. `planned`: the frame's plan is whole, so `--export-frame`
/// can write its scene (not so for an error raised while the plan draws the camera's pose).
pub(super) fn refused(
    base: &Base,
    i: u32,
    scene: &SceneConfig,
    e: InputError,
    planned: bool,
) -> InputError {
    let field = cause(base, scene, &e);
    let at = e.field.as_ref().map_or(String::new(), |f| format!(" {f}:"));
    let inner = format!("{}:{at} {}", e.file.display(), e.message);
    let fix = match planned {
        true => format!(
            "or change the dataset's `{field}` (`prism dataset {} --export-frame {i}` writes the frame's scene)",
            base.file.display()
        ),
        false => format!("change the dataset's `{field}`: the values it drew make this"),
    };
    InputError::new(
        &base.file,
        format!("frame {i}'s scene, as the dataset draws it, is refused: {inner}"),
    )
    .field(&field)
    // The scene's own hint speaks of steps the user wrote, and a drawn pose has none.
    .hint(match e.hint {
        Some(h) if planned => format!("{h}; {fix}"),
        _ => fix,
    })
}

/// The dataset field behind error `e` of a frame's scene `scene`.
fn cause(base: &Base, scene: &SceneConfig, e: &InputError) -> String {
    let c = &base.config;
    let motion = c.motion.clone().unwrap_or_default();
    let dir = base.scene_file.parent().unwrap_or(Path::new("."));
    let field = e.field.as_deref().unwrap_or("");
    // The shape it names: by its field in the scene, or as the file a glTF shape includes.
    let index = |prefix: &str| {
        let rest = field.strip_prefix(prefix)?;
        rest[..rest.find(']')?].parse::<usize>().ok()
    };
    let shape = index("shapes[")
        .filter(|_| e.file == base.scene_file)
        .or_else(|| {
            scene.shapes.iter().position(|s| match &s.shape {
                crate::config::ShapeKind::Gltf { path, .. } => dir.join(path) == e.file,
                _ => false,
            })
        })
        .and_then(|k| scene.shapes.get(k));
    if let Some(name) = shape.and_then(|s| s.name.as_deref()) {
        if let Some(j) = motion
            .objects
            .iter()
            .position(|o| o.shapes.iter().any(|n| n == name))
        {
            return format!("motion.objects[{j}]");
        }
        if let Some(j) = motion
            .lights
            .iter()
            .position(|l| l.targets.iter().any(|n| n == name))
        {
            return format!("motion.lights[{j}]");
        }
        if base.assets.iter().any(|a| a.name == name) {
            return "objects.assets".into();
        }
    }
    if let Some(k) = index("emitters[") {
        let target = format!("emitters[{k}]");
        if let Some(j) = motion
            .lights
            .iter()
            .position(|l| l.targets.contains(&target))
        {
            return format!("motion.lights[{j}]");
        }
    }
    let open = ["integrator.caustics", "camera.shutter"];
    if motion.shutter > 0.0 && open.iter().any(|f| field.starts_with(f)) {
        return "motion.shutter".into();
    }
    if field.starts_with("camera.animation") && motion.camera.is_some() {
        return "motion.camera".into();
    }
    if field.starts_with("aovs") || e.message.contains("flow layers") {
        return "outputs.aovs".into();
    }
    "scene".into()
}
