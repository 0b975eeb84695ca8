//! Shapes that move while the shutter is open. Each keeps its geometry in object space, under
//! a bottom-level `Bvh` of its own; a top-level 8-wide tree (`bvh8`) holds each one's world
//! bounds over the whole shutter interval (`Motion::bounds`). A ray meeting such a box is
//! carried into the object's space at the ray's own time and traced there; its hit's surface
//! is computed in object space and carried back. Scenes without moving shapes have none of
//! this (`Scene::moving` is None), so their rays do no extra work.

use super::bvh::Bvh;
use super::bvh8::{Tree, Visit};
use super::Prim;
use crate::math::float::gamma;
use crate::motion::Motion;
use crate::ray::Ray;
use crate::shape::{PrimHit, Shape, SurfacePoint};
use glam::{Mat3, Mat4, Vec3};
use obvhs::aabb::Aabb;
use obvhs::Boundable;

struct Item {
    motion: Motion,
    blas: Bvh,
    /// The object's shape index in the scene.
    shape: u32,
}

struct MotionBox(Aabb);

impl Boundable for MotionBox {
    fn aabb(&self) -> Aabb {
        self.0
    }
}

/// A hit on a moving shape: its scene shape index, primitive, and the surface in world space.
pub struct MovingHit {
    pub shape: u32,
    pub prim: u32,
    pub t: f32,
    /// Barycentrics (b1, b2) in triangle `prim` (per-vertex data).
    pub bary: glam::Vec2,
    pub surface: SurfacePoint,
}

pub struct Moving {
    tree: Tree,
    /// Objects in leaf order.
    items: Vec<Item>,
    world: (Vec3, Vec3),
}

/// A world ray in an object's space at the ray's time: unit direction (the analytic shapes
/// need one), with `scale` = object distance per world distance.
struct Local {
    ray: Ray,
    scale: f32,
    m: Mat4,
    inv: Mat4,
}

fn local(motion: &Motion, ray: &Ray, t_max: f32) -> Option<Local> {
    let m = motion.matrix(ray.time);
    let inv = m.inverse();
    let d = inv.transform_vector3(ray.d);
    let scale = d.length();
    if !(scale.is_finite() && scale > 0.0) {
        return None; // a scale through 0 at this instant: nothing to hit
    }
    Some(Local {
        ray: Ray {
            o: inv.transform_point3(ray.o),
            d: d / scale,
            t_max: t_max * scale,
            time: ray.time,
        },
        scale,
        m,
        inv,
    })
}

impl Moving {
    /// Builds the levels over `list`: (scene shape index, its object-space shape, motion),
    /// bounded over the times `t0..t1`. None for an empty list.
    pub fn build(list: Vec<(u32, &Shape, Motion)>, t0: f32, t1: f32) -> Option<Moving> {
        if list.is_empty() {
            return None;
        }
        let mut boxes = Vec::with_capacity(list.len());
        let mut items = Vec::with_capacity(list.len());
        let mut world = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        for (shape, s, motion) in list {
            let prims = (0..s.prim_count())
                .filter(|&i| !s.prim_is_degenerate(i))
                .map(|i| Prim {
                    id: i as u32,
                    geom: s.prim_geom(i),
                })
                .collect();
            let blas = Bvh::build(prims);
            let object = blas.bounds();
            let (lo, hi) = if object.0.cmple(object.1).all() {
                motion.bounds(object, t0, t1)
            } else {
                (Vec3::ZERO, Vec3::ZERO)
            };
            world = (world.0.min(lo), world.1.max(hi));
            // Pad for the rounding of the ray's transform into object space (relative 1e-5 of
            // the box's reach: far above f32 rounding of one 4×4 product).
            let pad = lo.abs().max(hi.abs()) * 1e-5;
            boxes.push(MotionBox(Aabb::new((lo - pad).into(), (hi + pad).into())));
            items.push(Item {
                motion,
                blas,
                shape,
            });
        }
        let mut order: Vec<usize> = Vec::with_capacity(items.len());
        let tree = Tree::build(&boxes, 4, |leaf| {
            let first = order.len() as u32;
            order.extend(leaf.iter().map(|&i| i as usize));
            (first, leaf.len() as u32)
        });
        let mut slots: Vec<Option<Item>> = items.into_iter().map(Some).collect();
        let items = order.iter().map(|&i| slots[i].take().unwrap()).collect();
        Some(Moving { tree, items, world })
    }

    /// The closest hit within (0, t_max) at the ray's time, with its world-space surface
    /// computed from `shapes` (the scene's, object space for moving shapes).
    pub fn intersect(&self, ray: &Ray, t_max: f32, shapes: &[Shape]) -> Option<MovingHit> {
        let mut t_max = t_max;
        let mut best: Option<(usize, Local, PrimHit, u32)> = None;
        self.tree
            .traverse::<true>(ray, &mut t_max, |first, count, t_max| {
                for k in first as usize..(first + count) as usize {
                    let it = &self.items[k];
                    let Some(l) = local(&it.motion, ray, *t_max) else {
                        continue;
                    };
                    if let Some(h) = it.blas.intersect(&l.ray) {
                        let t = h.hit.t / l.scale;
                        if t < *t_max {
                            *t_max = t;
                            best = Some((k, l, h.hit, h.prim));
                        }
                    }
                }
                Visit::Continue
            });
        let (k, l, hit, prim) = best?;
        let shape = self.items[k].shape;
        let s = shapes[shape as usize].surface(prim as usize, &l.ray, &hit);
        Some(MovingHit {
            shape,
            prim,
            t: t_max,
            bary: glam::Vec2::new(hit.b1, hit.b2),
            surface: to_world(s, &l),
        })
    }

    /// True if a moving shape lies on the ray within (0, t_max) at the ray's time.
    pub fn occluded(&self, ray: &Ray) -> bool {
        let mut t_max = ray.t_max;
        self.tree
            .traverse::<false>(ray, &mut t_max, |first, count, t_max| {
                for it in &self.items[first as usize..(first + count) as usize] {
                    if let Some(l) = local(&it.motion, ray, *t_max) {
                        if it.blas.occluded(&l.ray) {
                            return Visit::Stop;
                        }
                    }
                }
                Visit::Continue
            })
    }

    /// The motion of scene shape `shape`, if it is one of these.
    pub fn motion(&self, shape: u32) -> Option<&Motion> {
        self.items
            .iter()
            .find(|it| it.shape == shape)
            .map(|it| &it.motion)
    }

    /// World bounds of the moving shapes over the shutter interval.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.world
    }

    pub fn len(&self) -> usize {
        self.items.len()
    }

    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }
}

/// An object-space surface point carried to world space by the ray's transform. The error
/// bound grows by the transform's rounding of the point, and by that of the next ray's origin
/// into object space (γ3 each way, PBR 4th ed. §6.8.4), as `shape::Instance` does.
fn to_world(s: SurfacePoint, l: &Local) -> SurfacePoint {
    let (m, inv) = (&l.m, &l.inv);
    let lin = Mat3::from_mat4(*m);
    let p = m.transform_point3(s.p);
    let e_obj = s.p_error + gamma(3) * (lin.abs() * s.p.abs() + m.w_axis.truncate().abs());
    let mut p_error = (1.0 + gamma(3)) * (lin.abs() * e_obj);
    let inv_abs = Mat3::from_mat4(*inv).abs();
    let back = gamma(3) * (inv_abs * p.abs() + inv.w_axis.truncate().abs());
    p_error += (1.0 + gamma(3)) * (lin.abs() * back);
    let nt = Mat3::from_mat4(*inv).transpose();
    let ng = (nt * s.ng).normalize();
    let n = (nt * s.frame.n).normalize();
    SurfacePoint {
        p,
        p_error,
        ng,
        frame: crate::math::Frame::from_normal_tangent(n, lin * s.frame.s),
        uv: s.uv,
    }
}
