//! A mesh placed in the world by a transform without being copied: one of several uses of the
//! same mesh (a RON mesh file named by several shapes, a glTF mesh under several nodes). The
//! mesh stays in object space, shared; the acceleration structure traces it once
//! (`accel::instances`) and each instance computes its hits' surface data in world space from
//! its three vertices transformed on the fly, with the same arithmetic as the world-space copy
//! the single-use path makes (`Mesh::transformed`), and the same surface code
//! (`shape::tri_surface`), so both shade alike. A normal-mapped mesh keeps its object-space
//! tangents; each hit maps its triangle's three (`normal_map::transform_tangent`).

use super::mesh::{Mesh, TriangleSurface};
use super::normal_map::{transform_tangent, NormalMapping};
use super::tri_surface::{self, Corners};
use crate::math::float::gamma;
use crate::math::Transform;
use glam::{Mat3, Vec2, Vec3, Vec4};
use std::sync::Arc;

#[derive(Clone, Debug, PartialEq)]
pub struct Instance {
    /// The shared mesh, in object space (a normal map's tangents too).
    pub mesh: Arc<Mesh>,
    pub to_world: Transform,
    /// Negate the transformed shading normals (`flip_normals`).
    pub negate_normals: bool,
    /// Reverse the winding (`flip_normals`, or a glTF node that mirrors, glTF 2.0 §3.7.4).
    pub swap_winding: bool,
}

impl Instance {
    /// The world-space copy the single-use path would make of this instance.
    pub fn flatten(&self) -> Mesh {
        let mut m = Mesh::clone(&self.mesh).transformed(&self.to_world, false);
        if self.negate_normals {
            m.normals.iter_mut().for_each(|n| *n = -*n);
        }
        if self.swap_winding {
            m.indices.iter_mut().for_each(|t| t.swap(1, 2));
        }
        m
    }

    /// Triangle `i`'s object-space vertex indices in world order (the winding swapped when
    /// `swap_winding`).
    #[inline]
    fn order(&self, i: usize) -> [usize; 3] {
        let [a, b, c] = self.mesh.indices[i].map(|v| v as usize);
        if self.swap_winding {
            [a, c, b]
        } else {
            [a, b, c]
        }
    }

    /// Triangle `i` in world space: the values `Mesh::transformed` gives its vertices.
    #[inline]
    fn corners(&self, i: usize) -> WorldCorners<'_> {
        let idx = self.order(i);
        let m = &self.mesh;
        let t = &self.to_world;
        let normal = |k: usize| {
            let n = t.normal(m.normals[k]).normalize_or_zero();
            if self.negate_normals {
                -n
            } else {
                n
            }
        };
        let (has_n, has_uv) = (!m.normals.is_empty(), !m.uvs.is_empty());
        WorldCorners {
            inst: self,
            idx,
            p: idx.map(|k| t.point(m.positions[k])),
            n: if has_n {
                idx.map(normal)
            } else {
                [Vec3::ZERO; 3]
            },
            uv: if has_uv {
                idx.map(|k| m.uvs[k])
            } else {
                [Vec2::ZERO; 3]
            },
            has_n,
            has_uv,
        }
    }

    #[inline]
    pub fn vertices(&self, i: usize) -> [Vec3; 3] {
        self.order(i)
            .map(|k| self.to_world.point(self.mesh.positions[k]))
    }

    pub fn triangle_area(&self, i: usize) -> f32 {
        let [a, b, c] = self.vertices(i);
        0.5 * (b - a).cross(c - a).length()
    }

    /// World bounds of the vertices (min, max).
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.mesh
            .positions
            .iter()
            .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &p| {
                let p = self.to_world.point(p);
                (lo.min(p), hi.max(p))
            })
    }

    /// Surface data at barycentrics (b1, b2) of the object-space triangle `i` (in the mesh's
    /// own winding, as the object-space intersection reports them).
    #[inline]
    pub fn surface(&self, i: usize, b1: f32, b2: f32) -> TriangleSurface {
        let (b1, b2) = if self.swap_winding {
            (b2, b1)
        } else {
            (b1, b2)
        };
        let mut s = tri_surface::surface(&self.corners(i), b1, b2);
        // Rays leaving this point are traced in object space: the world-to-object transform of
        // their origin adds rounding error (γ3 per component, PBR 4th ed. §6.8.4), mapped back
        // to world space, which the origin's offset must clear too.
        let (m, inv) = (&self.to_world.m, &self.to_world.inv);
        let inv_abs = Mat3::from_mat4(*inv).abs();
        let e_obj = gamma(3) * (inv_abs * s.p.abs() + inv.w_axis.truncate().abs());
        s.p_error += (1.0 + gamma(3)) * (Mat3::from_mat4(*m).abs() * e_obj);
        s
    }
}

/// An instance's triangle with its corners mapped to world space (positions, normals; uvs as
/// they are), and its object-space vertex indices for the normal map's tangents.
struct WorldCorners<'a> {
    inst: &'a Instance,
    idx: [usize; 3],
    p: [Vec3; 3],
    n: [Vec3; 3],
    uv: [Vec2; 3],
    has_n: bool,
    has_uv: bool,
}

impl Corners for WorldCorners<'_> {
    #[inline(always)]
    fn p(&self, j: usize) -> Vec3 {
        self.p[j]
    }
    #[inline(always)]
    fn has_normals(&self) -> bool {
        self.has_n
    }
    #[inline(always)]
    fn n(&self, j: usize) -> Vec3 {
        self.n[j]
    }
    #[inline(always)]
    fn has_uvs(&self) -> bool {
        self.has_uv
    }
    #[inline(always)]
    fn uv(&self, j: usize) -> Vec2 {
        self.uv[j]
    }
    #[inline(always)]
    fn normal_map(&self) -> Option<(&NormalMapping, [Vec4; 3])> {
        let nm = self.inst.mesh.normal_map.as_deref()?;
        let to_world = &self.inst.to_world;
        // As the world-space copy's tangents (`Mesh::transformed`), computed per hit.
        let mirror = to_world.flips_handedness();
        let t = |j: usize| transform_tangent(to_world, mirror, nm.tangents[self.idx[j]]);
        Some((nm, [t(0), t(1), t(2)]))
    }
}
