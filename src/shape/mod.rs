//! Shapes: triangle meshes (and the rectangles and cubes built from them), spheres and disks,
//! all in world space (an `Instance` is a shared mesh placed by a transform, world space in what
//! it reports). Each is split into primitives for the acceleration structure.

pub mod instance;
pub mod mesh;
pub mod mesh_io;
pub mod normal_map;
pub mod triangle;

use crate::math::float::gamma;
use crate::math::{sampling, Frame, Transform};
use glam::{Vec2, Vec3};
pub use instance::Instance;
pub use mesh::Mesh;
use std::f32::consts::PI;

#[derive(Clone, Debug, PartialEq)]
pub struct Sphere {
    pub center: Vec3,
    pub radius: f32,
    /// Normals point inward (the front side is the inside).
    pub flip: bool,
}

/// The unit disk in the local z = 0 plane (normal +z), placed by `to_world`.
#[derive(Clone, Debug, PartialEq)]
pub struct Disk {
    pub to_world: Transform,
    pub flip: bool,
}

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

/// Ray/disk: the ray in the disk's object space meets z = 0 inside the unit circle; (b1, b2) are
/// the object-space (x, y) of the hit.
#[inline]
fn intersect_disk(
    ray: &crate::ray::Ray,
    to_object: &[glam::Vec4; 3],
    t_max: f32,
) -> Option<PrimHit> {
    let o = ray.o.extend(1.0);
    let d = ray.d.extend(0.0);
    let (oz, dz) = (to_object[2].dot(o), to_object[2].dot(d));
    if dz == 0.0 {
        return None;
    }
    let t = -oz / dz;
    if !(t > 0.0 && t < t_max) {
        return None;
    }
    let x = to_object[0].dot(o) + t * to_object[0].dot(d);
    let y = to_object[1].dot(o) + t * to_object[1].dot(d);
    (x * x + y * y <= 1.0).then_some(PrimHit { t, b1: x, b2: y })
}

/// Ray/sphere intersection in f64 with the numerically stable root pair (the discriminant is
/// formed from the perpendicular distance, which does not cancel for distant spheres).
#[inline]
fn intersect_sphere(
    ray: &crate::ray::Ray,
    center: Vec3,
    radius: f32,
    t_max: f32,
) -> Option<PrimHit> {
    let o = ray.o.as_dvec3() - center.as_dvec3();
    let d = ray.d.as_dvec3();
    let r = radius as f64;
    let b = o.dot(d);
    let perp = o - b * d;
    let disc = r * r - perp.length_squared();
    if disc < 0.0 {
        return None;
    }
    let c = o.length_squared() - r * r;
    let q = -b - disc.sqrt().copysign(b);
    let (mut t0, mut t1) = if q != 0.0 { (c / q, q) } else { (0.0, 0.0) };
    if t0 > t1 {
        std::mem::swap(&mut t0, &mut t1);
    }
    let t_max = t_max as f64;
    let t = if t0 > 0.0 && t0 < t_max {
        t0
    } else if t1 > 0.0 && t1 < t_max {
        t1
    } else {
        return None;
    };
    Some(PrimHit {
        t: t as f32,
        b1: 0.0,
        b2: 0.0,
    })
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

impl Sphere {
    fn surface_at(&self, hit: Vec3) -> SurfacePoint {
        // Reproject onto the sphere: the error then depends only on |p|, not on the ray length.
        let dir = (hit - self.center).normalize();
        let p = self.center + dir * self.radius;
        let p_error = gamma(5) * (self.center.abs() + (dir * self.radius).abs());
        let n = if self.flip { -dir } else { dir };
        let phi = dir.y.atan2(dir.x);
        let phi = if phi < 0.0 { phi + 2.0 * PI } else { phi };
        let theta = dir.z.clamp(-1.0, 1.0).acos();
        let dpdu = Vec3::new(-dir.y, dir.x, 0.0);
        SurfacePoint {
            p,
            p_error,
            ng: n,
            frame: Frame::from_normal_tangent(n, dpdu),
            uv: Vec2::new(phi / (2.0 * PI), theta / PI),
        }
    }

    /// Uniform point on the whole sphere.
    pub fn sample_area(&self, u: Vec2) -> AreaSample {
        let dir = sampling::square_to_uniform_sphere(u);
        let s = self.surface_at(self.center + dir * self.radius);
        AreaSample {
            p: s.p,
            p_error: s.p_error,
            n: s.ng,
            pdf_area: 1.0 / (4.0 * PI * self.radius * self.radius),
        }
    }

    /// 1 − cos θ_max of the cone the sphere subtends from `p` (None if `p` is inside), computed
    /// without cancellation so a tiny distant sphere keeps an accurate, non-zero cone.
    pub fn cone_one_minus_cos(&self, p: Vec3) -> Option<f32> {
        let dc2 = (self.center - p).length_squared();
        let r2 = self.radius * self.radius;
        if dc2 <= r2 * (1.0 + 1e-4) {
            return None;
        }
        let sin2 = r2 / dc2;
        let cos = (1.0 - sin2).max(0.0).sqrt();
        Some(sin2 / (1.0 + cos))
    }

    /// A point on the part of the sphere visible from `p`, uniform in solid angle (the cone
    /// method), or uniform in area when `p` is inside. Returns the sample and its solid-angle pdf.
    pub fn sample_from(&self, p: Vec3, u: Vec2) -> (AreaSample, f32) {
        let Some(omc) = self.cone_one_minus_cos(p) else {
            let s = self.sample_area(u);
            let to = s.p - p;
            let d2 = to.length_squared();
            let cos = s.n.dot(-to / d2.sqrt()).abs();
            let pdf = if cos > 0.0 {
                s.pdf_area * d2 / cos
            } else {
                0.0
            };
            return (s, pdf);
        };
        let to_c = self.center - p;
        let dc = to_c.length();
        let frame = Frame::from_normal(to_c / dc);
        // θ from the cone axis: 1 − cos θ = u·omc and sin²θ = (1 − cos θ)(1 + cos θ), never
        // formed by subtracting from 1 (for a tiny light that would leave a few distinct angles).
        let one_minus_cos_t = u.x * omc;
        let cos_t = 1.0 - one_minus_cos_t;
        let sin2_t = one_minus_cos_t * (2.0 - one_minus_cos_t);
        // Angle α at the centre between −axis and the surface point the direction hits first:
        // cos α = sin²θ / sin θmax + cos θ · √(1 − sin²θ / sin²θmax), free of cancellation.
        let r = self.radius;
        let sin_max = r / dc;
        let ratio = (sin2_t / (sin_max * sin_max)).min(1.0);
        let cos_a = (sin2_t / sin_max + cos_t * (1.0 - ratio).sqrt()).clamp(-1.0, 1.0);
        let sin_a = (1.0 - cos_a * cos_a).max(0.0).sqrt();
        let (sp, cp) = (2.0 * PI * u.y).sin_cos();
        let local = Vec3::new(sin_a * cp, sin_a * sp, cos_a);
        let dir = -frame.to_world(local);
        let s = self.surface_at(self.center + dir * r);
        let pdf = 1.0 / (2.0 * PI * omc);
        (
            AreaSample {
                p: s.p,
                p_error: s.p_error,
                n: s.ng,
                pdf_area: 0.0,
            },
            pdf,
        )
    }

    /// Solid-angle pdf of `sample_from(p, ·)` choosing the surface point `q` with normal `n`.
    pub fn pdf_from(&self, p: Vec3, q: Vec3, n: Vec3) -> f32 {
        match self.cone_one_minus_cos(p) {
            Some(omc) => 1.0 / (2.0 * PI * omc),
            None => {
                let to = q - p;
                let d2 = to.length_squared();
                let cos = n.dot(to / d2.sqrt()).abs();
                if cos > 0.0 {
                    d2 / (cos * 4.0 * PI * self.radius * self.radius)
                } else {
                    0.0
                }
            }
        }
    }
}

impl Disk {
    fn surface_at(&self, local: Vec2) -> SurfacePoint {
        let (p, p_error) = self.to_world.point_with_error(local.extend(0.0));
        let mut n = self.to_world.normal(Vec3::Z).normalize();
        if self.flip {
            n = -n;
        }
        let r = local.length();
        let phi = local.y.atan2(local.x);
        let phi = if phi < 0.0 { phi + 2.0 * PI } else { phi };
        let dpdu = self.to_world.vector(Vec3::new(-local.y, local.x, 0.0));
        SurfacePoint {
            p,
            p_error,
            ng: n,
            frame: Frame::from_normal_tangent(n, dpdu),
            uv: Vec2::new(r, phi / (2.0 * PI)),
        }
    }

    /// Uniform point on the (possibly elliptical) disk: an affine map keeps uniform density.
    pub fn sample_area(&self, u: Vec2, area: f32) -> AreaSample {
        let s = self.surface_at(sampling::square_to_disk_concentric(u));
        AreaSample {
            p: s.p,
            p_error: s.p_error,
            n: s.ng,
            pdf_area: 1.0 / area,
        }
    }
}
