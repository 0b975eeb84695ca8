//! Surface data at a point of a triangle, computed from its three corners: one definition for a
//! world-space mesh (`Mesh`, corners read straight from its arrays) and for an instance
//! (`Instance`, corners of the shared object-space mesh mapped to world space first), so an
//! instance shades exactly as its world-space copy would. Generic over how the corners are read:
//! each caller gets its own monomorphised copy, and the mesh's is the code it had on its own
//! (callgrind counts of the Cornell box are in docs/performance.md).

use super::normal_map::NormalMapping;
use crate::math::float::gamma;
use crate::math::Frame;
use glam::{Vec2, Vec3, Vec4};

/// Surface data at a point of a triangle.
pub struct TriangleSurface {
    pub p: Vec3,
    pub p_error: Vec3,
    pub ng: Vec3,
    pub frame: Frame,
    pub uv: Vec2,
}

/// A triangle's corners j = 0, 1, 2 in world space, in the triangle's winding.
pub trait Corners {
    fn p(&self, j: usize) -> Vec3;
    /// Whether the mesh has per-vertex shading normals (`n`; else flat shading).
    fn has_normals(&self) -> bool;
    fn n(&self, j: usize) -> Vec3;
    /// Whether the mesh has texture coordinates (`uv`).
    fn has_uvs(&self) -> bool;
    fn uv(&self, j: usize) -> Vec2;
    /// The mesh's normal map and the corners' world-space tangents (xyz, bitangent sign w);
    /// None for a mesh without one.
    fn normal_map(&self) -> Option<(&NormalMapping, [Vec4; 3])>;
}

/// Position, its error bound, and the unit geometric normal at barycentrics (b1, b2): what
/// emitter sampling needs, without the shading frame.
#[inline(always)]
pub fn point<C: Corners>(c: &C, b1: f32, b2: f32) -> (Vec3, Vec3, Vec3) {
    point_with_normal(c, b1, b2, winding_normal(c.p(0), c.p(1), c.p(2)))
}

/// The unit normal of the triangle p0 p1 p2 by its winding (zero if degenerate): the same
/// for every point of it, so area lights keep it per triangle (`point_with_normal`).
#[inline(always)]
pub fn winding_normal(p0: Vec3, p1: Vec3, p2: Vec3) -> Vec3 {
    (p1 - p0).cross(p2 - p0).normalize_or_zero()
}

/// `point`, given the triangle's `winding_normal` (the same bits as `point` computes).
#[inline(always)]
pub fn point_with_normal<C: Corners>(c: &C, b1: f32, b2: f32, winding: Vec3) -> (Vec3, Vec3, Vec3) {
    let (p0, p1, p2) = (c.p(0), c.p(1), c.p(2));
    let b0 = 1.0 - b1 - b2;
    // Barycentric interpolation is more accurate than o + t·d, and its error is bounded.
    let p = b0 * p0 + b1 * p1 + b2 * p2;
    let p_error = gamma(7) * ((b0 * p0).abs() + (b1 * p1).abs() + (b2 * p2).abs());
    let mut ng = winding;
    if c.has_normals() {
        // The geometric normal follows the shading normal's side, so "front" is the side
        // the vertex normals point to, whatever the winding.
        let n = b0 * c.n(0) + b1 * c.n(1) + b2 * c.n(2);
        if ng.dot(n) < 0.0 {
            ng = -ng;
        }
    }
    (p, p_error, ng)
}

/// Point, normals, shading frame and uv at barycentrics (b1, b2).
#[inline(always)]
pub fn surface<C: Corners>(c: &C, b1: f32, b2: f32) -> TriangleSurface {
    let (p, p_error, ng) = point(c, b1, b2);
    let b0 = 1.0 - b1 - b2;
    let uv = uv_at(c, b0, b1, b2);
    let dpdu = dpdu(c);
    let ns = if !c.has_normals() {
        ng
    } else {
        let n = (b0 * c.n(0) + b1 * c.n(1) + b2 * c.n(2)).normalize_or_zero();
        if n == Vec3::ZERO {
            ng
        } else {
            n
        }
    };
    let frame = match c.normal_map() {
        None => Frame::from_normal_tangent(ns, dpdu),
        Some((nm, t)) => nm.frame(t, [b0, b1, b2], ns, uv),
    };
    TriangleSurface {
        p,
        p_error,
        ng,
        frame,
        uv,
    }
}

/// The shading frame `surface` gives at every point of a flat triangle (no vertex normals, no
/// normal map: `Mesh::is_flat`), by the same operations: the winding normal, and dp/du (the
/// same for every point of a triangle).
pub fn flat_frame<C: Corners>(c: &C) -> Frame {
    debug_assert!(!c.has_normals() && c.normal_map().is_none());
    Frame::from_normal_tangent(winding_normal(c.p(0), c.p(1), c.p(2)), dpdu(c))
}

/// `surface` of a flat triangle whose frame is known (`flat_frame`): the same bits,
/// without the cross product, normalisation, dp/du and frame of each hit (about 100
/// instructions of a hit's 340 on the Cornell box).
#[inline(always)]
pub fn flat_surface<C: Corners>(c: &C, b1: f32, b2: f32, frame: &Frame) -> TriangleSurface {
    let (p, p_error, ng) = point_with_normal(c, b1, b2, frame.n);
    let uv = uv_at(c, 1.0 - b1 - b2, b1, b2);
    TriangleSurface {
        p,
        p_error,
        ng,
        frame: *frame,
        uv,
    }
}

/// Texture coordinates at barycentrics (b0, b1, b2); (b1, b2) for a mesh without them.
#[inline(always)]
fn uv_at<C: Corners>(c: &C, b0: f32, b1: f32, b2: f32) -> Vec2 {
    if !c.has_uvs() {
        Vec2::new(b1, b2)
    } else {
        b0 * c.uv(0) + b1 * c.uv(1) + b2 * c.uv(2)
    }
}

/// dp/du from the uv parameterisation, for a tangent that follows the texture (the first edge
/// without usable uvs).
#[inline(always)]
fn dpdu<C: Corners>(c: &C) -> Vec3 {
    let e1 = c.p(1) - c.p(0);
    if !c.has_uvs() {
        return e1;
    }
    let (uv0, uv1, uv2) = (c.uv(0), c.uv(1), c.uv(2));
    let e2 = c.p(2) - c.p(0);
    let (duv1, duv2) = (uv1 - uv0, uv2 - uv0);
    let det = duv1.x * duv2.y - duv1.y * duv2.x;
    if det.abs() > 1e-12 {
        (e1 * duv2.y - e2 * duv1.y) / det
    } else {
        e1
    }
}
