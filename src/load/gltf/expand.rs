//! A `Gltf` shape of a RON scene expanded into the scene's shapes, materials and lights:
//! the walked node tree's primitives, instanced or copied, with material overrides by name.

use super::materials::GltfMaterials;
use super::nodes::{walk_timed, Timed};
use crate::bsdf::Material;
use crate::config::{EmitterConfig, ShapeConfig, ShapeKind};
use crate::emitter::AreaRadiance;
use crate::error::InputError;
use crate::math::Transform;
use crate::shape::normal_map::{mikktspace_tangents, transform_tangent, NormalMapping};
use crate::shape::{Mesh, Shape};
use glam::Vec4;
use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

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
    /// With an open shutter: the motion carrying the shape (then in object space) to the world.
    pub motion: Option<crate::motion::Motion>,
}

/// The render's time for an included file: the instant (or the shutter's opening), whether
/// the shutter stays open, and the shape's own motion then.
#[derive(Default)]
pub struct When {
    pub time: f32,
    pub open: bool,
    pub root: Option<crate::motion::Motion>,
}

/// What a `Gltf` shape adds to the scene.
pub struct Expanded {
    pub shapes: Vec<ExpandedShape>,
    pub materials: Vec<Material>,
    /// The name of each of `materials` (for the sidecar and the material ids).
    pub material_names: Vec<String>,
    /// Its KHR_lights_punctual lights (unless `lights: false`), each with its motion while the
    /// shutter is open under an animated node (`GltfLight::motion`).
    pub emitters: Vec<(String, EmitterConfig, Option<crate::motion::Motion>)>,
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
    when: When,
    warnings: &mut Vec<String>,
) -> Result<Expanded, InputError> {
    let ShapeKind::Gltf {
        path,
        materials: overrides,
        lights,
        allow_outside,
        animation,
    } = &sc.shape
    else {
        unreachable!("expand is called for glTF shapes only")
    };
    let t = crate::load::transform(&sc.to_world, file, &format!("{field}.to_world"))?;
    let full = base.join(path);
    let model = super::take_or_open(&full, *allow_outside).map_err(|e| {
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
    let clip = super::animation::read(&model, animation.as_deref(), warnings)?;
    let timed = Timed {
        clip: clip.as_ref(),
        time: when.time,
        open: when.open,
        root: when.root,
    };
    let walk = walk_timed(&model, t.m, instancing, &timed, warnings)?;
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
        Some(e) => Some(crate::load::emission::area_radiance(
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
            Some(k) => {
                if p.colors.is_some() {
                    warnings.push(format!(
                        "{}: {}: the scene's material replaces the glTF material, so its vertex colours (COLOR_0) are not read",
                        full.display(),
                        p.name
                    ));
                }
                (MatRef::Scene(k), None, None)
            }
            None => {
                let gm = model.doc.meshes().nth(p.source.0).expect("walked mesh");
                let gm = gm
                    .primitives()
                    .nth(p.source.1)
                    .expect("walked primitive")
                    .material();
                let (k, emission, normal_map) = match &p.colors {
                    None => mats.get(&gm, warnings)?,
                    Some(c) => {
                        // The corners in the order the shape's barycentrics follow: an
                        // instance's are the file's; a copy's winding is turned by a mirroring
                        // node and by `flip_normals`.
                        let swapped = !p.instanced && (p.placement.swap_winding != sc.flip_normals);
                        let tris: Vec<[u32; 3]> = (p.placement.mesh.indices.iter())
                            .map(|t| if swapped { [t[0], t[2], t[1]] } else { *t })
                            .collect();
                        let corners = super::colors::corners(c, &tris);
                        mats.tinted(&gm, (p.source, swapped), &corners, c.alpha, warnings)?
                    }
                };
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
                motion: None,
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
            motion: p.motion,
        });
    }
    out.material_names = mats.names();
    out.materials = mats.into_materials();
    if *lights {
        for l in &walk.lights {
            out.emitters.push((
                format!("{field} ({} light {})", full.display(), l.name),
                l.emitter.clone(),
                l.motion.clone(),
            ));
        }
    }
    Ok(out)
}
