//! Ray queries over the scene's primitives: closest hit and occlusion.
//!
//! One small interface; the backend is chosen at build time of the scene. `Bvh` (obvhs' compressed
//! wide BVH) renders; `BruteForce` tests every primitive and exists to check the fast one.

mod brute;
mod bvh;

use crate::ray::Ray;
use crate::shape::{PrimGeom, PrimHit};
pub use brute::BruteForce;
pub use bvh::Bvh;
use serde::{Deserialize, Serialize};

/// Which acceleration structure to build.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum AccelKind {
    #[default]
    Bvh,
    BruteForce,
}

/// A primitive for the acceleration structure: its scene-wide id and its geometry.
#[derive(Clone, Copy, Debug)]
pub struct Prim {
    pub id: u32,
    pub geom: PrimGeom,
}

/// The closest hit: the primitive's scene-wide id and where along the ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub prim: u32,
    pub hit: PrimHit,
}

pub enum Accel {
    Bvh(Bvh),
    BruteForce(BruteForce),
}

impl Accel {
    pub fn build(prims: Vec<Prim>, kind: AccelKind) -> Accel {
        match kind {
            AccelKind::Bvh => Accel::Bvh(Bvh::build(prims)),
            AccelKind::BruteForce => Accel::BruteForce(BruteForce::new(prims)),
        }
    }

    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        match self {
            Accel::Bvh(b) => b.intersect(ray),
            Accel::BruteForce(b) => b.intersect(ray),
        }
    }

    /// True if anything lies on the ray within (0, t_max).
    #[inline]
    pub fn occluded(&self, ray: &Ray) -> bool {
        match self {
            Accel::Bvh(b) => b.occluded(ray),
            Accel::BruteForce(b) => b.occluded(ray),
        }
    }

    /// Scene bounds (min, max); a unit box at the origin for an empty scene.
    pub fn bounds(&self) -> (glam::Vec3, glam::Vec3) {
        let prims = match self {
            Accel::Bvh(b) => b.prims(),
            Accel::BruteForce(b) => b.prims(),
        };
        if prims.is_empty() {
            return (glam::Vec3::splat(-1.0), glam::Vec3::splat(1.0));
        }
        prims.iter().fold(
            (glam::Vec3::INFINITY, glam::Vec3::NEG_INFINITY),
            |(lo, hi), p| {
                let (a, b) = p.bounds();
                (lo.min(a), hi.max(b))
            },
        )
    }
}
