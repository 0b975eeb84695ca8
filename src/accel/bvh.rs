//! obvhs' 8-wide compressed BVH (CWBVH, Ylitie et al. 2017) built with PLOC; we keep the
//! primitives in the BVH's leaf order so a leaf's primitives sit next to each other in memory.

use super::{Hit, Prim};
use crate::ray::Ray;
use crate::shape::{triangle::RayShear, PrimGeom};
use glam::UVec2;
use obvhs::aabb::Aabb;
use obvhs::cwbvh::{builder::build_cwbvh, CwBvh};
use obvhs::{Boundable, BvhBuildParams};
use std::time::Duration;

struct PrimBox(Aabb);

impl Boundable for PrimBox {
    fn aabb(&self) -> Aabb {
        self.0
    }
}

pub struct Bvh {
    bvh: Option<CwBvh>,
    /// Primitives in BVH order: traversal's primitive index addresses these directly.
    geoms: Vec<PrimGeom>,
    ids: Vec<u32>,
}

/// obvhs' node test ignores boxes that end before t = 1e-4, a fixed absolute distance: rays
/// leaving a point that close to a surface (a corner, a contact, any scene at a scale of 1e-4)
/// would pass through it. The box test therefore runs on the same ray started this far behind
/// its origin, so obvhs' cut-off falls behind the real origin; primitive tests use the real ray.
const BOX_SHIFT: f32 = 2e-4;

/// The ray for obvhs' box tests (see `BOX_SHIFT`).
#[inline(always)]
fn box_ray(ray: &Ray) -> obvhs::ray::Ray {
    obvhs::ray::Ray::new(
        (ray.o - ray.d * BOX_SHIFT).into(),
        ray.d.into(),
        0.0,
        ray.t_max + BOX_SHIFT,
    )
}

impl Bvh {
    pub fn build(prims: Vec<Prim>) -> Self {
        if prims.is_empty() {
            return Self {
                bvh: None,
                geoms: Vec::new(),
                ids: Vec::new(),
            };
        }
        let boxes: Vec<PrimBox> = prims
            .iter()
            .map(|p| {
                let (lo, hi) = p.geom.bounds();
                PrimBox(Aabb::new(lo.into(), hi.into()))
            })
            .collect();
        let bvh = build_cwbvh(
            &boxes,
            BvhBuildParams::medium_build(),
            &mut Duration::default(),
        );
        let order = &bvh.primitive_indices;
        let geoms = order.iter().map(|&i| prims[i as usize].geom).collect();
        let ids = order.iter().map(|&i| prims[i as usize].id).collect();
        Self {
            bvh: Some(bvh),
            geoms,
            ids,
        }
    }

    pub fn prims(&self) -> &[PrimGeom] {
        &self.geoms
    }

    /// Closest hit. Uses obvhs' `traverse!` macro so the primitive test inlines into the loop.
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        let bvh = self.bvh.as_ref()?;
        let shear = RayShear::new(ray);
        let mut oray = box_ray(ray);
        let mut t_max = ray.t_max;
        let mut best = None;
        let mut state = bvh.new_traversal(oray.direction);
        let mut node;
        obvhs::traverse!(
            bvh,
            node,
            state,
            node.intersect_ray(&oray, state.oct_inv4),
            {
                let i = state.primitive_id as usize;
                if let Some(h) = self.geoms[i].intersect(ray, &shear, t_max) {
                    t_max = h.t;
                    oray.tmax = h.t + BOX_SHIFT;
                    best = Some(Hit {
                        prim: self.ids[i],
                        hit: h,
                    });
                }
            }
        );
        best
    }

    /// True if any primitive lies on the ray within (0, t_max); stops at the first one found.
    #[inline]
    pub fn occluded(&self, ray: &Ray) -> bool {
        let Some(bvh) = self.bvh.as_ref() else {
            return false;
        };
        let shear = RayShear::new(ray);
        let oray = box_ray(ray);
        let mut state = bvh.new_traversal(oray.direction);
        let mut node;
        let mut hit = false;
        'search: {
            obvhs::traverse!(
                bvh,
                node,
                state,
                node.intersect_ray(&oray, state.oct_inv4),
                {
                    if self.geoms[state.primitive_id as usize]
                        .intersect(ray, &shear, ray.t_max)
                        .is_some()
                    {
                        hit = true;
                        break 'search;
                    }
                }
            );
        }
        hit
    }
}
