//! An 8-wide BVH: each node holds its eight children's boxes as SIMD lanes (structure of arrays),
//! so one ray tests all eight with a handful of AVX instructions (or, on CPUs without AVX2, two
//! 4-wide SSE halves computing the same numbers). obvhs builds a binary BVH (PLOC with
//! reinsertion and SAH leaf collapsing), which is collapsed here into 8-wide nodes.
//!
//! Why not obvhs' own traversal: its 8-wide compressed nodes (CWBVH) are made for GPUs; on this
//! project's CPUs they traced 0.3–0.4× as many rays per second as Embree (docs/performance.md),
//! while uncompressed wide nodes with SIMD box and triangle tests are what fast CPU ray tracers
//! use. Why 8 wide rather than 4: half the tree depth for the same instructions per node test on
//! AVX2: diffuse-bounce rays +27% (20k triangles) and +28% (1M) per second over the 4-wide tree
//! this replaced, +18% with the SSE path alone (docs/performance.md). Why hand-written AVX
//! intrinsics: `wide`'s 8-lane type picks AVX at compile time only, and prism's release builds
//! target baseline x86-64 so they run on every machine of a cluster; the AVX2 path is chosen at
//! run time. Both paths compute each lane with the same IEEE operations, so hits, traversal
//! order and images are identical on every CPU. The tree knows nothing of primitives: leaves are
//! ranges of the caller's items.

mod slab;
mod traverse;

use crate::math::float::gamma;
use arrayvec::ArrayVec;
use glam::Vec3;
use obvhs::bvh2::builder::build_bvh2;
use obvhs::{Boundable, BvhBuildParams};
use std::time::Duration;
use wide::f32x4;

/// Children per node.
const W: usize = 8;
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
const STACK: usize = 128;

/// One node: per axis, the children's low and high bounds, `[lo_x, hi_x, lo_y, hi_y, lo_z,
/// hi_z]`, each eight lanes stored as two 4-lane halves (one 32-byte AVX load, or two SSE ones).
/// Unused lanes hold an empty box (lo = +inf, hi = -inf) that no ray enters.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
struct Node {
    b: [[f32x4; 2]; 6],
    child: [u32; W],
}

impl Node {
    fn unused() -> Node {
        let (inf, neg) = (
            [f32x4::splat(f32::INFINITY); 2],
            [f32x4::splat(f32::NEG_INFINITY); 2],
        );
        Node {
            b: [inf, neg, inf, neg, inf, neg],
            child: [EMPTY; W],
        }
    }

    fn set_child(&mut self, lane: usize, lo: Vec3, hi: Vec3, child: u32) {
        let (half, l) = (lane / 4, lane % 4);
        for axis in 0..3 {
            self.b[2 * axis][half].as_array_mut()[l] = lo[axis];
            self.b[2 * axis + 1][half].as_array_mut()[l] = hi[axis];
        }
        self.child[lane] = child;
    }
}

pub struct Tree {
    nodes: Vec<Node>,
    root: u32,
    /// Largest number of entries a traversal can have on its stack (7 per level).
    stack_needed: usize,
    /// Whether this CPU runs the AVX2 node test (checked once, at build).
    #[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
    pub(super) avx2: bool,
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

#[cfg(target_arch = "x86_64")]
fn has_avx2() -> bool {
    std::is_x86_feature_detected!("avx2")
}

#[cfg(not(target_arch = "x86_64"))]
fn has_avx2() -> bool {
    false
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
        let avx2 = has_avx2();
        if boxes.is_empty() {
            return Tree {
                nodes: Vec::new(),
                root: EMPTY,
                stack_needed: 0,
                avx2,
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
                avx2,
                lo,
                hi,
            };
        }
        // Each wide node takes a binary node's children, then repeatedly opens the inner child
        // with the largest surface area (the one a ray most likely enters) until it has eight.
        let mut nodes = vec![Node::unused()];
        let mut work = vec![(0u32, 0usize, 1usize)]; // (binary node, wide node, depth)
        let mut depth_max = 1;
        while let Some((i2, slot, depth)) = work.pop() {
            depth_max = depth_max.max(depth);
            let first = n2[i2 as usize].first_index;
            let mut kids: ArrayVec<u32, W> = [first, first + 1].into_iter().collect();
            while kids.len() < W {
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
            stack_needed: (W - 1) * depth_max + 1,
            avx2,
            lo,
            hi,
        }
    }
}

impl Tree {
    /// Each leaf's first item and item count, in node order (a test hook: `Bvh::triangle_leaves`).
    pub fn leaves(&self) -> Vec<(u32, u32)> {
        let decode = |c: u32| ((c & !LEAF) >> 3, (c & 7) + 1);
        if self.root == EMPTY {
            return Vec::new();
        }
        if self.root & LEAF != 0 {
            return vec![decode(self.root)];
        }
        let nodes = self.nodes.iter().flat_map(|n| n.child);
        nodes
            .filter(|&c| c != EMPTY && c & LEAF != 0)
            .map(decode)
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ray::Ray;
    use obvhs::aabb::Aabb;

    struct B(Aabb);
    impl Boundable for B {
        fn aabb(&self) -> Aabb {
            self.0
        }
    }

    /// The AVX2 and the portable node tests must give the same traversal: the same leaves in the
    /// same order, with the same `t_max` updates, so images do not depend on the CPU. Random
    /// boxes (some flat, some nested), random rays (some with zero direction components, some
    /// starting inside boxes), leaves that shrink `t_max` as hits would.
    #[test]
    #[cfg_attr(
        not(prism_host_avx2),
        ignore = "this CPU lacks AVX2: only the portable path runs"
    )]
    fn avx2_and_portable_traversals_agree() {
        assert!(
            has_avx2(),
            "built on a CPU with AVX2, run on one without: rebuild here"
        );
        let mut state = 7u32;
        let mut next = || {
            state = state.wrapping_mul(747796405).wrapping_add(2891336453);
            (state >> 8) as f32 / (1u32 << 24) as f32
        };
        let boxes: Vec<B> = (0..3000)
            .map(|i| {
                let c = Vec3::new(next(), next(), next()) * 20.0 - 10.0;
                let mut e = Vec3::new(next(), next(), next()) * if i % 10 == 0 { 6.0 } else { 0.5 };
                if i % 7 == 0 {
                    e.y = 0.0; // flat, like an axis-aligned quad
                }
                B(Aabb::new((c - e).into(), (c + e).into()))
            })
            .collect();
        let mut leaves = Vec::new();
        let tree = Tree::build(&boxes, 4, |prims| {
            leaves.push(prims.to_vec());
            (leaves.len() as u32 - 1, 1)
        });
        let mut visited = 0usize;
        for i in 0..4000 {
            let o = Vec3::new(next(), next(), next()) * 30.0 - 15.0;
            let mut d = Vec3::new(next(), next(), next()) * 2.0 - 1.0;
            if i % 5 == 0 {
                d.x = 0.0;
            }
            if i % 11 == 0 {
                d.z = -0.0;
            }
            if d.length_squared() == 0.0 {
                continue;
            }
            let ray = Ray::new(o, d.normalize());
            // A leaf "hit" shrinks t_max to a value fixed by the leaf, so both runs see the same.
            let run = |avx2: bool, ordered: bool| {
                let mut seq = Vec::new();
                let mut t_max = 40.0f32;
                let leaf = |first: u32, _count: u32, t: &mut f32, _avx2: bool| {
                    seq.push((first, t.to_bits()));
                    if first % 3 == 0 {
                        *t = t.min(5.0 + (first % 17) as f32);
                    }
                    Visit::Continue
                };
                let stopped = match (avx2, ordered) {
                    // SAFETY: checked above that the CPU has AVX2.
                    (true, true) => unsafe {
                        tree.traverse_avx2::<true, _>(&ray, &mut t_max, leaf)
                    },
                    (true, false) => unsafe {
                        tree.traverse_avx2::<false, _>(&ray, &mut t_max, leaf)
                    },
                    (false, true) => tree.traverse_on::<true, false, _>(&ray, &mut t_max, leaf),
                    (false, false) => tree.traverse_on::<false, false, _>(&ray, &mut t_max, leaf),
                };
                assert!(!stopped);
                (seq, t_max.to_bits())
            };
            for ordered in [true, false] {
                let (a, b) = (run(true, ordered), run(false, ordered));
                assert_eq!(a, b, "ray {i} ({ray:?}), ordered {ordered}");
                visited += a.0.len();
            }
        }
        assert!(
            visited > 4000,
            "the rays should meet leaves ({visited} visits)"
        );
    }
}
