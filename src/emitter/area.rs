//! Area emitters: uniform radiance from the front side of a shape. Points are sampled uniformly
//! by area (meshes pick a triangle by area), except on spheres, which sample the cone they
//! subtend (uniform in solid angle, so a small distant sphere light is not noisy).

use super::EmitterSample;
use crate::interaction::SurfaceInteraction;
use crate::math::distribution::Distribution1D;
use crate::math::sampling::square_to_triangle;
use crate::shape::{AreaSample, Shape};
use crate::spectrum::{Curve, Wavelengths};
use glam::{Vec2, Vec3};

/// A point sampled on an area light, seen from a receiving point.
#[derive(Clone, Copy, Debug)]
pub struct AreaLightSample {
    /// Unit direction from the receiving point towards the light.
    pub wi: Vec3,
    /// The shadow ray to test visibility with.
    pub shadow: crate::ray::Ray,
    /// Solid-angle density of `wi`.
    pub pdf: f32,
}

#[derive(Clone, Debug)]
pub struct AreaEmitter {
    pub shape: u32,
    pub radiance: Curve,
    /// Triangle choice by area (meshes only).
    triangles: Option<Distribution1D>,
    area: f32,
}

impl AreaEmitter {
    pub fn new(shape_index: u32, shape: &Shape, radiance: Curve) -> Self {
        let triangles = match shape {
            Shape::Mesh(m) => {
                let areas: Vec<f32> = (0..m.indices.len()).map(|i| m.triangle_area(i)).collect();
                Some(Distribution1D::new(&areas))
            }
            Shape::Instance(inst) => {
                let n = inst.mesh.indices.len();
                let areas: Vec<f32> = (0..n).map(|i| inst.triangle_area(i)).collect();
                Some(Distribution1D::new(&areas))
            }
            _ => None,
        };
        Self {
            shape: shape_index,
            radiance,
            triangles,
            area: shape.area(),
        }
    }

    /// A uniform point on the shape (area measure; for emitter sampling the caller handles the
    /// sphere case by its cone).
    pub fn sample_area(&self, u: Vec2, shape: &Shape) -> AreaSample {
        match shape {
            Shape::Mesh(m) => {
                let (tri, _, ux) = self.triangles.as_ref().unwrap().sample_discrete(u.x);
                let b = square_to_triangle(Vec2::new(ux, u.y));
                let (p, p_error, n) = m.point(tri, b.x, b.y);
                AreaSample {
                    p,
                    p_error,
                    n,
                    pdf_area: 1.0 / self.area,
                }
            }
            Shape::Instance(inst) => {
                let (tri, _, ux) = self.triangles.as_ref().unwrap().sample_discrete(u.x);
                let b = square_to_triangle(Vec2::new(ux, u.y));
                let s = inst.surface(tri, b.x, b.y);
                AreaSample {
                    p: s.p,
                    p_error: s.p_error,
                    n: s.ng,
                    pdf_area: 1.0 / self.area,
                }
            }
            Shape::Sphere(s) => s.sample_area(u),
            Shape::Disk(d) => d.sample_area(u, self.area),
        }
    }

    /// `sample_point` with the radiance evaluated.
    #[inline(always)]
    pub fn sample_li<const N: usize>(
        &self,
        si: &SurfaceInteraction,
        u: Vec2,
        wl: &Wavelengths<N>,
        shapes: &[Shape],
    ) -> Option<EmitterSample<N>> {
        let s = self.sample_point(si, u, shapes)?;
        Some(EmitterSample {
            wi: s.wi,
            shadow: s.shadow,
            radiance: self.radiance.eval(wl),
            pdf: s.pdf,
            delta: false,
        })
    }

    /// A point on the light as seen from `si`: direction, shadow ray and solid-angle density,
    /// without the radiance, which is the same everywhere on the light. The path loop
    /// evaluates that once per path, and only for samples that reach `si` (see
    /// `path::LeMemo`). Always inline: the path loop calls it at every hit.
    #[inline(always)]
    pub fn sample_point(
        &self,
        si: &SurfaceInteraction,
        u: Vec2,
        shapes: &[Shape],
    ) -> Option<AreaLightSample> {
        let shape = &shapes[self.shape as usize];
        let (s, pdf) = match shape {
            Shape::Sphere(sph) => sph.sample_from(si.p, u),
            _ => {
                let s = self.sample_area(u, shape);
                let to = s.p - si.p;
                let d2 = to.length_squared();
                let cos = s.n.dot(-to) / d2.sqrt();
                (
                    s,
                    if cos > 0.0 {
                        s.pdf_area * d2 / cos
                    } else {
                        0.0
                    },
                )
            }
        };
        let to = s.p - si.p;
        let dist = to.length();
        if !(pdf > 0.0 && pdf.is_finite() && dist > 0.0) {
            return None;
        }
        let wi = to / dist;
        // One-sided: nothing leaves the back of the emitter.
        if s.n.dot(-wi) <= 0.0 {
            return None;
        }
        Some(AreaLightSample {
            wi,
            shadow: si.spawn_to(s.p, s.p_error, Some(s.n)),
            pdf,
        })
    }

    /// Density of `sample_li` from `p` yielding the emitter point `light`.
    #[inline]
    pub fn pdf_li(&self, p: Vec3, light: &SurfaceInteraction, shapes: &[Shape]) -> f32 {
        match &shapes[self.shape as usize] {
            Shape::Sphere(sph) => sph.pdf_from(p, light.p, light.ng),
            _ => {
                let to = light.p - p;
                let d2 = to.length_squared();
                let cos = light.ng.dot(-to) / d2.sqrt();
                if cos > 0.0 {
                    d2 / (cos * self.area)
                } else {
                    0.0
                }
            }
        }
    }
}
