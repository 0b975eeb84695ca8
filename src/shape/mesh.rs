//! Triangle meshes in world space, and the built-in rectangle and cube (Mitsuba 3's shapes).

pub use super::tri_surface::TriangleSurface;
use super::tri_surface::{self, Corners};
use crate::math::Transform;
use glam::{Vec2, Vec3, Vec4};

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

    /// Applies `to_world` (normals by the inverse transpose, a normal map's tangents by the
    /// linear part, `normal_map::transform_tangent`); `flip` reverses the winding, which turns
    /// the surface's front side around.
    pub fn transformed(mut self, to_world: &Transform, flip: bool) -> Mesh {
        for p in &mut self.positions {
            *p = to_world.point(*p);
        }
        for n in &mut self.normals {
            let t = to_world.normal(*n).normalize_or_zero();
            *n = if flip { -t } else { t };
        }
        if let Some(nm) = &mut self.normal_map {
            let mirror = to_world.flips_handedness();
            for t in &mut nm.tangents {
                *t = super::normal_map::transform_tangent(to_world, mirror, *t);
            }
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

    /// Triangle `i`'s corners, read from the mesh's arrays.
    #[inline(always)]
    fn corners(&self, i: usize) -> MeshCorners<'_> {
        MeshCorners {
            m: self,
            idx: self.indices[i].map(|v| v as usize),
        }
    }

    /// Position, its error bound, and the unit geometric normal at barycentrics (b1, b2) of
    /// triangle `i`: what emitter sampling needs, without the shading frame.
    #[inline]
    pub fn point(&self, i: usize, b1: f32, b2: f32) -> (Vec3, Vec3, Vec3) {
        tri_surface::point(&self.corners(i), b1, b2)
    }

    /// Triangle `i`'s unit normal by its winding (`tri_surface::winding_normal`).
    pub fn winding_normal(&self, i: usize) -> Vec3 {
        let c = self.corners(i);
        tri_surface::winding_normal(c.p(0), c.p(1), c.p(2))
    }

    /// `point`, given triangle `i`'s `winding_normal` (area lights keep them: 60 of the 143
    /// instructions of `point` on the Cornell box's light).
    #[inline(always)]
    pub fn point_with_normal(&self, i: usize, b1: f32, b2: f32, n: Vec3) -> (Vec3, Vec3, Vec3) {
        tri_surface::point_with_normal(&self.corners(i), b1, b2, n)
    }

    /// Point, normals, shading frame and uv at barycentrics (b1, b2) of triangle `i`.
    #[inline]
    pub fn surface(&self, i: usize, b1: f32, b2: f32) -> TriangleSurface {
        tri_surface::surface(&self.corners(i), b1, b2)
    }

    /// Whether every triangle's shading frame is the same at all its points (no vertex normals,
    /// no normal map: `tri_surface::is_flat`).
    pub fn is_flat(&self) -> bool {
        self.normals.is_empty() && self.normal_map.is_none()
    }

    /// The shading frame of triangle `i` of a flat mesh (`is_flat`), as `surface` gives it.
    pub fn flat_frame(&self, i: usize) -> crate::math::Frame {
        tri_surface::flat_frame(&self.corners(i))
    }

    /// `surface` of triangle `i` of a flat mesh, given its `flat_frame` (the same bits).
    #[inline(always)]
    pub fn flat_surface(
        &self,
        i: usize,
        b1: f32,
        b2: f32,
        frame: &crate::math::Frame,
    ) -> TriangleSurface {
        tri_surface::flat_surface(&self.corners(i), b1, b2, frame)
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

/// A world-space mesh's triangle: its vertex indices, its corners read from the arrays.
struct MeshCorners<'a> {
    m: &'a Mesh,
    idx: [usize; 3],
}

impl Corners for MeshCorners<'_> {
    #[inline(always)]
    fn p(&self, j: usize) -> Vec3 {
        self.m.positions[self.idx[j]]
    }
    #[inline(always)]
    fn has_normals(&self) -> bool {
        !self.m.normals.is_empty()
    }
    #[inline(always)]
    fn n(&self, j: usize) -> Vec3 {
        self.m.normals[self.idx[j]]
    }
    #[inline(always)]
    fn has_uvs(&self) -> bool {
        !self.m.uvs.is_empty()
    }
    #[inline(always)]
    fn uv(&self, j: usize) -> Vec2 {
        self.m.uvs[self.idx[j]]
    }
    #[inline(always)]
    fn normal_map(&self) -> Option<(&super::normal_map::NormalMapping, [Vec4; 3])> {
        let nm = self.m.normal_map.as_deref()?;
        let t = &nm.tangents;
        Some((nm, [t[self.idx[0]], t[self.idx[1]], t[self.idx[2]]]))
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
