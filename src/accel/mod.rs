//! Ray queries over the scene's primitives: closest hit and occlusion.
//!
//! One small interface; the backend is chosen at build time of the scene. `Bvh` (prism's 8-wide
//! SIMD BVH, built with obvhs) renders by default; `Embree` (Intel Embree 3, cargo feature `embree`) is the
//! alternative; `BruteForce` tests every primitive and exists to check the fast ones.

mod brute;
mod bvh;
mod bvh8;
#[cfg(feature = "embree")]
mod embree;
pub mod instances;
pub mod moving;

use crate::ray::Ray;
use crate::shape::{PrimGeom, PrimHit};
pub use brute::BruteForce;
pub use bvh::Bvh;
#[cfg(feature = "embree")]
pub use embree::Embree;
use serde::{Deserialize, Serialize};

/// Which acceleration structure to build. `Embree` exists in every build so that scene files
/// parse the same everywhere; a build without the `embree` feature rejects it when the scene is
/// checked (`is_available`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
pub enum AccelKind {
    #[default]
    Bvh,
    BruteForce,
    Embree,
}

impl AccelKind {
    /// False for `Embree` in a build without the `embree` feature.
    pub fn is_available(self) -> bool {
        self != AccelKind::Embree || cfg!(feature = "embree")
    }
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
    #[cfg(feature = "embree")]
    Embree(Embree),
}

impl Accel {
    /// Builds the structure. `kind` must be available in this build (`AccelKind::is_available`;
    /// the scene loader checks it and reports a clear error for scene files and flags).
    pub fn build(prims: Vec<Prim>, kind: AccelKind) -> Accel {
        match kind {
            AccelKind::Bvh => Accel::Bvh(Bvh::build(prims)),
            AccelKind::BruteForce => Accel::BruteForce(BruteForce::new(prims)),
            #[cfg(feature = "embree")]
            AccelKind::Embree => Accel::Embree(Embree::build(prims)),
            #[cfg(not(feature = "embree"))]
            AccelKind::Embree => {
                panic!("Accel::build: this prism was built without the `embree` feature")
            }
        }
    }

    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        match self {
            Accel::Bvh(b) => b.intersect(ray),
            Accel::BruteForce(b) => b.intersect(ray),
            #[cfg(feature = "embree")]
            Accel::Embree(b) => b.intersect(ray),
        }
    }

    /// True if anything lies on the ray within (0, t_max).
    #[inline]
    pub fn occluded(&self, ray: &Ray) -> bool {
        match self {
            Accel::Bvh(b) => b.occluded(ray),
            Accel::BruteForce(b) => b.occluded(ray),
            #[cfg(feature = "embree")]
            Accel::Embree(b) => b.occluded(ray),
        }
    }

    /// Scene bounds (min, max); a unit box at the origin for an empty scene.
    pub fn bounds(&self) -> (glam::Vec3, glam::Vec3) {
        let fold = |prims: &[PrimGeom]| {
            prims.iter().fold(
                (glam::Vec3::INFINITY, glam::Vec3::NEG_INFINITY),
                |(lo, hi), p| {
                    let (a, b) = p.bounds();
                    (lo.min(a), hi.max(b))
                },
            )
        };
        let (lo, hi) = match self {
            Accel::Bvh(b) => b.bounds(),
            Accel::BruteForce(b) => fold(b.prims()),
            #[cfg(feature = "embree")]
            Accel::Embree(b) => fold(b.prims()),
        };
        if lo.cmple(hi).all() {
            (lo, hi)
        } else {
            (glam::Vec3::splat(-1.0), glam::Vec3::splat(1.0))
        }
    }
}
