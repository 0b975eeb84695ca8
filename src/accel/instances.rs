//! Instancing: a two-level BVH. Each mesh used by several shapes has one bottom-level `Bvh`
//! over its object-space triangles; a top-level 8-wide tree (`bvh8`) holds each instance's
//! world bounds. A ray meeting an instance's box is carried into its object space (its origin
//! and direction by the inverse transform; the direction is not renormalised, so distances
//! along it stay the world ray's) and traced through the shared bottom level. Memory therefore
//! grows with the unique geometry, plus 56 bytes per instance here (and its shape's own).

use super::bvh::Bvh;
use super::bvh8::{Tree, Visit};
use super::{Hit, Prim};
use crate::math::float::gamma;
use crate::ray::Ray;
use crate::shape::{Instance, PrimGeom};
use glam::{Vec3, Vec4};
use obvhs::aabb::Aabb;
use obvhs::Boundable;
use std::collections::HashMap;

/// Instances per top-level leaf.
const MAX_LEAF_INSTANCES: u32 = 4;

/// One instance as the traversal reads it.
#[derive(Clone, Copy, Debug)]
struct Item {
    /// World-to-object rows (affine, 3×4).
    to_object: [Vec4; 3],
    blas: u32,
    /// The instance's shape index in the scene.
    shape: u32,
}

impl Item {
    #[inline(always)]
    fn ray(&self, ray: &Ray, t_max: f32) -> Ray {
        let (o, d) = (ray.o.extend(1.0), ray.d.extend(0.0));
        let r = &self.to_object;
        Ray {
            o: Vec3::new(r[0].dot(o), r[1].dot(o), r[2].dot(o)),
            d: Vec3::new(r[0].dot(d), r[1].dot(d), r[2].dot(d)),
            t_max,
            time: ray.time,
        }
    }
}

struct InstBox(Aabb);

impl Boundable for InstBox {
    fn aabb(&self) -> Aabb {
        self.0
    }
}

pub struct Instances {
    tree: Tree,
    /// Instances in leaf order.
    items: Vec<Item>,
    /// Bottom levels, one per unique mesh.
    blas: Vec<Bvh>,
    /// Triangles over all unique meshes.
    unique_triangles: u64,
    /// World bounds of the instances' vertices.
    world: (Vec3, Vec3),
}

impl Instances {
    /// Builds the two levels over `list`: (scene shape index, instance). Instances sharing a
    /// mesh (the same `Arc`) share its bottom level. None for an empty list.
    pub fn build(list: &[(u32, &Instance)]) -> Option<Instances> {
        if list.is_empty() {
            return None;
        }
        let mut index: HashMap<*const crate::shape::Mesh, u32> = HashMap::new();
        let mut blas = Vec::new();
        let mut unique_triangles = 0;
        let mut boxes = Vec::with_capacity(list.len());
        let mut items = Vec::with_capacity(list.len());
        let mut world = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        for &(shape, inst) in list {
            let key = std::sync::Arc::as_ptr(&inst.mesh);
            let b = *index.entry(key).or_insert_with(|| {
                let m = &inst.mesh;
                unique_triangles += m.indices.len() as u64;
                // Object-space degenerate triangles can never be hit: left out, as the flat
                // path leaves out its world-space ones.
                let prims = (0..m.indices.len())
                    .filter(|&i| {
                        let a = m.triangle_area(i);
                        a > 0.0 && a.is_finite()
                    })
                    .map(|i| Prim {
                        id: i as u32,
                        geom: PrimGeom::Triangle(m.vertices(i)),
                    })
                    .collect();
                blas.push(Bvh::build(prims));
                blas.len() as u32 - 1
            });
            // The vertices' world bounds: tight for rotated instances too (the scene's bounds
            // are then the flattened scene's), padded for the top level.
            let object = blas[b as usize].bounds();
            let (lo, hi) = if object.0.cmple(object.1).all() {
                inst.bounds()
            } else {
                (Vec3::ZERO, Vec3::ZERO) // nothing to hit: a point (its bottom level finds nothing)
            };
            world = (world.0.min(lo), world.1.max(hi));
            boxes.push(InstBox(padded(inst, object, lo, hi)));
            let inv = inst.to_world.inv;
            items.push(Item {
                to_object: [inv.row(0), inv.row(1), inv.row(2)],
                blas: b,
                shape,
            });
        }
        let mut order = Vec::with_capacity(items.len());
        let tree = Tree::build(&boxes, MAX_LEAF_INSTANCES, |leaf| {
            let first = order.len() as u32;
            order.extend(leaf.iter().map(|&i| items[i as usize]));
            (first, leaf.len() as u32)
        });
        Some(Instances {
            tree,
            items: order,
            blas,
            unique_triangles,
            world,
        })
    }

    /// The closest hit within (0, ray.t_max): the instance's shape index and its object-space
    /// triangle hit (the triangle's index in the mesh, the distance along the world ray).
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<(u32, Hit)> {
        let mut t_max = ray.t_max;
        let mut best = None;
        self.tree
            .traverse::<true>(ray, &mut t_max, |first, count, t_max| {
                for it in &self.items[first as usize..(first + count) as usize] {
                    if let Some(h) = self.blas[it.blas as usize].intersect(&it.ray(ray, *t_max)) {
                        if h.hit.t < *t_max {
                            *t_max = h.hit.t;
                            best = Some((it.shape, h));
                        }
                    }
                }
                Visit::Continue
            });
        best
    }

    /// True if any instance lies on the ray within (0, t_max).
    #[inline]
    pub fn occluded(&self, ray: &Ray) -> bool {
        let mut t_max = ray.t_max;
        self.tree
            .traverse::<false>(ray, &mut t_max, |first, count, t_max| {
                let items = &self.items[first as usize..(first + count) as usize];
                for it in items {
                    if self.blas[it.blas as usize].occluded(&it.ray(ray, *t_max)) {
                        return Visit::Stop;
                    }
                }
                Visit::Continue
            })
    }

    /// World bounds of all instances (min, max).
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.world
    }

    /// Instances, unique meshes and their triangles.
    pub fn counts(&self) -> (usize, usize, u64) {
        (self.items.len(), self.blas.len(), self.unique_triangles)
    }
}

/// The world box `lo..hi` of `inst`'s transformed vertices (computed in f32) padded by a bound
/// on the transform's rounding (γ3 (|M| |p| + |t|) per component, PBR 4th ed. §6.8.4, over
/// the object box `olo..ohi`) and 2γ3 of the box itself, so it surely holds the exact
/// transformed triangles the object-space test meets.
fn padded(inst: &Instance, (olo, ohi): (Vec3, Vec3), lo: Vec3, hi: Vec3) -> Aabb {
    let m = &inst.to_world.m;
    let p = olo.abs().max(ohi.abs());
    let err = gamma(3) * (glam::Mat3::from_mat4(*m).abs() * p + m.w_axis.truncate().abs());
    let pad = err + lo.abs().max(hi.abs()) * (2.0 * gamma(3));
    Aabb::new((lo - pad).into(), (hi + pad).into())
}
