//! Which shapes become instances (`shape::Instance`, traced by `accel::instances`) rather than
//! world-space copies: a RON `Mesh` file named by two or more shapes, a glTF mesh under two or
//! more nodes (`load::gltf`; a normal-mapped one with its tangents in mesh space, an emissive
//! one sampled as an area light through its transform). Each such mesh is read once and shared.
//! A mesh used once, an emitting RON shape, the `Embree` and `BruteForce` backends and
//! `flatten: true` keep the world-space copy, so scenes without repeated meshes build and
//! render exactly as before.

use super::check::check;
use crate::accel::AccelKind;
use crate::config::{SceneConfig, ShapeConfig, ShapeKind};
use crate::error::InputError;
use crate::shape::{mesh_io, Instance, Mesh, Shape};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Whether the scene instances repeated meshes at all.
pub fn enabled(cfg: &SceneConfig) -> bool {
    !cfg.flatten && cfg.accel == AccelKind::Bvh
}

/// The RON scene's mesh files used by more than one non-emitting shape, read once each.
pub struct MeshFiles {
    uses: HashMap<PathBuf, usize>,
    loaded: HashMap<PathBuf, Arc<Mesh>>,
}

/// A mesh file's identity: its canonical path (two spellings of one file are one mesh).
fn key(full: &Path) -> PathBuf {
    full.canonicalize().unwrap_or_else(|_| full.to_path_buf())
}

impl MeshFiles {
    pub fn new(cfg: &SceneConfig, base: &Path) -> MeshFiles {
        let mut uses = HashMap::new();
        if enabled(cfg) {
            for sc in &cfg.shapes {
                if let (ShapeKind::Mesh { path }, None) = (&sc.shape, &sc.emitter) {
                    *uses.entry(key(&base.join(path))).or_insert(0) += 1;
                }
            }
            uses.retain(|_, n| *n > 1);
        }
        MeshFiles {
            uses,
            loaded: HashMap::new(),
        }
    }

    /// Shape `sc` as an instance if its mesh file is used more than once (None: build it the
    /// usual way, `geometry::shape`).
    pub fn instance(
        &mut self,
        sc: &ShapeConfig,
        file: &Path,
        field: &str,
        base: &Path,
        warnings: &mut Vec<String>,
    ) -> Result<Option<Shape>, InputError> {
        let ShapeKind::Mesh { path } = &sc.shape else {
            return Ok(None);
        };
        if sc.emitter.is_some() || self.uses.is_empty() {
            return Ok(None);
        }
        let full = base.join(path);
        let k = key(&full);
        if !self.uses.contains_key(&k) {
            return Ok(None);
        }
        let to_world = super::transform(&sc.to_world, file, &format!("{field}.to_world"))?;
        let mesh = match self.loaded.get(&k) {
            Some(m) => m.clone(),
            None => {
                let mesh = mesh_io::load(&full).map_err(|m| {
                    let err = InputError::new(file, m)
                        .field(format!("{field}.shape.path"))
                        .hint("give an OBJ or PLY mesh prism reads (scenes/README.md)");
                    super::inputs::missing_hint(
                        err,
                        &full,
                        "mesh paths are relative to the scene file",
                    )
                })?;
                let degenerate = (0..mesh.indices.len())
                    .filter(|&i| {
                        let a = mesh.triangle_area(i);
                        !(a > 0.0 && a.is_finite())
                    })
                    .count();
                check(
                    degenerate < mesh.indices.len(),
                    file,
                    field,
                    "every triangle of this mesh has zero area",
                )?;
                if degenerate > 0 {
                    warnings.push(format!(
                        "{}: {field}: {degenerate} of {} triangles of {} have zero area and are skipped",
                        file.display(),
                        mesh.indices.len(),
                        full.display()
                    ));
                }
                let m = Arc::new(mesh);
                self.loaded.insert(k, m.clone());
                m
            }
        };
        let inst = Instance {
            mesh,
            to_world,
            negate_normals: sc.flip_normals,
            swap_winding: sc.flip_normals,
        };
        check_extent(&inst, file, field)?;
        Ok(Some(Shape::Instance(inst)))
    }
}

/// Refuses an instance reaching beyond `extent::MAX_COORD` (checked on its vertices' world
/// bounds, which contain every triangle's).
pub fn check_extent(inst: &Instance, file: &Path, field: &str) -> Result<(), InputError> {
    let (lo, hi) = inst.bounds();
    let far = lo.abs().max(hi.abs()).max_element();
    if far.is_finite() && far <= super::extent::MAX_COORD {
        return Ok(());
    }
    // The exact per-triangle check (it skips degenerate triangles) words the error.
    super::extent::check_shape(&Shape::Instance(inst.clone()), file, field)
}

/// Primitives the memory estimate counts (`resources::Plan::prims`): every shape's own, and an
/// instanced mesh's once, with one more per instance (its record and share of the top level).
pub fn unique_prims(shapes: &[Shape]) -> u64 {
    let mut seen = std::collections::HashSet::new();
    shapes
        .iter()
        .map(|s| match s {
            Shape::Instance(i) => {
                let first = seen.insert(Arc::as_ptr(&i.mesh));
                1 + if first {
                    i.mesh.indices.len() as u64
                } else {
                    0
                }
            }
            s => s.prim_count() as u64,
        })
        .sum()
}
