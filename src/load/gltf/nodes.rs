//! The node tree: transforms composed from the root down, mesh primitives read into world-space
//! meshes named after their node, cameras and lights collected with their world transforms.

use super::lights::{self, GltfCamera, GltfLight};
use super::Model;
use crate::error::InputError;
use crate::load::extent;
use crate::math::Transform;
use crate::shape::{Instance, Mesh};
use glam::{Mat4, Vec2, Vec3};
use std::collections::HashMap;
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
    /// Its vertex colours (`COLOR_0`), shared by every use.
    pub colors: Option<Arc<super::colors::Colors>>,
    /// The primitive's mesh in mesh space, shared by all its uses, and its placement
    /// (`swap_winding`: the node mirrors).
    pub placement: Instance,
    /// Whether the mesh is instanced (`walk_with`): `placement` is then the shape and `mesh`
    /// is empty.
    pub instanced: bool,
    /// With an open shutter, under an animated node: the motion that carries `mesh` (then in
    /// the animated node's space) to the world (`Timed`).
    pub motion: Option<crate::motion::Motion>,
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

/// A local mesh read once per (mesh, primitive), with its tangents and vertex colours.
type LocalMesh = (
    Arc<Mesh>,
    Arc<Vec<[f32; 4]>>,
    Option<Arc<super::colors::Colors>>,
);

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
    walk_timed(model, to_world, instancing, &Timed::default(), warnings)
}

/// The time a walk poses the nodes at (`super::animation`).
#[derive(Default)]
pub struct Timed<'a> {
    pub clip: Option<&'a super::animation::Clip>,
    /// The instant (or the shutter's opening).
    pub time: f32,
    /// The shutter stays open: animated subtrees keep their motion (`Primitive::motion`).
    pub open: bool,
    /// The shape's own motion (RON `animation`), above the whole tree, with an open shutter.
    pub root: Option<crate::motion::Motion>,
}

/// An animated node's subtree with an open shutter: world(t) = motion(t) · below (`motion` a
/// chain where animated nodes nest).
#[derive(Clone)]
struct Chain {
    motion: crate::motion::Motion,
    below: Mat4,
}

/// As `walk_with`, with the nodes posed at `timed.time` (and kept moving, `timed.open`).
pub fn walk_timed(
    model: &Model,
    to_world: Mat4,
    instancing: bool,
    timed: &Timed,
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
    let root = timed.root.clone().map(|motion| Chain {
        motion,
        below: Mat4::IDENTITY,
    });
    let mut stack: Vec<(gltf::Node, Mat4, Option<Chain>)> =
        scene.nodes().map(|n| (n, to_world, root.clone())).collect();
    stack.reverse();
    while let Some((node, parent, mut chain)) = stack.pop() {
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
        let tracks = timed.clip.and_then(|c| c.nodes.get(&node.index()));
        let local = match tracks {
            Some(tr) => tr.local(&node, timed.time),
            None => Mat4::from_cols_array_2d(&node.transform().matrix()),
        };
        if !local.is_finite() {
            return Err(InputError::new(path, "the node's transform is not finite")
                .field(field)
                .hint("give the node a finite matrix, or finite translation, rotation and scale"));
        }
        let world = parent * local;
        if let Some(tr) = tracks.filter(|_| timed.open) {
            let own = tr.motion(&node);
            let motion = match chain.take() {
                // Under a moving node (or the shape's own animation): a chain, parent(t) ·
                // the static nodes between · own(t).
                Some(c) => own.under(c.motion, c.below),
                // Under static nodes: one track where they fold into it (rotation,
                // translation, uniform scale), else a chain under them.
                None => super::animation::fold(parent, own.clone())
                    .unwrap_or_else(|| own.under(crate::motion::Motion::still(), parent)),
            };
            chain = Some(Chain {
                motion,
                below: Mat4::IDENTITY,
            });
        } else if let Some(c) = &mut chain {
            c.below *= local;
        }
        // Nodes at 1e30 are finite but overflow the 32-bit geometry (as OBJ's `extent` check).
        let at = world.w_axis.truncate();
        extent::check_point(at, path, &field, "the node (its translation in the world)")?;
        if let Some(cam) = node.camera() {
            w.cameras.push(lights::camera(&cam, world, node.name()));
        }
        if let Some(light) = node.light() {
            let moving = chain.as_ref().map(|c| (c.motion.clone(), c.below));
            w.lights.push(lights::light(&light, world, moving));
        }
        if let Some(mesh) = node.mesh() {
            w.mesh_instances += 1;
            let name = node
                .name()
                .or(mesh.name())
                .map_or_else(|| format!("node{}", node.index()), str::to_owned);
            // Under a moving node the mesh is placed in that node's space, which the motion
            // carries to the world.
            let placed = chain.as_ref().map_or(world, |c| c.below);
            let t = Transform::from_matrix(placed).ok_or_else(|| {
                InputError::new(
                    path,
                    "the node's world transform is singular (a zero scale?)",
                )
                .field(&field)
                .hint("give every node a non-zero scale")
            })?;
            extent::check_transform(&t, path, &field)?;
            // A mirroring transform turns the winding around (glTF 2.0 §3.7.4: front faces
            // follow the determinant's sign).
            let mirror = placed.determinant() < 0.0;
            for prim in mesh.primitives() {
                let key = (mesh.index(), prim.index());
                if let std::collections::hash_map::Entry::Vacant(e) = cache.entry(key) {
                    e.insert(read_primitive(model, &prim, mesh.index(), warnings)?);
                }
                let Some((local_mesh, tangents, colors)) = &cache[&key] else {
                    continue;
                };
                let material = prim.material();
                let placement = Instance {
                    mesh: local_mesh.clone(),
                    to_world: t,
                    negate_normals: false,
                    swap_winding: mirror,
                };
                let vertex = format!("a vertex placed by {field}");
                let source = format!(
                    "meshes[{}].primitives[{}].attributes.POSITION",
                    key.0, key.1
                );
                if instancing && uses[mesh.index()] > 1 && chain.is_none() {
                    for p in &local_mesh.positions {
                        let p = t.point(*p);
                        extent::check_point(p, path, &source, &vertex)?;
                        let b = w.bounds.get_or_insert((p, p));
                        *b = (b.0.min(p), b.1.max(p));
                    }
                    w.primitives.push(Primitive {
                        mesh: Mesh::default(),
                        material: material.index(),
                        source: key,
                        name: name.clone(),
                        tangents: tangents.clone(),
                        colors: colors.clone(),
                        placement,
                        instanced: true,
                        motion: None,
                    });
                    continue;
                }
                let mut m = Mesh::clone(local_mesh).transformed(&t, false);
                if mirror {
                    m.indices.iter_mut().for_each(|tri| tri.swap(1, 2));
                }
                let at = chain.as_ref().map(|c| c.motion.matrix(timed.time));
                for p in &m.positions {
                    extent::check_point(*p, path, &source, &vertex)?;
                    let p = at.map_or(*p, |a| a.transform_point3(*p));
                    let b = w.bounds.get_or_insert((p, p));
                    *b = (b.0.min(p), b.1.max(p));
                }
                w.primitives.push(Primitive {
                    mesh: m,
                    material: prim.material().index(),
                    source: key,
                    name: name.clone(),
                    tangents: tangents.clone(),
                    colors: colors.clone(),
                    placement,
                    instanced: false,
                    motion: chain.as_ref().map(|c| c.motion.clone()),
                });
            }
        }
        for c in node.children().collect::<Vec<_>>().into_iter().rev() {
            stack.push((c, world, chain.clone()));
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
    super::unread::primitive(model, prim, &field, warnings);
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
    let colors = super::colors::read(model, prim, &field, mesh.positions.len())?;
    Ok(Some((
        Arc::new(mesh),
        Arc::new(tangents),
        colors.map(Arc::new),
    )))
}
