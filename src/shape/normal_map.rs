//! Normal mapping (glTF `normalTexture`): per-vertex tangents and a tangent-space normal map
//! perturb a mesh's shading normal. A mesh without one pays a single `None` test per hit.

use crate::math::{Frame, Transform};
use crate::texture::Grid;
use glam::{Vec2, Vec3, Vec4};
use std::sync::Arc;

/// A mesh's normal map with its tangent frames.
#[derive(Clone, Debug, PartialEq)]
pub struct NormalMapping {
    /// Per vertex: the tangent (xyz, along +u) and the bitangent sign w, with bitangent =
    /// w · (normal × tangent) (glTF's convention); in the space of the mesh's positions (world
    /// space, or object space for an instance's shared mesh, mapped at each hit).
    pub tangents: Vec<Vec4>,
    /// Tangent-space normals (x along the tangent, y along the bitangent, z along the normal),
    /// already scaled by the texture's `scale` in x and y.
    pub map: Arc<Grid<Vec3>>,
}

impl NormalMapping {
    /// The shading frame at barycentrics `b` of a triangle whose corners have world-space
    /// tangents `t` (from `tangents`), with interpolated shading normal `ns` and texture
    /// coordinates `uv`.
    #[inline(never)]
    pub fn frame(&self, t: [Vec4; 3], b: [f32; 3], ns: Vec3, uv: Vec2) -> Frame {
        let t4 = b[0] * t[0] + b[1] * t[1] + b[2] * t[2];
        let sign = if t[0].w < 0.0 { -1.0 } else { 1.0 };
        // Gram–Schmidt: the tangent made orthogonal to the interpolated normal.
        let t = (t4.truncate() - ns * ns.dot(t4.truncate())).normalize_or_zero();
        if t == Vec3::ZERO {
            return Frame::from_normal(ns);
        }
        let bt = ns.cross(t) * sign;
        let m = self.map.eval_vec3(uv);
        let n = (m.x * t + m.y * bt + m.z * ns).normalize_or_zero();
        if n == Vec3::ZERO {
            return Frame::from_normal(ns);
        }
        Frame::from_normal_tangent(n, t)
    }
}

/// Tangent `t` (xyz, bitangent sign w) mapped by `to_world`: xyz by its linear part (a tangent
/// is a difference of points, not a normal, so not by the inverse transpose), renormalised; w
/// negated where the map mirrors (`mirror`: `to_world.flips_handedness()`), since the mapped
/// bitangent L·b = −w · (n′ × t′) then (glTF 2.0 §3.7.4; MikkTSpace's bitangent sign).
#[inline]
pub fn transform_tangent(to_world: &Transform, mirror: bool, t: Vec4) -> Vec4 {
    let v = to_world.vector(t.truncate()).normalize_or_zero();
    v.extend(if mirror { -t.w } else { t.w })
}

/// MikkTSpace tangents (the `mikktspace` crate) for a mesh with normals and uvs, per vertex.
/// glTF's v runs down the image while its bitangent points up it (glTF 2.0 §3.9.3: +Y of a
/// normal texture is "up"), so v is flipped for MikkTSpace, whose bitangent follows +v. A
/// vertex shared by faces with different tangents keeps the last one (exporters split vertices
/// at uv seams, where that matters). None if the algorithm fails (degenerate uvs).
pub fn mikktspace_tangents(
    positions: &[Vec3],
    normals: &[Vec3],
    uvs: &[Vec2],
    indices: &[[u32; 3]],
) -> Option<Vec<Vec4>> {
    struct G<'a> {
        p: &'a [Vec3],
        n: &'a [Vec3],
        uv: &'a [Vec2],
        ix: &'a [[u32; 3]],
        out: Vec<Vec4>,
    }
    impl mikktspace::Geometry for G<'_> {
        fn num_faces(&self) -> usize {
            self.ix.len()
        }
        fn num_vertices_of_face(&self, _face: usize) -> usize {
            3
        }
        fn position(&self, face: usize, vert: usize) -> [f32; 3] {
            self.p[self.ix[face][vert] as usize].into()
        }
        fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
            self.n[self.ix[face][vert] as usize].into()
        }
        fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
            let uv = self.uv[self.ix[face][vert] as usize];
            [uv.x, 1.0 - uv.y]
        }
        fn set_tangent_encoded(&mut self, tangent: [f32; 4], face: usize, vert: usize) {
            self.out[self.ix[face][vert] as usize] = Vec4::from(tangent);
        }
    }
    let mut g = G {
        p: positions,
        n: normals,
        uv: uvs,
        ix: indices,
        out: vec![Vec4::ZERO; positions.len()],
    };
    mikktspace::generate_tangents(&mut g).then_some(g.out)
}
