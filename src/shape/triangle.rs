//! Watertight ray/triangle intersection (Woop, Benthin & Wald, JCGT 2013): rays that hit a shared
//! edge or vertex hit at least one of the triangles, so meshes have no cracks for light to leak.

use crate::math::float::gamma;
use crate::ray::Ray;
use glam::Vec3;
use wide::f32x4;

// The 4-lane test (`Triangle4`) shares this file's arithmetic; it is a child module so that it
// reads `RayShear`'s fields.
#[path = "triangle_packet.rs"]
mod packet;
pub use packet::{Hits4, Hits8, Triangle4};

/// Per-ray constants of the watertight test: the axis permutation that makes the ray's largest
/// direction component z, the ray origin in that order, and the shear that aligns the ray with
/// z. The packet tests (`Triangle4`) read it as it is, splatting each constant where they use
/// it: a separate 4-lane copy cost about 40 instructions per ray query to build (Cornell box
/// profile, docs/performance.md "Fifth stop"), more than the broadcasts it saves.
#[derive(Clone, Copy, Debug)]
pub struct RayShear {
    /// The ray origin, permuted: `o[i]` is its `k[i]` component.
    o: [f32; 3],
    /// Axes (kx, ky, kz), as indices the compiler knows are below 3 (no bounds checks).
    k: [Axis; 3],
    sx: f32,
    sy: f32,
    sz: f32,
}

/// A coordinate axis, as an index the compiler knows is below 3: `v[3 * vertex + axis]` then
/// needs no bounds check (with a `usize` axis those were 18 of the ~150 instructions of each
/// packet test in a Cornell-box profile).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
enum Axis {
    X,
    Y,
    Z,
}

impl RayShear {
    #[inline]
    pub fn new(ray: &Ray) -> Self {
        use Axis::{X, Y, Z};
        let a = ray.d.abs();
        // The largest component, as the nested comparisons (x over y, then the winner over
        // z; ties go to the later axis) but from flags, so that a diffuse bounce's random
        // direction costs no mispredicted branch.
        let x_over_y = a.x > a.y;
        let x_wins = x_over_y & (a.x > a.z);
        let y_wins = !x_over_y & (a.y > a.z);
        let kz_i = 2 - 2 * x_wins as usize - y_wins as usize;
        let (d, o) = (ray.d.to_array(), ray.o.to_array());
        // (kz + 1) % 3 and (kz + 2) % 3, swapped for a negative d[kz] (winding preserved).
        const PERM: [[Axis; 3]; 6] = [
            [Y, Z, X],
            [Z, X, Y],
            [X, Y, Z],
            [Z, Y, X],
            [X, Z, Y],
            [Y, X, Z],
        ];
        let [kx, ky, kz] = PERM[kz_i + 3 * (d[kz_i] < 0.0) as usize];
        let sz = 1.0 / d[kz as usize];
        Self {
            o: [o[kx as usize], o[ky as usize], o[kz as usize]],
            k: [kx, ky, kz],
            sx: d[kx as usize] * sz,
            sy: d[ky as usize] * sz,
            sz,
        }
    }

    /// A vertex relative to the ray origin, permuted and sheared: (x, y) in the ray's frame,
    /// and the unsheared z (sheared later, only for triangles the ray passes through).
    #[inline(always)]
    fn project(&self, v: Vec3) -> (f32, f32, f32) {
        let p = v.to_array();
        let [kx, ky, kz] = self.k;
        let (x, y, z) = (
            p[kx as usize] - self.o[0],
            p[ky as usize] - self.o[1],
            p[kz as usize] - self.o[2],
        );
        (x - self.sx * z, y - self.sy * z, z)
    }
}

/// A hit: distance and barycentrics (b1, b2) of vertices 1 and 2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriHit {
    pub t: f32,
    pub b1: f32,
    pub b2: f32,
}

#[inline]
pub fn intersect(s: &RayShear, t_max: f32, v: &[Vec3; 3]) -> Option<TriHit> {
    let (ax, ay, az) = s.project(v[0]);
    let (bx, by, bz) = s.project(v[1]);
    let (cx, cy, cz) = s.project(v[2]);
    let mut u = cx * by - cy * bx;
    let mut w_ = ax * cy - ay * cx;
    let mut w = bx * ay - by * ax;
    // Exactly zero edge functions are ambiguous in f32: redo them in f64 (rare).
    if u == 0.0 || w_ == 0.0 || w == 0.0 {
        u = (cx as f64 * by as f64 - cy as f64 * bx as f64) as f32;
        w_ = (ax as f64 * cy as f64 - ay as f64 * cx as f64) as f32;
        w = (bx as f64 * ay as f64 - by as f64 * ax as f64) as f32;
    }
    if (u < 0.0 || w_ < 0.0 || w < 0.0) && (u > 0.0 || w_ > 0.0 || w > 0.0) {
        return None;
    }
    let det = u + w_ + w;
    if det == 0.0 {
        return None;
    }
    let (az, bz, cz) = (s.sz * az, s.sz * bz, s.sz * cz);
    let t_scaled = u * az + w_ * bz + w * cz;
    // t must lie in (0, t_max); compare before dividing, with det's sign folded in.
    let ts = t_scaled * det.signum();
    if ts <= 0.0 || ts >= t_max * det.abs() {
        return None;
    }
    let inv = 1.0 / det;
    let t = t_scaled * inv;
    if t.is_nan() || t <= 0.0 {
        return None;
    }
    // A t this close to 0 may be rounding error rather than a hit: a ray leaving a large,
    // slightly non-planar or rotated surface would otherwise re-hit it (shadow acne). Reject t
    // unless it exceeds a conservative bound on its own error, propagated through the shear,
    // the edge functions and the scaled depths (the error analysis of Pharr, Jakob & Humphreys,
    // PBR 4th ed., §6.8.6). Only runs for hits, and only costs arithmetic.
    if t < near_hit_error(ax, ay, bx, by, cx, cy, [az, bz, cz], [u, w_, w], inv) {
        return None;
    }
    Some(TriHit {
        t,
        b1: w_ * inv,
        b2: w * inv,
    })
}

/// Arithmetic shared by the scalar and the 4-lane triangle tests, so both round identically.
trait Lane: Copy + std::ops::Add<Output = Self> + std::ops::Mul<Output = Self> {
    fn splat(x: f32) -> Self;
    fn abs(self) -> Self;
    fn max(self, o: Self) -> Self;
}

impl Lane for f32 {
    #[inline(always)]
    fn splat(x: f32) -> Self {
        x
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f32::abs(self)
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        f32::max(self, o)
    }
}

impl Lane for f32x4 {
    #[inline(always)]
    fn splat(x: f32) -> Self {
        f32x4::splat(x)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f32x4::abs(self)
    }
    // Operands are never NaN where the result is used (NaN lanes fail earlier tests).
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        self.fast_max(o)
    }
}

/// Upper bound on the rounding error of a hit's t (see `intersect`).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn near_hit_error<T: Lane>(
    ax: T,
    ay: T,
    bx: T,
    by: T,
    cx: T,
    cy: T,
    z: [T; 3],
    e: [T; 3],
    inv_det: T,
) -> T {
    let max_z = z[0].abs().max(z[1].abs()).max(z[2].abs());
    let max_x = ax.abs().max(bx.abs()).max(cx.abs());
    let max_y = ay.abs().max(by.abs()).max(cy.abs());
    let max_e = e[0].abs().max(e[1].abs()).max(e[2].abs());
    let g = |n: i32| T::splat(gamma(n));
    let dz = g(3) * max_z;
    let dx = g(5) * (max_x + max_z);
    let dy = g(5) * (max_y + max_z);
    let de = T::splat(2.0) * (g(2) * max_x * max_y + dy * max_x + dx * max_y);
    T::splat(3.0) * (g(3) * max_e * max_z + de * max_z + dz * max_e) * inv_det.abs()
}

#[cfg(test)]
#[path = "triangle_tests.rs"]
mod tests;
