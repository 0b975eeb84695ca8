//! Shapes: triangle meshes (and the rectangles and cubes built from them), spheres and disks,
//! all in world space (an `Instance` is a shared mesh placed by a transform, world space in what
//! it reports). Each is split into primitives for the acceleration structure.

mod disk;
pub mod instance;
pub mod mesh;
pub mod mesh_io;
pub mod normal_map;
mod sphere;
pub mod tri_surface;
pub mod triangle;

use crate::math::float::gamma;
use crate::math::Frame;
use disk::intersect_disk;
pub use disk::Disk;
use glam::{Vec2, Vec3};
pub use instance::Instance;
pub use mesh::Mesh;
use sphere::intersect_sphere;
pub use sphere::Sphere;
use std::f32::consts::PI;

#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    Mesh(Mesh),
    Sphere(Sphere),
    Disk(Disk),
    /// A shared mesh placed by a transform (one of its several uses; `shape::instance`).
    Instance(Instance),
}

/// Geometry of one primitive, as the acceleration structure stores it (compact and
/// self-contained, so traversal touches one array).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PrimGeom {
    Triangle([Vec3; 3]),
    Sphere {
        center: Vec3,
        radius: f32,
    },
    /// World-to-object rows of the disk's transform (affine, 3×4).
    Disk {
        to_object: [glam::Vec4; 3],
    },
}

/// A primitive hit: distance and two shape-specific coordinates (barycentrics for triangles).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrimHit {
    pub t: f32,
    pub b1: f32,
    pub b2: f32,
}

/// Surface data at a hit or sampled point.
pub struct SurfacePoint {
    pub p: Vec3,
    pub p_error: Vec3,
    pub ng: Vec3,
    pub frame: Frame,
    pub uv: Vec2,
}

/// A point sampled on a shape for emitter sampling, with its density w.r.t. area.
#[derive(Clone, Copy, Debug)]
pub struct AreaSample {
    pub p: Vec3,
    pub p_error: Vec3,
    pub n: Vec3,
    pub pdf_area: f32,
}

impl PrimGeom {
    /// Axis-aligned bounds (min, max).
    pub fn bounds(&self) -> (Vec3, Vec3) {
        match *self {
            PrimGeom::Triangle([a, b, c]) => (a.min(b).min(c), a.max(b).max(c)),
            PrimGeom::Sphere { center, radius } => (center - radius, center + radius),
            PrimGeom::Disk { to_object } => {
                let inv =
                    glam::Mat4::from_cols(to_object[0], to_object[1], to_object[2], glam::Vec4::W)
                        .transpose()
                        .inverse();
                let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                    .map(|(x, y)| inv.transform_point3(Vec3::new(x, y, 0.0)));
                let lo = corners.iter().fold(Vec3::INFINITY, |a, &b| a.min(b));
                let hi = corners.iter().fold(Vec3::NEG_INFINITY, |a, &b| a.max(b));
                // Pad by the rounding error of the transform so the box surely holds the disk.
                let pad = (hi.abs().max(lo.abs())) * gamma(4);
                (lo - pad, hi + pad)
            }
        }
    }

    #[inline]
    pub fn intersect(
        &self,
        ray: &crate::ray::Ray,
        shear: &triangle::RayShear,
        t_max: f32,
    ) -> Option<PrimHit> {
        match self {
            PrimGeom::Triangle(v) => triangle::intersect(shear, t_max, v).map(|h| PrimHit {
                t: h.t,
                b1: h.b1,
                b2: h.b2,
            }),
            _ => self.intersect_analytic(ray, t_max),
        }
    }

    /// Intersection with a sphere or disk (None for a triangle). Backends that test triangles
    /// themselves (Embree) call this for the analytic shapes, so every backend shares one
    /// definition of them.
    #[inline]
    pub fn intersect_analytic(&self, ray: &crate::ray::Ray, t_max: f32) -> Option<PrimHit> {
        match self {
            PrimGeom::Triangle(_) => None,
            PrimGeom::Sphere { center, radius } => intersect_sphere(ray, *center, *radius, t_max),
            PrimGeom::Disk { to_object } => intersect_disk(ray, to_object, t_max),
        }
    }
}

impl Shape {
    pub fn prim_count(&self) -> usize {
        match self {
            Shape::Mesh(m) => m.indices.len(),
            Shape::Instance(i) => i.mesh.indices.len(),
            _ => 1,
        }
    }

    pub fn prim_geom(&self, i: usize) -> PrimGeom {
        match self {
            Shape::Mesh(m) => PrimGeom::Triangle(m.vertices(i)),
            Shape::Instance(inst) => PrimGeom::Triangle(inst.vertices(i)),
            Shape::Sphere(s) => PrimGeom::Sphere {
                center: s.center,
                radius: s.radius,
            },
            Shape::Disk(d) => {
                let m = d.to_world.inv;
                PrimGeom::Disk {
                    to_object: [m.row(0), m.row(1), m.row(2)],
                }
            }
        }
    }

    /// True if primitive `i` cannot be hit or sampled (zero area or non-finite), so the scene
    /// leaves it out of the acceleration structure.
    pub fn prim_is_degenerate(&self, i: usize) -> bool {
        match self {
            Shape::Mesh(m) => {
                let a = m.triangle_area(i);
                !(a > 0.0 && a.is_finite())
            }
            Shape::Instance(inst) => {
                let a = inst.triangle_area(i);
                !(a > 0.0 && a.is_finite())
            }
            Shape::Sphere(s) => !(s.radius > 0.0 && s.radius.is_finite() && s.center.is_finite()),
            Shape::Disk(_) => {
                let a = self.area();
                a.is_nan() || a <= 0.0
            }
        }
    }

    /// Surface data at a hit of primitive `prim` by `ray`.
    #[inline]
    pub fn surface(&self, prim: usize, ray: &crate::ray::Ray, hit: &PrimHit) -> SurfacePoint {
        match self {
            Shape::Mesh(m) => {
                let s = m.surface(prim, hit.b1, hit.b2);
                SurfacePoint {
                    p: s.p,
                    p_error: s.p_error,
                    ng: s.ng,
                    frame: s.frame,
                    uv: s.uv,
                }
            }
            Shape::Instance(inst) => {
                let s = inst.surface(prim, hit.b1, hit.b2);
                SurfacePoint {
                    p: s.p,
                    p_error: s.p_error,
                    ng: s.ng,
                    frame: s.frame,
                    uv: s.uv,
                }
            }
            Shape::Sphere(s) => s.surface_at(ray.at(hit.t)),
            Shape::Disk(d) => d.surface_at(Vec2::new(hit.b1, hit.b2)),
        }
    }

    pub fn area(&self) -> f32 {
        match self {
            Shape::Mesh(m) => (0..m.indices.len()).map(|i| m.triangle_area(i)).sum(),
            Shape::Instance(inst) => (0..inst.mesh.indices.len())
                .map(|i| inst.triangle_area(i))
                .sum(),
            Shape::Sphere(s) => 4.0 * PI * s.radius * s.radius,
            Shape::Disk(d) => {
                PI * d
                    .to_world
                    .vector(Vec3::X)
                    .cross(d.to_world.vector(Vec3::Y))
                    .length()
            }
        }
    }
}
