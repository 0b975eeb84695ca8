//! The ray–box slab test of one node's eight children.

use super::{Node, ROBUST, W};
use crate::ray::Ray;
use wide::{f32x4, CmpLe};

/// Per-ray constants of the slab test.
pub(super) struct BoxQuery {
    o: [f32; 3],
    inv: [f32; 3],
    /// Index into `Node::b` of the plane the ray enters first on each axis (the far one is
    /// `near ^ 1`).
    near: [usize; 3],
}

impl BoxQuery {
    #[inline(always)]
    pub(super) fn new(ray: &Ray) -> Self {
        // A zero direction component becomes a tiny one of the same sign, so the slab distances
        // are ±huge (never 0 · inf = NaN) and a ray in a slab's plane still counts as inside.
        let inv = |d: f32| {
            let d = if d.abs() < 1e-30 {
                1e-30f32.copysign(d)
            } else {
                d
            };
            1.0 / d
        };
        let (ix, iy, iz) = (inv(ray.d.x), inv(ray.d.y), inv(ray.d.z));
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
    /// min(slab exits, t_max) · ROBUST, met if near <= far; both paths do exactly this.
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
            let t_near = x0.fast_max(y0).fast_max(z0.fast_max(f32x4::ZERO));
            let t_far = x1.fast_min(y1).fast_min(z1.fast_min(f32x4::splat(t_max))) * ROBUST;
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
        let t_near = _mm256_max_ps(
            _mm256_max_ps(x0, y0),
            _mm256_max_ps(z0, _mm256_setzero_ps()),
        );
        let t_far = _mm256_mul_ps(
            _mm256_min_ps(
                _mm256_min_ps(x1, y1),
                _mm256_min_ps(z1, _mm256_set1_ps(t_max)),
            ),
            _mm256_set1_ps(ROBUST),
        );
        // SAFETY: `t` holds 8 floats.
        unsafe { _mm256_storeu_ps(t.as_mut_ptr(), t_near) };
        _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(t_near, t_far)) as u32
    }
}
