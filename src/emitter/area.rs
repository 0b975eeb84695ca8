//! Area emitters: radiance from the front side of a shape, uniform or textured over its uv
//! (`radiance::AreaRadiance`). Points are sampled by area (meshes pick a triangle by area),
//! except on spheres, which sample the cone they subtend (uniform in solid angle, so a small
//! distant sphere light is not noisy). A textured mesh light picks its triangle by area × the
//! triangle's mean emitted luminance instead, so black parts of the texture take no samples
//! (a triangle that emits nothing is never picked); `pdf_li` then reads the hit triangle's
//! density, the same number `sample_point` reports.

use super::parallelogram::Parallelogram;
use super::radiance::AreaRadiance;
use super::EmitterSample;
use crate::interaction::SurfaceInteraction;
use crate::math::distribution::Distribution1D;
use crate::math::sampling::square_to_triangle;
use crate::shape::{AreaSample, Mesh, Shape};
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
    /// Surface coordinates of the point (meshes; what a textured radiance is looked up at).
    pub uv: Vec2,
}

#[derive(Clone, Debug)]
pub struct AreaEmitter {
    pub shape: u32,
    pub radiance: AreaRadiance,
    /// Triangle choice (meshes only): by area, or by area × mean emission when textured.
    triangles: Option<Distribution1D>,
    area: f32,
    /// Textured meshes: each triangle's area density, pmf / area (0 for a triangle never
    /// picked); empty otherwise (the density is then 1 / area everywhere).
    tri_pdf: Vec<f32>,
    /// Meshes: each triangle's `Mesh::winding_normal`, so a sample does not recompute it.
    normals: Vec<Vec3>,
    /// A uniform light on a two-triangle parallelogram mesh, sampled as one.
    parallelogram: Option<Parallelogram>,
}

/// uv at barycentrics `b` of triangle `i`, as `Mesh::surface` computes it.
#[inline]
fn mesh_uv(m: &Mesh, i: usize, b: Vec2) -> Vec2 {
    if m.uvs.is_empty() {
        return b;
    }
    let [i0, i1, i2] = m.indices[i].map(|v| v as usize);
    (1.0 - b.x - b.y) * m.uvs[i0] + b.x * m.uvs[i1] + b.y * m.uvs[i2]
}

/// Corner uvs of triangle `i` of `m` (the barycentric parameterisation without uvs).
fn corner_uvs(m: &Mesh, i: usize) -> [Vec2; 3] {
    if m.uvs.is_empty() {
        return [Vec2::ZERO, Vec2::X, Vec2::Y];
    }
    m.indices[i].map(|v| m.uvs[v as usize])
}

impl AreaEmitter {
    /// A light of uniform `radiance`.
    pub fn new(shape_index: u32, shape: &Shape, radiance: Curve) -> Self {
        Self::with_radiance(shape_index, shape, AreaRadiance::Uniform(radiance))
    }

    /// A light of uniform or textured `radiance`. A textured one must be a mesh or an instance
    /// (the loaders refuse textured spheres and disks).
    pub fn with_radiance(shape_index: u32, shape: &Shape, radiance: AreaRadiance) -> Self {
        // Per triangle: (area, corner uvs).
        let tris: Option<Vec<(f32, [Vec2; 3])>> = match shape {
            Shape::Mesh(m) => Some(
                (0..m.indices.len())
                    .map(|i| (m.triangle_area(i), corner_uvs(m, i)))
                    .collect(),
            ),
            Shape::Instance(inst) => Some(
                (0..inst.mesh.indices.len())
                    .map(|i| (inst.triangle_area(i), corner_uvs(&inst.mesh, i)))
                    .collect(),
            ),
            _ => None,
        };
        let (triangles, tri_pdf) = match (tris, &radiance) {
            (None, _) => (None, Vec::new()),
            (Some(t), AreaRadiance::Uniform(_)) => {
                let areas: Vec<f32> = t.iter().map(|x| x.0).collect();
                (Some(Distribution1D::new(&areas)), Vec::new())
            }
            (Some(t), AreaRadiance::Textured(tex)) => {
                let weights: Vec<f32> = t
                    .iter()
                    .map(|&(a, uv)| {
                        let w = a * tex.mean_over_triangle(uv);
                        if w.is_finite() && a > 0.0 {
                            w.max(0.0)
                        } else {
                            0.0
                        }
                    })
                    .collect();
                let d = Distribution1D::new(&weights);
                let pdf = t
                    .iter()
                    .enumerate()
                    .map(|(i, &(a, _))| {
                        let p = d.pmf(i);
                        if a > 0.0 && p > 0.0 {
                            p / a
                        } else {
                            0.0
                        }
                    })
                    .collect();
                (Some(d), pdf)
            }
        };
        let normals = match shape {
            Shape::Mesh(m) => (0..m.indices.len()).map(|i| m.winding_normal(i)).collect(),
            _ => Vec::new(),
        };
        let area = shape.area();
        let parallelogram = match (shape, &radiance) {
            (Shape::Mesh(m), AreaRadiance::Uniform(_)) => Parallelogram::of(m, 1.0 / area),
            _ => None,
        };
        Self {
            shape: shape_index,
            radiance,
            triangles,
            area,
            tri_pdf,
            normals,
            parallelogram,
        }
    }

    /// The object-space area density of a point on primitive `prim` (what `sample_area_uv`
    /// reports there).
    pub(super) fn pdf_area(&self, prim: u32) -> f32 {
        if self.tri_pdf.is_empty() {
            1.0 / self.area
        } else {
            self.tri_pdf.get(prim as usize).copied().unwrap_or(0.0)
        }
    }

    /// A uniform point on the shape (area measure; for emitter sampling the caller handles the
    /// sphere case by its cone). Uniform lights only: a textured one samples by its triangle
    /// weights, and a parallelogram as one (`sample_area_uv`).
    fn sample_area(&self, u: Vec2, shape: &Shape) -> AreaSample {
        match shape {
            Shape::Mesh(m) => {
                let (tri, _, ux) = self.triangles.as_ref().unwrap().sample_discrete(u.x);
                let b = square_to_triangle(Vec2::new(ux, u.y));
                let (p, p_error, n) = m.point_with_normal(tri, b.x, b.y, self.normals[tri]);
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

    /// A point on the shape with its uv (zero for a uniform light, which has no use for it): a
    /// uniform parallelogram as one, inline; another uniform light by `sample_area`; a textured
    /// one by its triangle weights, out of line, so uniform lights carry none of that code.
    #[inline(always)]
    pub fn sample_area_uv(&self, u: Vec2, shape: &Shape) -> (AreaSample, Vec2) {
        if let Some(q) = &self.parallelogram {
            // Inline: about 40 instructions, a third of them the call's own out of line.
            return (q.sample(u), Vec2::ZERO);
        }
        if self.tri_pdf.is_empty() {
            (self.sample_area(u, shape), Vec2::ZERO)
        } else {
            self.sample_area_textured(u, shape)
        }
    }

    #[inline(never)]
    fn sample_area_textured(&self, u: Vec2, shape: &Shape) -> (AreaSample, Vec2) {
        let (tri, _, ux) = self.triangles.as_ref().unwrap().sample_discrete(u.x);
        let b = square_to_triangle(Vec2::new(ux, u.y));
        let pdf_area = self.tri_pdf[tri];
        let (p, p_error, n, uv) = match shape {
            Shape::Mesh(m) => {
                let (p, p_error, n) = m.point_with_normal(tri, b.x, b.y, self.normals[tri]);
                (p, p_error, n, mesh_uv(m, tri, b))
            }
            Shape::Instance(inst) => {
                let s = inst.surface(tri, b.x, b.y);
                (s.p, s.p_error, s.ng, s.uv)
            }
            _ => unreachable!("only meshes and instances have triangle densities"),
        };
        (
            AreaSample {
                p,
                p_error,
                n,
                pdf_area,
            },
            uv,
        )
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
            radiance: self.radiance.eval(s.uv, wl),
            pdf: s.pdf,
            delta: false,
        })
    }

    /// A point on the light as seen from `si`: direction, shadow ray, solid-angle density and
    /// uv, without the radiance. The path loop evaluates a uniform radiance once per path, a
    /// textured one at the point's uv, and only for samples that reach `si` (see
    /// `path::LeMemo`). Always inline: the path loop calls it at every hit.
    #[inline(always)]
    pub fn sample_point(
        &self,
        si: &SurfaceInteraction,
        u: Vec2,
        shapes: &[Shape],
    ) -> Option<AreaLightSample> {
        let shape = &shapes[self.shape as usize];
        let (s, pdf, uv) = match shape {
            Shape::Sphere(sph) => {
                let (s, pdf) = sph.sample_from(si.p, u);
                (s, pdf, Vec2::ZERO)
            }
            _ => {
                let (s, uv) = self.sample_area_uv(u, shape);
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
                    uv,
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
            uv,
        })
    }

    /// Density of `sample_li` from `p` yielding the emitter point `light` (a textured mesh
    /// light reads the density of the hit triangle, `light.prim`).
    #[inline]
    pub fn pdf_li(&self, p: Vec3, light: &SurfaceInteraction, shapes: &[Shape]) -> f32 {
        match &shapes[self.shape as usize] {
            Shape::Sphere(sph) => sph.pdf_from(p, light.p, light.ng),
            _ if self.tri_pdf.is_empty() => {
                let to = light.p - p;
                let d2 = to.length_squared();
                let cos = light.ng.dot(-to) / d2.sqrt();
                if cos > 0.0 {
                    d2 / (cos * self.area)
                } else {
                    0.0
                }
            }
            _ => self.pdf_li_textured(p, light),
        }
    }

    #[inline(never)]
    fn pdf_li_textured(&self, p: Vec3, light: &SurfaceInteraction) -> f32 {
        let to = light.p - p;
        let d2 = to.length_squared();
        let cos = light.ng.dot(-to) / d2.sqrt();
        let pdf_area = self
            .tri_pdf
            .get(light.prim as usize)
            .copied()
            .unwrap_or(0.0);
        if cos > 0.0 {
            pdf_area * d2 / cos
        } else {
            0.0
        }
    }
}
