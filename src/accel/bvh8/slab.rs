//! The ray–box slab test of one node's eight children.
//!
//! A ray with a zero direction component whose origin lies exactly in a plane of a box (an
//! orthographic camera looking along an axis at geometry on a grid, an axis-aligned shadow ray)
//! gets the slab distance (plane − o) · (1/d) = 0 · ∞ = NaN on that axis. The distances are
//! folded into the entry and exit with the NaN on the discarded side: x86's `maxps(a, b)` and
//! `minps(a, b)` return `b` when either is NaN, so each slab distance goes first and the running
//! bound (0, or `t_max`, never NaN) second, and a NaN slab leaves the bound as it was. That is
//! pbrt-v4's `Bounds3::IntersectP` (`t0 = tNear > t0 ? tNear : t0`: a NaN `tNear` compares
//! false). The ray then counts as inside the closed slab, as the watertight triangle test counts
//! a ray along an edge as a hit. Embree instead replaces |d| < 1e-18 by +1e-18 before the
//! reciprocal (`rcp_safe`/`zero_fix`), as prism did with ±1e-30: that moves the ray off the
//! plane to one side, so the box on the other side gets an exit distance of 0 and is missed,
//! with the triangle in it (docs/performance.md, "Paths in lanes", third stop).

use super::{Node, ROBUST, W};
use crate::ray::Ray;
use wide::{f32x4, CmpLe};

/// Per-ray constants of the slab test.
pub(super) struct BoxQuery {
    o: [f32; 3],
    /// 1/d per axis: ±inf for a zero component (the slab distances are then ±inf, or NaN in
    /// the slab's planes, which the test discards).
    inv: [f32; 3],
    /// Index into `Node::b` of the plane the ray enters first on each axis (the far one is
    /// `near ^ 1`).
    near: [usize; 3],
}

/// `max(slab, bound)` that keeps `bound` where `slab` is NaN (`bound` is never NaN): `maxps`
/// on x86 (its NaN rule, the AVX2 path's), the NaN-ignoring max elsewhere.
#[inline(always)]
fn enter(slab: f32x4, bound: f32x4) -> f32x4 {
    if cfg!(target_feature = "sse") {
        slab.fast_max(bound)
    } else {
        slab.max(bound)
    }
}

/// `min(slab, bound)` that keeps `bound` where `slab` is NaN, as `enter`.
#[inline(always)]
fn exit(slab: f32x4, bound: f32x4) -> f32x4 {
    if cfg!(target_feature = "sse") {
        slab.fast_min(bound)
    } else {
        slab.min(bound)
    }
}

impl BoxQuery {
    #[inline(always)]
    pub(super) fn new(ray: &Ray) -> Self {
        let (ix, iy, iz) = (1.0 / ray.d.x, 1.0 / ray.d.y, 1.0 / ray.d.z);
        Self {
            o: ray.o.to_array(),
            inv: [ix, iy, iz],
            near: [
                (ix < 0.0) as usize,
                2 + (iy < 0.0) as usize,
                4 + (iz < 0.0) as usize,
            ],
        }
    }

    /// Which of the node's boxes the ray meets within [0, t_max] (bit per lane); `t` gets the
    /// distance at which it enters each. Per lane: near = max(slab entries, 0), far =
    /// min(slab exits, t_max) · ROBUST, met if near <= far, a NaN slab distance ignored (module
    /// doc); both paths do exactly this, in this order.
    #[inline(always)]
    pub(super) fn test<const AVX2: bool>(&self, node: &Node, t_max: f32, t: &mut [f32; W]) -> u32 {
        #[cfg(target_arch = "x86_64")]
        if AVX2 {
            // SAFETY: `AVX2` is true only inside `traverse_avx2`, run only on AVX2 CPUs.
            return unsafe { self.test_avx2(node, t_max, t) };
        }
        let mut mask = 0;
        for half in 0..2 {
            let slab = |axis: usize| {
                let n = self.near[axis];
                let (o, inv) = (f32x4::splat(self.o[axis]), f32x4::splat(self.inv[axis]));
                ((node.b[n][half] - o) * inv, (node.b[n ^ 1][half] - o) * inv)
            };
            let (x0, x1) = slab(0);
            let (y0, y1) = slab(1);
            let (z0, z1) = slab(2);
            let t_near = enter(x0, enter(y0, enter(z0, f32x4::ZERO)));
            let t_far = exit(x1, exit(y1, exit(z1, f32x4::splat(t_max)))) * ROBUST;
            t[4 * half..4 * half + 4].copy_from_slice(t_near.as_array_ref());
            mask |= (t_near.cmp_le(t_far).move_mask() as u32 & 0xf) << (4 * half);
        }
        mask
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn test_avx2(&self, node: &Node, t_max: f32, t: &mut [f32; W]) -> u32 {
        use std::arch::x86_64::*;
        let b = node.b.as_ptr() as *const f32;
        // SAFETY: `Node` is 32-byte aligned and `b` starts it; plane p is the 8 floats at 8p.
        let load = |p: usize| unsafe { _mm256_load_ps(b.add(8 * p)) };
        let slab = |axis: usize| {
            let n = self.near[axis];
            let (o, inv) = (_mm256_set1_ps(self.o[axis]), _mm256_set1_ps(self.inv[axis]));
            (
                _mm256_mul_ps(_mm256_sub_ps(load(n), o), inv),
                _mm256_mul_ps(_mm256_sub_ps(load(n ^ 1), o), inv),
            )
        };
        let (x0, x1) = slab(0);
        let (y0, y1) = slab(1);
        let (z0, z1) = slab(2);
        // The slab distance first, the bound second: `vmaxps`/`vminps` return the second
        // operand when either is NaN (module doc).
        let t_near = _mm256_max_ps(
            x0,
            _mm256_max_ps(y0, _mm256_max_ps(z0, _mm256_setzero_ps())),
        );
        let t_far = _mm256_mul_ps(
            _mm256_min_ps(
                x1,
                _mm256_min_ps(y1, _mm256_min_ps(z1, _mm256_set1_ps(t_max))),
            ),
            _mm256_set1_ps(ROBUST),
        );
        // SAFETY: `t` holds 8 floats.
        unsafe { _mm256_storeu_ps(t.as_mut_ptr(), t_near) };
        _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(t_near, t_far)) as u32
    }
}
