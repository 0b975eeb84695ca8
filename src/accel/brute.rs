//! Tests every primitive: slow, obviously correct, and the yardstick for the BVH.

use super::{Hit, Prim};
use crate::ray::Ray;
use crate::shape::{triangle::RayShear, PrimGeom};

pub struct BruteForce {
    geoms: Vec<PrimGeom>,
    ids: Vec<u32>,
}

impl BruteForce {
    pub fn new(prims: Vec<Prim>) -> Self {
        Self {
            ids: prims.iter().map(|p| p.id).collect(),
            geoms: prims.into_iter().map(|p| p.geom).collect(),
        }
    }

    pub fn prims(&self) -> &[PrimGeom] {
        &self.geoms
    }

    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        let shear = RayShear::new(ray);
        let mut t_max = ray.t_max;
        let mut best = None;
        for (i, g) in self.geoms.iter().enumerate() {
            if let Some(h) = g.intersect(ray, &shear, t_max) {
                t_max = h.t;
                best = Some(Hit {
                    prim: self.ids[i],
                    hit: h,
                });
            }
        }
        best
    }

    pub fn occluded(&self, ray: &Ray) -> bool {
        let shear = RayShear::new(ray);
        self.geoms
            .iter()
            .any(|g| g.intersect(ray, &shear, ray.t_max).is_some())
    }
}
