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
    /// The shape's `id` (plus the part's index for a glTF part), else 1 + the shape's index
    /// in `shapes` (0 is the background in the id layers).
    pub instance_id: u32,
    pub name: String,
    /// The index in the config's `shapes` of the shape it was built from.
    pub shape: usize,
    pub label: Option<String>,
    /// 1 + the label's index in `Objects::labels`; 0 if unlabelled.
    pub label_id: u32,
    pub material: String,
    /// 1 + the material's index in `Objects::materials`.
    pub material_id: u32,
    /// The shape's `to_world`, or an instance's whole transform (a glTF part's: the shape's
    /// `to_world` times its node's world matrix); meshes and spheres may also place themselves
    /// in their own coordinates, and `bounds` is the world box of the rendered geometry.
    pub to_world: Mat4,
    pub bounds: (Vec3, Vec3),
}

#[derive(Clone, Debug, Default, PartialEq)]
pub struct Objects {
    /// One per built shape, except that a `one_object` glTF shape's parts are one object.
    pub list: Vec<Object>,
    /// The index in `list` of each built shape's object.
    pub of_shape: Vec<usize>,
    /// Distinct labels, sorted.
    pub labels: Vec<String>,
    /// Material names in scene order (a shape without a material gets "(default)").
    pub materials: Vec<String>,
}

impl Objects {
    /// Label id of each built shape (for the `label` layer).
    pub fn label_ids(&self) -> Vec<u32> {
        self.of_shape
            .iter()
            .map(|&k| self.list[k].label_id)
            .collect()
    }

    /// Instance id of each built shape (for the `instance` layer).
    pub fn instance_ids(&self) -> Vec<u32> {
        self.of_shape
            .iter()
            .map(|&k| self.list[k].instance_id)
            .collect()
    }
}

/// The scene's objects, one per built shape (a `one_object` glTF shape's parts: one in all,
/// named as the shape, with its `to_world`, its parts' union box and its first part's
/// material). `source[j]` is the config shape that built shape `j` (a `Gltf` shape builds one
/// per mesh primitive under its nodes), `material_names` the name of each of the scene's
/// materials.
pub fn objects(
    cfg: &SceneConfig,
    scene: &Scene,
    file: &Path,
    source: &[usize],
    material_names: Vec<String>,
) -> Result<Objects, InputError> {
    let labels = label_table(cfg, file)?;
    // A given table need not be sorted: ids by lookup, not by binary search.
    let label_index: BTreeMap<&str, u32> = labels
        .iter()
        .enumerate()
        .map(|(k, l)| (l.as_str(), k as u32))
        .collect();
    // Names the scene gives first: a repeat among them is the user's to fix.
    let mut seen: BTreeMap<String, usize> = BTreeMap::new();
    for (i, sc) in cfg.shapes.iter().enumerate() {
        if matches!(sc.shape, crate::config::ShapeKind::Gltf { .. }) && !sc.one_object {
            continue;
        }
        let name = sc.name.clone().unwrap_or_else(|| format!("shape{i}"));
        if let Some(j) = seen.insert(name.clone(), i) {
            return Err(InputError::new(
                file,
                format!("the name \"{name}\" is also the name of shapes[{j}]"),
            )
            .field(format!("shapes[{i}].name"))
            .hint("instance names must be unique (unnamed shapes are called shape<index>); rename one of them"));
        }
    }
    let mut taken: std::collections::BTreeSet<String> = seen.into_keys().collect();
    let mut list: Vec<Object> = Vec::with_capacity(scene.shapes.len());
    let mut of_shape = Vec::with_capacity(scene.shapes.len());
    let (mut ids, mut part) = (BTreeMap::new(), 0u32);
    for (j, shape) in scene.shapes.iter().enumerate() {
        let i = source[j];
        let sc = &cfg.shapes[i];
        let gltf = matches!(sc.shape, crate::config::ShapeKind::Gltf { .. });
        let field = format!("shapes[{i}].to_world");
        let mut to_world = geometry::transform(&sc.to_world, file, &field)?.m;
        let bounds = match shape {
            // Its vertices' bounds: the same box, without transforming each triangle.
            crate::shape::Shape::Instance(inst) => {
                if !sc.one_object {
                    to_world = inst.to_world.m;
                }
                inst.bounds()
            }
            _ => (0..shape.prim_count())
                .map(|k| shape.prim_geom(k).bounds())
                .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), (a, b)| {
                    (lo.min(a), hi.max(b))
                }),
        };
        let next = j > 0 && source[j - 1] == i;
        if gltf && sc.one_object && next {
            // A further part of one object: it widens the object's box.
            let o = list.last_mut().expect("the shape's first part is listed");
            o.bounds = (o.bounds.0.min(bounds.0), o.bounds.1.max(bounds.1));
            of_shape.push(list.len() - 1);
            continue;
        }
        let name = match (&scene.shape_name[j], gltf && !sc.one_object) {
            // A glTF part: its node's name, under the shape's own name if it has one; node
            // names need not be unique (nor are a node's primitives), so repeats get #2, #3, ….
            (part, true) => {
                let part = part.clone().unwrap_or_else(|| format!("part{j}"));
                let base = match &sc.name {
                    Some(n) => format!("{n}/{part}"),
                    None => part,
                };
                let mut name = base.clone();
                let mut k = 1;
                while taken.contains(&name) {
                    k += 1;
                    name = format!("{base}#{k}");
                }
                taken.insert(name.clone());
                name
            }
            (_, false) => sc.name.clone().unwrap_or_else(|| format!("shape{i}")),
        };
        let m = scene.shape_material[j];
        // A given id counts the shape's parts from it.
        part = if next { part + 1 } else { 0 };
        let instance_id = match sc.id {
            Some(id) => id.checked_add(part).ok_or_else(|| {
                InputError::new(file, format!("instance id {id} + part {part} overflows"))
                    .field(format!("shapes[{i}].id"))
                    .hint("give a smaller id")
            })?,
            None => j as u32 + 1,
        };
        if let Some(&k) = ids.get(&instance_id) {
            let other: &Object = &list[k];
            return Err(InputError::new(
                file,
                format!("instance id {instance_id} is also the id of \"{}\"", other.name),
            )
            .field(format!("shapes[{i}].id"))
            .hint("instance ids must be unique (a glTF shape's parts take id, id + 1, …; shapes without `id` take 1 + their index)"));
        }
        ids.insert(instance_id, list.len());
        of_shape.push(list.len());
        list.push(Object {
            instance_id,
            name,
            shape: i,
            label: sc.label.clone(),
            label_id: sc
                .label
                .as_ref()
                .map_or(0, |l| label_index.get(l.as_str()).map_or(0, |&k| k + 1)),
            material: material_names[m as usize].clone(),
            material_id: m + 1,
            to_world,
            bounds,
        });
    }
    Ok(Objects {
        list,
        of_shape,
        labels,
        materials: material_names,
    })
}

/// The class table: the scene's `labels`, each shape's label among them, or else the shapes'
/// distinct labels, sorted.
fn label_table(cfg: &SceneConfig, file: &Path) -> Result<Vec<String>, InputError> {
    if cfg.labels.is_empty() {
        let set: std::collections::BTreeSet<_> =
            cfg.shapes.iter().filter_map(|s| s.label.clone()).collect();
        return Ok(set.into_iter().collect());
    }
    for (k, l) in cfg.labels.iter().enumerate() {
        if cfg.labels[..k].contains(l) {
            return Err(
                InputError::new(file, format!("the label \"{l}\" is listed twice"))
                    .field(format!("labels[{k}]"))
                    .hint("list each label once"),
            );
        }
    }
    for (i, s) in cfg.shapes.iter().enumerate() {
        if let Some(l) = s.label.as_ref().filter(|l| !cfg.labels.contains(l)) {
            return Err(InputError::new(file, format!("the label \"{l}\" is not in `labels`"))
                .field(format!("shapes[{i}].label"))
                .hint("add it to the scene's `labels`, or leave `labels` out to number the shapes' labels in sorted order"));
        }
    }
    Ok(cfg.labels.clone())
}

/// The `aovs` list by name; unknown or repeated names are errors that list the valid ones.
pub fn aovs(names: &[String], file: &Path) -> Result<Vec<Aov>, InputError> {
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
        out.push(a);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    /// A RON scene with a glTF shape before and after its own shapes: one object per built
    /// shape, each with its own name, material and id, the glTF parts named after their nodes
    /// (SimpleMeshes: one mesh under two unnamed nodes -> node0, node1; with the shape's name
    /// as prefix), and an empty glTF scene adding no object (the fuzzer found it panicking).
    #[test]
    fn gltf_parts_are_objects_of_their_own() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let dir = std::env::temp_dir().join(format!("prism-objects-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let simple = root.join("tests/data/gltf/SimpleMeshes.gltf");
        let empty = dir.join("empty.gltf");
        std::fs::write(
            &empty,
            r#"{"asset": {"version": "2.0"}, "scenes": [{"nodes": []}], "scene": 0}"#,
        )
        .unwrap();
        let scene = dir.join("s.ron");
        std::fs::write(
            &scene,
            format!(
                r#"(
            film: (width: 8, height: 6),
            materials: {{"red": Diffuse(reflectance: Constant(0.5))}},
            shapes: [
                (shape: Gltf(path: "{}"), name: "pair", label: "toy"),
                (shape: Sphere(radius: 0.1), material: "red", name: "ball"),
                (shape: Gltf(path: "{}")),
                (shape: Gltf(path: "{}"), material: "red"),
            ],
            emitters: [Constant(radiance: Named("D65"))],
        )"#,
                simple.display(),
                empty.display(),
                simple.display()
            ),
        )
        .unwrap();
        let job = crate::load::load(&scene, |_| {}).unwrap();
        let o = &job.objects;
        let names: Vec<&str> = o.list.iter().map(|x| x.name.as_str()).collect();
        assert_eq!(
            names,
            ["pair/node0", "pair/node1", "ball", "node0", "node1"]
        );
        assert_eq!(o.list.len(), job.scene.shapes.len());
        let ids: Vec<u32> = o.list.iter().map(|x| x.instance_id).collect();
        assert_eq!(ids, [1, 2, 3, 4, 5]);
        assert_eq!(o.list[0].label.as_deref(), Some("toy"));
        assert_eq!(o.list[1].label_id, 1);
        assert_eq!(o.list[2].label_id, 0);
        for k in [2, 3, 4] {
            assert_eq!(o.list[k].material, "red", "{:?}", o.list[k]);
        }
        // SimpleMeshes has no materials: the glTF default material.
        assert_eq!(o.list[0].material, "(glTF default)");
        // The second node is translated by +1 in x: its world box shows it.
        assert!((o.list[1].bounds.0.x - o.list[0].bounds.0.x - 1.0).abs() < 1e-6);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// Given ids and a class table: a glTF shape's parts count up from its `id`, labels take
    /// their place in `labels`; a repeated id, a label missing from `labels` or listed twice
    /// are refused naming the field.
    #[test]
    fn given_ids_and_labels_are_used_and_checked() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let simple = root.join("tests/data/gltf/SimpleMeshes.gltf");
        let scene = |id: u32, labels: &str, ball: &str| {
            format!(
                r#"(film: (width: 8, height: 6), labels: [{labels}],
                shapes: [
                    (shape: Gltf(path: "{}"), id: 10, label: "toy"),
                    (shape: Sphere(radius: 0.1), name: "ball", id: {id}, label: "{ball}"),
                ],
                emitters: [Constant(radiance: Named("D65"))])"#,
                simple.display()
            )
        };
        let file = root.join("scenes/given_ids.ron");
        let job = crate::load::load_str(&scene(3, "\"zebra\", \"toy\"", "zebra"), &file).unwrap();
        let ids: Vec<(u32, u32)> = job
            .objects
            .list
            .iter()
            .map(|o| (o.instance_id, o.label_id))
            .collect();
        assert_eq!(ids, [(10, 2), (11, 2), (3, 1)]);
        assert_eq!(job.objects.labels, ["zebra", "toy"]);
        let cases = [
            (
                scene(11, "\"zebra\", \"toy\"", "zebra"),
                "shapes[1].id",
                "instance id 11 is also the id of",
            ),
            (
                scene(3, "\"toy\"", "zebra"),
                "shapes[1].label",
                "\"zebra\" is not in `labels`",
            ),
            (
                scene(3, "\"toy\", \"zebra\", \"toy\"", "zebra"),
                "labels[2]",
                "listed twice",
            ),
        ];
        for (text, field, needle) in cases {
            let Err(e) = crate::load::load_str(&text, &file) else {
                panic!("{field}: accepted")
            };
            let msg = e.to_string();
            assert!(msg.contains(field) && msg.contains(needle), "{msg}");
        }
    }
}
