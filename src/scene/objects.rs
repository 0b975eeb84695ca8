//! The scene's objects as a vision dataset names them: each shape's instance id, name, label
//! and material, for the id AOVs and the sidecar.

use super::{geometry, Scene};
use crate::config::SceneConfig;
use crate::error::InputError;
use crate::film::Aov;
use glam::{Mat4, Vec3};
use std::collections::BTreeMap;
use std::path::Path;

#[derive(Clone, Debug, PartialEq)]
pub struct Object {
    /// 1 + the shape's index in `shapes` (0 is the background in the id layers).
    pub instance_id: u32,
    pub name: String,
    pub label: Option<String>,
    /// 1 + the label's index in `Objects::labels`; 0 if unlabelled.
    pub label_id: u32,
    pub material: String,
    /// 1 + the material's index in `Objects::materials`.
    pub material_id: u32,
    /// The shape's `to_world` (meshes and spheres may also place themselves in their own
    /// coordinates; `bounds` is the world box of the rendered geometry).
    pub to_world: Mat4,
    pub bounds: (Vec3, Vec3),
}

#[derive(Clone, Debug, Default, PartialEq)]
pub struct Objects {
    pub list: Vec<Object>,
    /// Distinct labels, sorted.
    pub labels: Vec<String>,
    /// Material names in scene order (a shape without a material gets "(default)").
    pub materials: Vec<String>,
}

impl Objects {
    /// Label id of each shape (for the `label` layer).
    pub fn label_ids(&self) -> Vec<u32> {
        self.list.iter().map(|o| o.label_id).collect()
    }
}

pub fn objects(cfg: &SceneConfig, scene: &Scene, file: &Path) -> Result<Objects, InputError> {
    let mut materials: Vec<String> = cfg.materials.keys().cloned().collect();
    if materials.len() < scene.materials.len() {
        materials.push("(default)".into());
    }
    let labels: Vec<String> = cfg
        .shapes
        .iter()
        .filter_map(|s| s.label.clone())
        .collect::<std::collections::BTreeSet<_>>()
        .into_iter()
        .collect();
    let mut seen: BTreeMap<String, usize> = BTreeMap::new();
    let mut list = Vec::with_capacity(cfg.shapes.len());
    for (i, sc) in cfg.shapes.iter().enumerate() {
        let name = sc.name.clone().unwrap_or_else(|| format!("shape{i}"));
        if let Some(j) = seen.insert(name.clone(), i) {
            return Err(InputError::new(
                file,
                format!("the name \"{name}\" is also the name of shapes[{j}]"),
            )
            .field(format!("shapes[{i}].name"))
            .hint("instance names must be unique (unnamed shapes are called shape<index>); rename one of them"));
        }
        let to_world = geometry::transform(&sc.to_world, file, &format!("shapes[{i}].to_world"))?.m;
        let shape = &scene.shapes[i];
        let bounds = match shape {
            // Its vertices' bounds: the same box, without transforming each triangle.
            crate::shape::Shape::Instance(inst) => inst.bounds(),
            _ => (0..shape.prim_count())
                .map(|k| shape.prim_geom(k).bounds())
                .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), (a, b)| {
                    (lo.min(a), hi.max(b))
                }),
        };
        let m = scene.shape_material[i];
        list.push(Object {
            instance_id: i as u32 + 1,
            name,
            label: sc.label.clone(),
            label_id: sc
                .label
                .as_ref()
                .map_or(0, |l| labels.binary_search(l).map_or(0, |k| k as u32 + 1)),
            material: materials[m as usize].clone(),
            material_id: m + 1,
            to_world,
            bounds,
        });
    }
    Ok(Objects {
        list,
        labels,
        materials,
    })
}

/// The `aovs` list by name; unknown or repeated names are errors that list the valid ones.
/// `caustics`: the scene traces caustics from the lights, whose splats have no per-pixel
/// samples for `stderr`.
pub fn aovs(names: &[String], caustics: bool, file: &Path) -> Result<Vec<Aov>, InputError> {
    let mut out = Vec::with_capacity(names.len());
    for (i, n) in names.iter().enumerate() {
        let Some(a) = Aov::parse(n.trim()) else {
            return Err(InputError::new(file, format!("unknown AOV \"{n}\""))
                .field(format!("aovs[{i}]"))
                .hint(format!(
                    "the AOVs are: {} (in the scene's `aovs` or `--aovs`)",
                    Aov::names()
                )));
        };
        if out.contains(&a) {
            return Err(
                InputError::new(file, format!("the AOV \"{n}\" is listed twice"))
                    .field(format!("aovs[{i}]"))
                    .hint("list each AOV once"),
            );
        }
        if a == Aov::Stderr && caustics {
            return Err(InputError::new(
                file,
                "the stderr AOV cannot be measured with caustic light tracing (its light paths are not per-pixel samples)",
            )
            .field(format!("aovs[{i}]"))
            .hint("remove \"stderr\" or turn caustics off (`--caustics off`)"));
        }
        out.push(a);
    }
    Ok(out)
}
