//! The node tree: transforms composed from the root down, mesh primitives read into world-space
//! meshes named after their node, cameras and lights collected with their world transforms.

use super::lights::{self, GltfCamera, GltfLight};
use super::materials::GltfMaterials;
use super::Model;
use crate::bsdf::Material;
use crate::config::{EmitterConfig, ShapeConfig, ShapeKind};
use crate::emitter::AreaRadiance;
use crate::error::InputError;
use crate::math::Transform;
use crate::shape::normal_map::{mikktspace_tangents, transform_tangent, NormalMapping};
use crate::shape::{Instance, Mesh, Shape};
use glam::{Mat4, Vec2, Vec3, Vec4};
use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

/// One mesh primitive placed in the world.
pub struct Primitive {
    pub mesh: Mesh,
    /// Its glTF material index (None: the glTF default material).
    pub material: Option<usize>,
    /// The instance's name: the node's, else the mesh's, else `node<i>`.
    pub name: String,
    /// (mesh, primitive) indices in the file.
    pub source: (usize, usize),
    /// Per-vertex tangents (xyz, w = bitangent sign) in mesh space, if the file has them;
    /// shared by every use of the primitive.
    pub tangents: Arc<Vec<[f32; 4]>>,
    /// The primitive's mesh in mesh space, shared by all its uses, and its placement
    /// (`swap_winding`: the node mirrors).
    pub placement: Instance,
    /// Whether the mesh is instanced (`walk_with`): `placement` is then the shape and `mesh`
    /// is empty.
    pub instanced: bool,
}

/// What the walk over the default scene finds.
pub struct Walk {
    pub primitives: Vec<Primitive>,
    pub cameras: Vec<GltfCamera>,
    pub lights: Vec<GltfLight>,
    /// World bounds of every vertex (min, max); None without geometry.
    pub bounds: Option<(Vec3, Vec3)>,
    /// Nodes visited and mesh instances (node–mesh pairs), for checks and statistics.
    pub nodes: usize,
    pub mesh_instances: usize,
}

/// A local mesh read once per (mesh, primitive), with its tangents.
type LocalMesh = (Arc<Mesh>, Arc<Vec<[f32; 4]>>);

/// Walks the default scene (or the first, if the file names none) under `to_world`, every
/// primitive copied into world space.
pub fn walk(model: &Model, to_world: Mat4, warnings: &mut Vec<String>) -> Result<Walk, InputError> {
    walk_with(model, to_world, false, warnings)
}

/// As `walk`; with `instancing`, a mesh under several nodes is not copied but instanced
/// (`Primitive::instanced`); a normal-mapped one keeps its tangents in mesh space, and an
/// emissive one is an area light sampled through its transform (`AreaEmitter`).
pub fn walk_with(
    model: &Model,
    to_world: Mat4,
    instancing: bool,
    warnings: &mut Vec<String>,
) -> Result<Walk, InputError> {
    let path = &model.path;
    let mut uses = vec![0usize; model.doc.meshes().len()];
    for n in model.doc.nodes() {
        if let Some(m) = n.mesh() {
            uses[m.index()] += 1;
        }
    }
    let scene = model
        .doc
        .default_scene()
        .or_else(|| model.doc.scenes().next())
        .ok_or_else(|| {
            InputError::new(path, "the file has no scenes, so nothing to render")
                .field("scenes")
                .hint("export the model with at least one scene holding its nodes")
        })?;
    let mut w = Walk {
        primitives: Vec::new(),
        cameras: Vec::new(),
        lights: Vec::new(),
        bounds: None,
        nodes: 0,
        mesh_instances: 0,
    };
    let mut cache: HashMap<(usize, usize), Option<LocalMesh>> = HashMap::new();
    // Depth-first, iteratively (deep trees must not overflow the stack); a node reached twice
    // (a cycle, which the spec forbids) is refused.
    let mut seen = vec![false; model.doc.nodes().len()];
    let mut stack: Vec<(gltf::Node, Mat4)> = scene.nodes().map(|n| (n, to_world)).collect();
    stack.reverse();
    while let Some((node, parent)) = stack.pop() {
        let field = format!("nodes[{}]", node.index());
        if std::mem::replace(&mut seen[node.index()], true) {
            return Err(InputError::new(
                path,
                "this node is reached twice: the node tree has a cycle or a shared child",
            )
            .field(field)
            .hint("each node may have one parent (glTF 2.0 §3.5.1)"));
        }
        w.nodes += 1;
        let local = Mat4::from_cols_array_2d(&node.transform().matrix());
        if !local.is_finite() {
            return Err(InputError::new(path, "the node's transform is not finite").field(field));
        }
        let world = parent * local;
        if let Some(cam) = node.camera() {
            w.cameras.push(lights::camera(&cam, world, node.name()));
        }
        if let Some(light) = node.light() {
            w.lights.push(lights::light(&light, world));
        }
        if let Some(mesh) = node.mesh() {
            w.mesh_instances += 1;
            let name = node
                .name()
                .or(mesh.name())
                .map_or_else(|| format!("node{}", node.index()), str::to_owned);
            let t = Transform::from_matrix(world).ok_or_else(|| {
                InputError::new(
                    path,
                    "the node's world transform is singular (a zero scale?)",
                )
                .field(&field)
                .hint("give every node a non-zero scale")
            })?;
            // A mirroring transform turns the winding around (glTF 2.0 §3.7.4: front faces
            // follow the determinant's sign).
            let mirror = world.determinant() < 0.0;
            for prim in mesh.primitives() {
                let key = (mesh.index(), prim.index());
                if let std::collections::hash_map::Entry::Vacant(e) = cache.entry(key) {
                    e.insert(read_primitive(model, &prim, mesh.index(), warnings)?);
                }
                let Some((local_mesh, tangents)) = &cache[&key] else {
                    continue;
                };
                let material = prim.material();
                let placement = Instance {
                    mesh: local_mesh.clone(),
                    to_world: t,
                    negate_normals: false,
                    swap_winding: mirror,
                };
                if instancing && uses[mesh.index()] > 1 {
                    for p in &local_mesh.positions {
                        let p = t.point(*p);
                        let b = w.bounds.get_or_insert((p, p));
                        *b = (b.0.min(p), b.1.max(p));
                    }
                    w.primitives.push(Primitive {
                        mesh: Mesh::default(),
                        material: material.index(),
                        source: key,
                        name: name.clone(),
                        tangents: tangents.clone(),
                        placement,
                        instanced: true,
                    });
                    continue;
                }
                let mut m = Mesh::clone(local_mesh).transformed(&t, false);
                if mirror {
                    m.indices.iter_mut().for_each(|tri| tri.swap(1, 2));
                }
                for p in &m.positions {
                    let b = w.bounds.get_or_insert((*p, *p));
                    *b = (b.0.min(*p), b.1.max(*p));
                }
                w.primitives.push(Primitive {
                    mesh: m,
                    material: prim.material().index(),
                    source: key,
                    name: name.clone(),
                    tangents: tangents.clone(),
                    placement,
                    instanced: false,
                });
            }
        }
        for c in node.children().collect::<Vec<_>>().into_iter().rev() {
            stack.push((c, world));
        }
    }
    Ok(w)
}

/// Reads a primitive's triangles in mesh space; None (with a warning) for points and lines.
fn read_primitive(
    model: &Model,
    prim: &gltf::Primitive,
    mesh: usize,
    warnings: &mut Vec<String>,
) -> Result<Option<LocalMesh>, InputError> {
    use gltf::mesh::Mode;
    let path = &model.path;
    let field = format!("meshes[{mesh}].primitives[{}]", prim.index());
    let reader = prim.reader(|b| model.buffers.get(b.index()).map(|d| &d.0[..]));
    let positions: Vec<Vec3> = reader
        .read_positions()
        .ok_or_else(|| {
            InputError::new(path, "the primitive has no POSITION attribute")
                .field(format!("{field}.attributes.POSITION"))
                .hint("every triangle primitive needs vertex positions")
        })?
        .map(Vec3::from)
        .collect();
    let n = positions.len() as u32;
    let list: Vec<u32> = match reader.read_indices() {
        Some(ix) => ix.into_u32().collect(),
        None => (0..n).collect(),
    };
    let tris: Vec<[u32; 3]> = match prim.mode() {
        Mode::Triangles => list.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
        // Strips alternate their winding so that every triangle faces the same way.
        Mode::TriangleStrip => (2..list.len())
            .map(|i| {
                if i % 2 == 0 {
                    [list[i - 2], list[i - 1], list[i]]
                } else {
                    [list[i - 1], list[i - 2], list[i]]
                }
            })
            .collect(),
        Mode::TriangleFan => (2..list.len())
            .map(|i| [list[0], list[i - 1], list[i]])
            .collect(),
        other => {
            warnings.push(format!(
                "{}: {field}: mode {other:?} has no surface to render; skipped",
                path.display()
            ));
            return Ok(None);
        }
    };
    let normals: Vec<Vec3> = reader
        .read_normals()
        .map(|it| it.map(Vec3::from).collect())
        .unwrap_or_default();
    let uvs: Vec<Vec2> = reader
        .read_tex_coords(super::materials::uv_set(&prim.material()))
        .map(|it| it.into_f32().map(Vec2::from).collect())
        .unwrap_or_default();
    let tangents: Vec<[f32; 4]> = reader
        .read_tangents()
        .map(|it| it.collect())
        .unwrap_or_default();
    let mesh = Mesh {
        positions,
        normals,
        uvs,
        indices: tris,
        normal_map: None,
    };
    if mesh.indices.is_empty() {
        warnings.push(format!(
            "{}: {field}: no triangles; skipped",
            path.display()
        ));
        return Ok(None);
    }
    mesh.validate().map_err(|m| {
        InputError::new(path, m)
            .field(&field)
            .hint("the accessors of this primitive disagree; re-export the model")
    })?;
    Ok(Some((Arc::new(mesh), Arc::new(tangents))))
}

/// A material reference of an expanded shape.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MatRef {
    /// One of the scene's own materials (by index).
    Scene(u32),
    /// One of `Expanded::materials`.
    New(usize),
}

/// One shape of an included glTF file.
pub struct ExpandedShape {
    pub shape: Shape,
    pub material: MatRef,
    /// Area-light radiance (emissive material or the shape's `emitter`).
    pub emission: Option<AreaRadiance>,
    pub name: Option<String>,
}

/// What a `Gltf` shape adds to the scene.
pub struct Expanded {
    pub shapes: Vec<ExpandedShape>,
    pub materials: Vec<Material>,
    /// The name of each of `materials` (for the sidecar and the material ids).
    pub material_names: Vec<String>,
    /// Its KHR_lights_punctual lights (unless `lights: false`).
    pub emitters: Vec<(String, EmitterConfig)>,
}

/// Expands shape `sc` (a `ShapeKind::Gltf`), called `field` in errors, with paths relative to
/// `base`; `names` are the scene's material names (in index order) for overrides.
#[allow(clippy::too_many_arguments)]
pub fn expand(
    sc: &ShapeConfig,
    file: &Path,
    field: &str,
    base: &Path,
    names: &[&String],
    range: (f32, f32),
    instancing: bool,
    warnings: &mut Vec<String>,
) -> Result<Expanded, InputError> {
    let ShapeKind::Gltf {
        path,
        materials: overrides,
        lights,
    } = &sc.shape
    else {
        unreachable!("expand is called for glTF shapes only")
    };
    let t = super::super::transform(&sc.to_world, file, &format!("{field}.to_world"))?;
    let full = base.join(path);
    let model = super::take_or_open(&full).map_err(|e| {
        let hint = e.hint.clone().unwrap_or_default();
        e.hint(format!("{hint} (included by {} {field})", file.display()).trim_start())
    })?;
    for ext in &model.ignored_extensions {
        warnings.push(format!(
            "{}: extension {ext} is used but not supported; it is ignored",
            full.display()
        ));
    }
    // An `emitter` on the include makes every shape an area light, instanced or not.
    let walk = walk_with(&model, t.m, instancing, warnings)?;
    let lookup = |name: &str, f: String| -> Result<u32, InputError> {
        names
            .iter()
            .position(|n| n.as_str() == name)
            .map(|k| k as u32)
            .ok_or_else(|| {
                InputError::new(file, format!("unknown material \"{name}\""))
                    .field(f)
                    .hint("name one of the scene's `materials`")
            })
    };
    let all = sc
        .material
        .as_deref()
        .map(|m| lookup(m, format!("{field}.material")))
        .transpose()?;
    let mut by_name = HashMap::new();
    for (gltf_name, prism_name) in overrides {
        let f = format!("{field}.shape.materials.\"{gltf_name}\"");
        if !model.doc.materials().any(|m| m.name() == Some(gltf_name)) {
            let list: Vec<String> = model
                .doc
                .materials()
                .filter_map(|m| m.name().map(|n| format!("\"{n}\"")))
                .collect();
            return Err(InputError::new(
                file,
                format!("{} has no material named \"{gltf_name}\"", full.display()),
            )
            .field(f)
            .hint(format!(
                "its materials are: {}",
                if list.is_empty() {
                    "(none named)".into()
                } else {
                    list.join(", ")
                }
            )));
        }
        by_name.insert(gltf_name.as_str(), lookup(prism_name, f)?);
    }
    let area = match &sc.emitter {
        Some(e) => Some(crate::scene::emission::area_radiance(
            &e.radiance,
            file,
            &format!("{field}.emitter.radiance"),
            range,
            warnings,
        )?),
        None => None,
    };
    let mut mats = GltfMaterials::new(&model);
    // Per (mesh, primitive): its normal map's tangents in mesh space, and its normal-mapped
    // shared mesh where instanced.
    let mut local_tangents: HashMap<(usize, usize), Option<Arc<Vec<Vec4>>>> = HashMap::new();
    let mut mapped: HashMap<(usize, usize), Arc<Mesh>> = HashMap::new();
    let mut out = Expanded {
        shapes: Vec::new(),
        materials: Vec::new(),
        material_names: Vec::new(),
        emitters: Vec::new(),
    };
    for p in walk.primitives {
        let gltf_mat = p
            .material
            .map(|i| model.doc.materials().nth(i).expect("validated index"));
        let over = all.or_else(|| {
            gltf_mat
                .as_ref()
                .and_then(|m| m.name())
                .and_then(|n| by_name.get(n).copied())
        });
        let (material, emission, normal_map) = match over {
            Some(k) => (MatRef::Scene(k), None, None),
            None => {
                let gm = model.doc.meshes().nth(p.source.0).expect("walked mesh");
                let gm = gm
                    .primitives()
                    .nth(p.source.1)
                    .expect("walked primitive")
                    .material();
                let (k, emission, normal_map) = mats.get(&gm, warnings)?;
                (MatRef::New(k), emission, normal_map)
            }
        };
        let emission = area.clone().or(emission);
        // A normal map's tangents in mesh space, once per primitive: the file's, else
        // MikkTSpace's on the mesh as the file gives it (glTF 2.0 §3.7.2.1: from the specified
        // positions, normals and uvs), so every use maps the same tangents.
        let tangents = normal_map.as_ref().and_then(|_| {
            local_tangents
                .entry(p.source)
                .or_insert_with(|| {
                    let m = &p.placement.mesh;
                    if !p.tangents.is_empty() {
                        Some(Arc::new(
                            p.tangents.iter().map(|t| Vec4::from(*t)).collect(),
                        ))
                    } else if !m.normals.is_empty() && !m.uvs.is_empty() {
                        mikktspace_tangents(&m.positions, &m.normals, &m.uvs, &m.indices)
                            .map(Arc::new)
                    } else {
                        None
                    }
                })
                .clone()
        });
        if normal_map.is_some() && tangents.is_none() {
            warnings.push(format!(
                "{}: {}: the normal map needs NORMAL and TEXCOORD_0 (or TANGENT) on the mesh; it is ignored",
                full.display(),
                p.name
            ));
        }
        let normal_map = normal_map.zip(tangents);
        let mut inst = p.placement;
        let mirror = inst.to_world.flips_handedness();
        if sc.flip_normals {
            inst.negate_normals = !inst.negate_normals;
            inst.swap_winding = !inst.swap_winding;
        }
        let mut mesh = if !p.instanced {
            if sc.flip_normals {
                p.mesh.transformed(&Transform::IDENTITY, true)
            } else {
                p.mesh
            }
        } else {
            if let Some((map, tangents)) = normal_map {
                // One normal-mapped copy of the mesh (tangents in mesh space) for all its uses.
                inst.mesh = mapped
                    .entry(p.source)
                    .or_insert_with(|| {
                        Arc::new(Mesh {
                            normal_map: Some(Box::new(NormalMapping {
                                tangents: tangents.to_vec(),
                                map,
                            })),
                            ..Mesh::clone(&inst.mesh)
                        })
                    })
                    .clone();
            }
            out.shapes.push(ExpandedShape {
                shape: Shape::Instance(inst),
                material,
                emission,
                name: Some(p.name),
            });
            continue;
        };
        if let Some((map, tangents)) = normal_map {
            let tangents = tangents
                .iter()
                .map(|t| transform_tangent(&inst.to_world, mirror, *t))
                .collect();
            mesh.normal_map = Some(Box::new(NormalMapping { tangents, map }));
        }
        out.shapes.push(ExpandedShape {
            shape: Shape::Mesh(mesh),
            material,
            emission,
            name: Some(p.name),
        });
    }
    out.material_names = mats.names();
    out.materials = mats.into_materials();
    if *lights {
        for l in &walk.lights {
            out.emitters.push((
                format!("{field} ({} light {})", full.display(), l.name),
                l.emitter.clone(),
            ));
        }
    }
    Ok(out)
}
