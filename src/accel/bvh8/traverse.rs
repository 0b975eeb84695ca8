//! The tree's traversal: a stack of nodes still to visit, nearest first when ordered, with the
//! node test compiled twice (portable SIMD, and AVX2 where the CPU has it).

use super::slab::BoxQuery;
use super::{Tree, Visit, EMPTY, LEAF, ROBUST, STACK, W};
use crate::ray::Ray;
use arrayvec::ArrayVec;

impl Tree {
    /// Visits the leaves `ray` may meet within (0, t_max], nearest first when `ORDERED`,
    /// skipping boxes beyond `t_max` (which `leaf` may shrink as it finds hits). `leaf` gets a
    /// leaf's first item and item count. Returns true if `leaf` stopped the traversal.
    #[inline(always)]
    pub fn traverse<const ORDERED: bool>(
        &self,
        ray: &Ray,
        t_max: &mut f32,
        mut leaf: impl FnMut(u32, u32, &mut f32) -> Visit,
    ) -> bool {
        self.traverse_isa::<ORDERED>(
            ray,
            t_max,
            #[inline(always)]
            |first, count, t_max, _| leaf(first, count, t_max),
        )
    }

    /// `traverse`, with `leaf` told (fourth argument, a constant once inlined) whether it runs
    /// inside the AVX2 build of the loop, where it may use AVX2 code inlined into it (the
    /// two-packet triangle test: out of line it cost a call per leaf).
    #[inline(always)]
    pub fn traverse_isa<const ORDERED: bool>(
        &self,
        ray: &Ray,
        t_max: &mut f32,
        leaf: impl FnMut(u32, u32, &mut f32, bool) -> Visit,
    ) -> bool {
        // A ray with a NaN or infinite origin or direction meets nothing: its slab distances
        // would be NaN, which the node test ignores (a ray in a slab's plane), so every lane
        // would pass, unused lanes included (whose child, EMPTY, would then be read as a leaf
        // past the end of the caller's items).
        if self.root == EMPTY || !finite(ray) {
            return false;
        }
        #[cfg(target_arch = "x86_64")]
        if self.avx2 {
            // SAFETY: `avx2` is set only where the CPU has AVX2.
            return unsafe { self.traverse_avx2::<ORDERED, _>(ray, t_max, leaf) };
        }
        self.traverse_on::<ORDERED, false, _>(ray, t_max, leaf)
    }

    /// The traversal compiled for AVX2: the node test, the loop and the caller's leaf code
    /// (inlined here) all get AVX encodings, with the same arithmetic as the portable path.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    pub(super) unsafe fn traverse_avx2<
        const ORDERED: bool,
        F: FnMut(u32, u32, &mut f32, bool) -> Visit,
    >(
        &self,
        ray: &Ray,
        t_max: &mut f32,
        leaf: F,
    ) -> bool {
        self.traverse_on::<ORDERED, true, _>(ray, t_max, leaf)
    }

    #[inline(always)]
    pub(super) fn traverse_on<
        const ORDERED: bool,
        const AVX2: bool,
        F: FnMut(u32, u32, &mut f32, bool) -> Visit,
    >(
        &self,
        ray: &Ray,
        t_max: &mut f32,
        leaf: F,
    ) -> bool {
        if self.stack_needed <= STACK {
            let mut stack = ArrayVec::<Entry, STACK>::new();
            self.traverse_with::<ORDERED, AVX2, _>(&mut stack, ray, t_max, leaf)
        } else {
            let mut stack = Vec::with_capacity(self.stack_needed);
            self.traverse_with::<ORDERED, AVX2, _>(&mut stack, ray, t_max, leaf)
        }
    }

    #[inline(always)]
    fn traverse_with<const ORDERED: bool, const AVX2: bool, S: Stack>(
        &self,
        stack: &mut S,
        ray: &Ray,
        t_max: &mut f32,
        mut leaf: impl FnMut(u32, u32, &mut f32, bool) -> Visit,
    ) -> bool {
        let q = BoxQuery::new(ray);
        let mut current = self.root;
        let mut t = [0.0f32; W];
        loop {
            if current & LEAF == 0 {
                let node = &self.nodes[current as usize];
                let mut bits = q.test::<AVX2>(node, *t_max, &mut t);
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
                // Filled with a constant (two vector stores), not the first entry (W pairs of
                // scalar stores, 0.4% of a Cornell render): only hits[..n] is read.
                let mut hits = [Entry { node: 0, t: 0.0 }; W];
                hits[0] = Entry {
                    node: node.child[a],
                    t: t[a],
                };
                let mut n = 1;
                while bits != 0 {
                    let c = bits.trailing_zeros() as usize;
                    bits &= bits - 1;
                    let e = Entry {
                        node: node.child[c],
                        t: t[c],
                    };
                    // Insertion sort by decreasing distance (a few entries).
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
                if let Visit::Stop = leaf(first, count, t_max, AVX2) {
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

/// Whether the ray's origin and direction are finite: x · 0 is ±0 for a finite x and NaN for
/// ±∞ or NaN, so the sum is zero exactly when all six are. Fewer instructions than six
/// `is_finite` tests (about 20 against 30, with one branch; each ray query runs it).
#[inline(always)]
fn finite(ray: &Ray) -> bool {
    let z = ray.o * 0.0 + ray.d * 0.0;
    z.x + z.y + z.z == 0.0
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
