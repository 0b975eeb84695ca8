//! Triangle meshes in world space, and the built-in rectangle and cube (Mitsuba 3's shapes).

use crate::math::float::gamma;
use crate::math::{Frame, Transform};
use glam::{Vec2, Vec3};

#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    pub positions: Vec<Vec3>,
    /// Per-vertex shading normals; empty for flat shading.
    pub normals: Vec<Vec3>,
    /// Per-vertex texture coordinates; empty if the mesh has none.
    pub uvs: Vec<Vec2>,
    pub indices: Vec<[u32; 3]>,
    /// A normal map with its tangents (glTF `normalTexture`); None for most meshes.
    pub normal_map: Option<Box<super::normal_map::NormalMapping>>,
}

/// Surface data at a point of a triangle.
pub struct TriangleSurface {
    pub p: Vec3,
    pub p_error: Vec3,
    pub ng: Vec3,
    pub frame: Frame,
    pub uv: Vec2,
}

impl Mesh {
    /// Mitsuba's `rectangle`: [-1,1]² in the z = 0 plane, normal +z, uv (0,0) at (-1,-1).
    pub fn rectangle() -> Mesh {
        Mesh {
            positions: vec![
                Vec3::new(-1.0, -1.0, 0.0),
                Vec3::new(1.0, -1.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(-1.0, 1.0, 0.0),
            ],
            normals: Vec::new(),
            uvs: vec![
                Vec2::new(0.0, 0.0),
                Vec2::new(1.0, 0.0),
                Vec2::new(1.0, 1.0),
                Vec2::new(0.0, 1.0),
            ],
            indices: vec![[0, 1, 2], [2, 3, 0]],
            normal_map: None,
        }
    }

    /// Mitsuba's `cube`: [-1,1]³ with outward faces, each face its own 4 vertices.
    pub fn cube() -> Mesh {
        let mut m = Mesh::default();
        // (normal, u axis, v axis): u × v = normal, so the winding faces outward.
        let faces = [
            (Vec3::X, Vec3::Y, Vec3::Z),
            (-Vec3::X, Vec3::Z, Vec3::Y),
            (Vec3::Y, Vec3::Z, Vec3::X),
            (-Vec3::Y, Vec3::X, Vec3::Z),
            (Vec3::Z, Vec3::X, Vec3::Y),
            (-Vec3::Z, Vec3::Y, Vec3::X),
        ];
        for (n, u, v) in faces {
            let base = m.positions.len() as u32;
            for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                m.positions.push(n + u * a + v * b);
                m.uvs.push(Vec2::new((a + 1.0) * 0.5, (b + 1.0) * 0.5));
            }
            m.indices.push([base, base + 1, base + 2]);
            m.indices.push([base + 2, base + 3, base]);
        }
        m
    }

    /// Applies `to_world` (normals by the inverse transpose); `flip` reverses the winding, which
    /// turns the surface's front side around.
    pub fn transformed(mut self, to_world: &Transform, flip: bool) -> Mesh {
        for p in &mut self.positions {
            *p = to_world.point(*p);
        }
        for n in &mut self.normals {
            let t = to_world.normal(*n).normalize_or_zero();
            *n = if flip { -t } else { t };
        }
        if flip {
            for tri in &mut self.indices {
                tri.swap(1, 2);
            }
        }
        self
    }

    #[inline]
    pub fn vertices(&self, i: usize) -> [Vec3; 3] {
        let [a, b, c] = self.indices[i];
        [
            self.positions[a as usize],
            self.positions[b as usize],
            self.positions[c as usize],
        ]
    }

    pub fn triangle_area(&self, i: usize) -> f32 {
        let [a, b, c] = self.vertices(i);
        0.5 * (b - a).cross(c - a).length()
    }

    /// Position, its error bound, and the unit geometric normal at barycentrics (b1, b2) of
    /// triangle `i`: what emitter sampling needs, without the shading frame.
    #[inline]
    pub fn point(&self, i: usize, b1: f32, b2: f32) -> (Vec3, Vec3, Vec3) {
        let [i0, i1, i2] = self.indices[i].map(|v| v as usize);
        let (p0, p1, p2) = (self.positions[i0], self.positions[i1], self.positions[i2]);
        let b0 = 1.0 - b1 - b2;
        // Barycentric interpolation is more accurate than o + t·d, and its error is bounded.
        let p = b0 * p0 + b1 * p1 + b2 * p2;
        let p_error = gamma(7) * ((b0 * p0).abs() + (b1 * p1).abs() + (b2 * p2).abs());
        let mut ng = (p1 - p0).cross(p2 - p0).normalize_or_zero();
        if !self.normals.is_empty() {
            // The geometric normal follows the shading normal's side, so "front" is the side
            // the vertex normals point to, whatever the winding.
            let n = b0 * self.normals[i0] + b1 * self.normals[i1] + b2 * self.normals[i2];
            if ng.dot(n) < 0.0 {
                ng = -ng;
            }
        }
        (p, p_error, ng)
    }

    /// Point, normals, shading frame and uv at barycentrics (b1, b2) of triangle `i`.
    #[inline]
    pub fn surface(&self, i: usize, b1: f32, b2: f32) -> TriangleSurface {
        let (p, p_error, ng) = self.point(i, b1, b2);
        let [i0, i1, i2] = self.indices[i].map(|v| v as usize);
        let b0 = 1.0 - b1 - b2;
        let e1 = self.positions[i1] - self.positions[i0];
        let (uv, dpdu) = if self.uvs.is_empty() {
            (Vec2::new(b1, b2), e1)
        } else {
            let (uv0, uv1, uv2) = (self.uvs[i0], self.uvs[i1], self.uvs[i2]);
            // dp/du from the uv parameterisation, for a tangent that follows the texture.
            let e2 = self.positions[i2] - self.positions[i0];
            let (duv1, duv2) = (uv1 - uv0, uv2 - uv0);
            let det = duv1.x * duv2.y - duv1.y * duv2.x;
            let dpdu = if det.abs() > 1e-12 {
                (e1 * duv2.y - e2 * duv1.y) / det
            } else {
                e1
            };
            (b0 * uv0 + b1 * uv1 + b2 * uv2, dpdu)
        };
        let ns = if self.normals.is_empty() {
            ng
        } else {
            let n = (b0 * self.normals[i0] + b1 * self.normals[i1] + b2 * self.normals[i2])
                .normalize_or_zero();
            if n == Vec3::ZERO {
                ng
            } else {
                n
            }
        };
        let frame = match &self.normal_map {
            None => Frame::from_normal_tangent(ns, dpdu),
            Some(nm) => nm.frame([i0, i1, i2], [b0, b1, b2], ns, uv),
        };
        TriangleSurface {
            p,
            p_error,
            ng,
            frame,
            uv,
        }
    }

    /// Checks indices and values; returns the message of the first problem.
    pub fn validate(&self) -> Result<(), String> {
        if self.indices.is_empty() {
            return Err("the mesh has no faces".into());
        }
        let n = self.positions.len();
        if let Some(p) = self.positions.iter().position(|p| !p.is_finite()) {
            return Err(format!(
                "vertex {p} has a non-finite position {:?}",
                self.positions[p]
            ));
        }
        if !self.normals.is_empty() && self.normals.len() != n {
            return Err(format!("{} normals for {} vertices", self.normals.len(), n));
        }
        if !self.uvs.is_empty() && self.uvs.len() != n {
            return Err(format!(
                "{} texture coordinates for {} vertices",
                self.uvs.len(),
                n
            ));
        }
        for (f, tri) in self.indices.iter().enumerate() {
            if let Some(&bad) = tri.iter().find(|&&v| v as usize >= n) {
                return Err(format!(
                    "face {f} uses vertex {bad}, but the mesh has {n} vertices"
                ));
            }
        }
        Ok(())
    }
}

/// One triangle's vertices (positions, and normals and uvs where the mesh has them) with their
/// indices in the mesh: an instance's, transformed to world space on the fly
/// (`shape::instance`). `Tri::surface` repeats `Mesh::point` and `Mesh::surface` operation for
/// operation, so an instance shades exactly as its world-space copy would; the mesh keeps its
/// own copy because routing it through `Tri` cost the flat path 3% more instructions per
/// sample (callgrind, Cornell box). Keep the two in step.
pub struct Tri {
    pub idx: [usize; 3],
    pub p: [Vec3; 3],
    pub n: Option<[Vec3; 3]>,
    pub uv: Option<[Vec2; 3]>,
}

/// `Mesh::point` on vertex data.
#[inline]
fn tri_point(p: &[Vec3; 3], n: Option<&[Vec3; 3]>, b1: f32, b2: f32) -> (Vec3, Vec3, Vec3) {
    let (p0, p1, p2) = (p[0], p[1], p[2]);
    let b0 = 1.0 - b1 - b2;
    // Barycentric interpolation is more accurate than o + t·d, and its error is bounded.
    let p = b0 * p0 + b1 * p1 + b2 * p2;
    let p_error = gamma(7) * ((b0 * p0).abs() + (b1 * p1).abs() + (b2 * p2).abs());
    let mut ng = (p1 - p0).cross(p2 - p0).normalize_or_zero();
    if let Some(nv) = n {
        // The geometric normal follows the shading normal's side, so "front" is the side
        // the vertex normals point to, whatever the winding.
        let n = b0 * nv[0] + b1 * nv[1] + b2 * nv[2];
        if ng.dot(n) < 0.0 {
            ng = -ng;
        }
    }
    (p, p_error, ng)
}

impl Tri {
    /// `Mesh::surface` on this triangle's data (`normal_map`: the mesh's, indexed by `idx`).
    #[inline]
    pub fn surface(
        &self,
        normal_map: Option<&super::normal_map::NormalMapping>,
        b1: f32,
        b2: f32,
    ) -> TriangleSurface {
        let (p, p_error, ng) = tri_point(&self.p, self.n.as_ref(), b1, b2);
        let [i0, i1, i2] = self.idx;
        let b0 = 1.0 - b1 - b2;
        let e1 = self.p[1] - self.p[0];
        let (uv, dpdu) = match self.uv {
            None => (Vec2::new(b1, b2), e1),
            Some([uv0, uv1, uv2]) => {
                // dp/du from the uv parameterisation, for a tangent that follows the texture.
                let e2 = self.p[2] - self.p[0];
                let (duv1, duv2) = (uv1 - uv0, uv2 - uv0);
                let det = duv1.x * duv2.y - duv1.y * duv2.x;
                let dpdu = if det.abs() > 1e-12 {
                    (e1 * duv2.y - e2 * duv1.y) / det
                } else {
                    e1
                };
                (b0 * uv0 + b1 * uv1 + b2 * uv2, dpdu)
            }
        };
        let ns = match self.n {
            None => ng,
            Some([n0, n1, n2]) => {
                let n = (b0 * n0 + b1 * n1 + b2 * n2).normalize_or_zero();
                if n == Vec3::ZERO {
                    ng
                } else {
                    n
                }
            }
        };
        let frame = match normal_map {
            None => Frame::from_normal_tangent(ns, dpdu),
            Some(nm) => nm.frame([i0, i1, i2], [b0, b1, b2], ns, uv),
        };
        TriangleSurface {
            p,
            p_error,
            ng,
            frame,
            uv,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtin_shapes_face_outward() {
        let r = Mesh::rectangle();
        assert!((r.triangle_area(0) + r.triangle_area(1) - 4.0).abs() < 1e-6);
        assert!((r.surface(0, 0.2, 0.2).ng - Vec3::Z).length() < 1e-6);
        let c = Mesh::cube();
        assert_eq!(c.indices.len(), 12);
        for i in 0..12 {
            let s = c.surface(i, 1.0 / 3.0, 1.0 / 3.0);
            assert!(
                s.ng.dot(s.p) > 0.9,
                "face {i} normal {:?} at {:?}",
                s.ng,
                s.p
            );
        }
        c.validate().unwrap();
    }
}
