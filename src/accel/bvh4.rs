//! A 4-wide BVH: each node holds its four children's boxes as SIMD lanes (structure of arrays),
//! so one ray tests all four with a handful of instructions. obvhs builds a binary BVH (PLOC with
//! reinsertion and SAH leaf collapsing), which is collapsed here into 4-wide nodes.
//!
//! Why not obvhs' own traversal: its 8-wide compressed nodes (CWBVH) are made for GPUs; on this
//! project's CPUs they traced 0.3–0.4× as many rays per second as Embree (docs/performance.md),
//! while uncompressed 4-wide nodes with SIMD box and triangle tests are what fast CPU ray tracers
//! use. The tree here knows nothing of primitives: leaves are ranges of the caller's items.

use crate::math::float::gamma;
use crate::ray::Ray;
use arrayvec::ArrayVec;
use glam::Vec3;
use obvhs::bvh2::builder::build_bvh2;
use obvhs::{Boundable, BvhBuildParams};
use std::time::Duration;
use wide::{f32x4, CmpLe};

/// A child reference: a node index, or `LEAF | first << 3 | (count - 1)` for a leaf of `count`
/// (1 to 8) consecutive caller items starting at `first`.
const LEAF: u32 = 1 << 31;
/// The root of a tree over nothing.
const EMPTY: u32 = u32::MAX;
/// Most items one leaf may hold (the 3 count bits).
pub const MAX_LEAF_ITEMS: usize = 8;

/// Slab test slack: box distances computed in floating point may be short of the true ones by
/// this factor, so the far distance is stretched by it and no box a ray truly meets is missed
/// (Ize 2013; PBR 4th ed. §6.8.2).
const ROBUST: f32 = 1.0 + 2.0 * gamma(3);

/// Traversal stack entries kept on the stack; deeper trees (degenerate input) use a heap stack.
const STACK: usize = 96;

#[derive(Clone, Copy, Debug)]
#[repr(C)]
struct Node {
    /// Per axis, the children's low and high bounds: `[lo_x, hi_x, lo_y, hi_y, lo_z, hi_z]`.
    /// Unused lanes hold an empty box (lo = +inf, hi = -inf) that no ray enters.
    b: [f32x4; 6],
    child: [u32; 4],
}

impl Node {
    fn unused() -> Node {
        let (inf, neg) = (f32x4::splat(f32::INFINITY), f32x4::splat(f32::NEG_INFINITY));
        Node {
            b: [inf, neg, inf, neg, inf, neg],
            child: [EMPTY; 4],
        }
    }

    fn set_child(&mut self, lane: usize, lo: Vec3, hi: Vec3, child: u32) {
        for axis in 0..3 {
            self.b[2 * axis].as_array_mut()[lane] = lo[axis];
            self.b[2 * axis + 1].as_array_mut()[lane] = hi[axis];
        }
        self.child[lane] = child;
    }
}

pub struct Tree {
    nodes: Vec<Node>,
    root: u32,
    /// Largest number of entries a traversal can have on its stack (3 per level).
    stack_needed: usize,
    /// Bounds of everything in the tree (inverted for an empty tree).
    pub lo: Vec3,
    pub hi: Vec3,
}

/// What a leaf callback tells the traversal.
pub enum Visit {
    Continue,
    /// Stop: an occlusion query found a blocker.
    Stop,
}

impl Tree {
    /// Builds the tree over `boxes`. `pack_leaf` receives each leaf's primitives (indices into
    /// `boxes`, at most `max_leaf_prims`), stores them in the caller's leaf storage and returns
    /// the first item and the item count (1 to `MAX_LEAF_ITEMS`) it used for them.
    pub fn build<B: Boundable>(
        boxes: &[B],
        max_leaf_prims: u32,
        mut pack_leaf: impl FnMut(&[u32]) -> (u32, u32),
    ) -> Tree {
        if boxes.is_empty() {
            return Tree {
                nodes: Vec::new(),
                root: EMPTY,
                stack_needed: 0,
                lo: Vec3::INFINITY,
                hi: Vec3::NEG_INFINITY,
            };
        }
        // obvhs' `slow_build` preset: about twice `medium_build`'s build time (1.8 s against
        // 1.0 s for a million triangles on 2 cores) for 9-14% more rays per second.
        let params = BvhBuildParams {
            max_prims_per_leaf: max_leaf_prims,
            ..BvhBuildParams::slow_build()
        };
        let bvh2 = build_bvh2(boxes, params, &mut Duration::default());
        let n2 = &bvh2.nodes;
        let mut leaf = |i: u32| {
            let n = &n2[i as usize];
            let first = n.first_index as usize;
            let (item, count) =
                pack_leaf(&bvh2.primitive_indices[first..first + n.prim_count as usize]);
            assert!(
                (1..=MAX_LEAF_ITEMS as u32).contains(&count) && item < 1 << 28,
                "BVH leaf out of range"
            );
            LEAF | item << 3 | (count - 1)
        };
        let root_box = n2[0].aabb();
        let (lo, hi) = (Vec3::from(root_box.min), Vec3::from(root_box.max));
        if n2[0].is_leaf() {
            return Tree {
                nodes: Vec::new(),
                root: leaf(0),
                stack_needed: 0,
                lo,
                hi,
            };
        }
        // Each 4-wide node takes a binary node's children, then repeatedly opens the inner child
        // with the largest surface area (the one a ray most likely enters) until it has four.
        let mut nodes = vec![Node::unused()];
        let mut work = vec![(0u32, 0usize, 1usize)]; // (binary node, 4-wide node, depth)
        let mut depth_max = 1;
        while let Some((i2, slot, depth)) = work.pop() {
            depth_max = depth_max.max(depth);
            let first = n2[i2 as usize].first_index;
            let mut kids: ArrayVec<u32, 4> = [first, first + 1].into_iter().collect();
            while kids.len() < 4 {
                let open = (0..kids.len())
                    .filter(|&k| !n2[kids[k] as usize].is_leaf())
                    .max_by(|&a, &b| {
                        let area = |k: usize| n2[kids[k] as usize].aabb().half_area();
                        area(a).total_cmp(&area(b))
                    });
                let Some(k) = open else { break };
                let c = n2[kids.swap_remove(k) as usize].first_index;
                kids.push(c);
                kids.push(c + 1);
            }
            for (lane, &k) in kids.iter().enumerate() {
                let n = &n2[k as usize];
                let child = if n.is_leaf() {
                    leaf(k)
                } else {
                    nodes.push(Node::unused());
                    work.push((k, nodes.len() - 1, depth + 1));
                    (nodes.len() - 1) as u32
                };
                let b = n.aabb();
                nodes[slot].set_child(lane, b.min.into(), b.max.into(), child);
            }
        }
        Tree {
            nodes,
            root: 0,
            stack_needed: 3 * depth_max + 1,
            lo,
            hi,
        }
    }

    /// Visits the leaves `ray` may meet within (0, t_max], nearest first when `ORDERED`,
    /// skipping boxes beyond `t_max` (which `leaf` may shrink as it finds hits). `leaf` gets a
    /// leaf's first item and item count. Returns true if `leaf` stopped the traversal.
    #[inline(always)]
    pub fn traverse<const ORDERED: bool>(
        &self,
        ray: &Ray,
        t_max: &mut f32,
        leaf: impl FnMut(u32, u32, &mut f32) -> Visit,
    ) -> bool {
        if self.root == EMPTY {
            return false;
        }
        if self.stack_needed <= STACK {
            let mut stack = ArrayVec::<Entry, STACK>::new();
            self.traverse_with::<ORDERED, _>(&mut stack, ray, t_max, leaf)
        } else {
            let mut stack = Vec::with_capacity(self.stack_needed);
            self.traverse_with::<ORDERED, _>(&mut stack, ray, t_max, leaf)
        }
    }

    #[inline(always)]
    fn traverse_with<const ORDERED: bool, S: Stack>(
        &self,
        stack: &mut S,
        ray: &Ray,
        t_max: &mut f32,
        mut leaf: impl FnMut(u32, u32, &mut f32) -> Visit,
    ) -> bool {
        let q = BoxQuery::new(ray);
        let mut current = self.root;
        loop {
            if current & LEAF == 0 {
                let node = &self.nodes[current as usize];
                let (mask, t_near) = q.test(node, *t_max);
                let t = t_near.as_array_ref();
                let mut bits = mask;
                if bits == 0 {
                    match pop(stack, *t_max) {
                        Some(next) => current = next,
                        None => return false,
                    }
                    continue;
                }
                let a = bits.trailing_zeros() as usize;
                bits &= bits - 1;
                if bits == 0 {
                    current = node.child[a];
                    continue;
                }
                if !ORDERED {
                    current = node.child[a];
                    while bits != 0 {
                        let c = bits.trailing_zeros() as usize;
                        bits &= bits - 1;
                        stack.push(Entry {
                            node: node.child[c],
                            t: t[c],
                        });
                    }
                    continue;
                }
                // Two or more children: push them farthest first so the nearest pops first;
                // the nearest of all is visited now.
                let mut hits = [Entry {
                    node: node.child[a],
                    t: t[a],
                }; 4];
                let mut n = 1;
                while bits != 0 {
                    let c = bits.trailing_zeros() as usize;
                    bits &= bits - 1;
                    let e = Entry {
                        node: node.child[c],
                        t: t[c],
                    };
                    // Insertion sort by decreasing distance (at most four entries).
                    let mut i = n;
                    while i > 0 && hits[i - 1].t < e.t {
                        hits[i] = hits[i - 1];
                        i -= 1;
                    }
                    hits[i] = e;
                    n += 1;
                }
                let nearest = hits[n - 1];
                for &e in &hits[..n - 1] {
                    stack.push(e);
                }
                current = nearest.node;
            } else {
                let first = (current & !LEAF) >> 3;
                let count = (current & 7) + 1;
                if let Visit::Stop = leaf(first, count, t_max) {
                    return true;
                }
                match pop(stack, *t_max) {
                    Some(next) => current = next,
                    None => return false,
                }
            }
        }
    }
}

/// A node waiting on the traversal stack, with the distance at which the ray enters its box.
#[derive(Clone, Copy, Debug)]
struct Entry {
    node: u32,
    t: f32,
}

/// The traversal stack: fixed-size for trees of normal depth, on the heap beyond.
trait Stack {
    fn push(&mut self, e: Entry);
    fn pop(&mut self) -> Option<Entry>;
}

impl Stack for ArrayVec<Entry, STACK> {
    #[inline(always)]
    fn push(&mut self, e: Entry) {
        ArrayVec::push(self, e)
    }
    #[inline(always)]
    fn pop(&mut self) -> Option<Entry> {
        ArrayVec::pop(self)
    }
}

impl Stack for Vec<Entry> {
    #[inline(always)]
    fn push(&mut self, e: Entry) {
        Vec::push(self, e)
    }
    #[inline(always)]
    fn pop(&mut self) -> Option<Entry> {
        Vec::pop(self)
    }
}

/// The next node on the stack whose box the ray enters before `t_max`.
#[inline(always)]
fn pop(stack: &mut impl Stack, t_max: f32) -> Option<u32> {
    while let Some(e) = stack.pop() {
        if e.t <= t_max * ROBUST {
            return Some(e.node);
        }
    }
    None
}

/// Per-ray constants of the 4-wide slab test.
struct BoxQuery {
    o: [f32x4; 3],
    inv: [f32x4; 3],
    /// Index into `Node::b` of the plane the ray enters first on each axis (the far one is
    /// `near ^ 1`).
    near: [usize; 3],
}

impl BoxQuery {
    #[inline(always)]
    fn new(ray: &Ray) -> Self {
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
            o: [
                f32x4::splat(ray.o.x),
                f32x4::splat(ray.o.y),
                f32x4::splat(ray.o.z),
            ],
            inv: [f32x4::splat(ix), f32x4::splat(iy), f32x4::splat(iz)],
            near: [
                (ix < 0.0) as usize,
                2 + (iy < 0.0) as usize,
                4 + (iz < 0.0) as usize,
            ],
        }
    }

    /// Which of the node's four boxes the ray meets within [0, t_max] (bit per lane), and the
    /// distance at which it enters each.
    #[inline(always)]
    fn test(&self, node: &Node, t_max: f32) -> (u32, f32x4) {
        let slab = |axis: usize| {
            let n = self.near[axis];
            (
                (node.b[n] - self.o[axis]) * self.inv[axis],
                (node.b[n ^ 1] - self.o[axis]) * self.inv[axis],
            )
        };
        let (x0, x1) = slab(0);
        let (y0, y1) = slab(1);
        let (z0, z1) = slab(2);
        let t_near = x0.fast_max(y0).fast_max(z0.fast_max(f32x4::ZERO));
        let t_far = x1.fast_min(y1).fast_min(z1.fast_min(f32x4::splat(t_max))) * ROBUST;
        let mask = t_near.cmp_le(t_far).move_mask() as u32 & 0xf;
        (mask, t_near)
    }
}
