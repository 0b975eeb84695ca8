//! prism's own acceleration structure: two 8-wide BVHs (`bvh8`), one over triangles stored four
//! to a SIMD packet (`Triangle4`), one over the analytic shapes (spheres, disks). A scene of
//! triangles only never touches the second, and the reverse.

use super::bvh8::{Tree, Visit, MAX_LEAF_ITEMS};
use super::{Hit, Prim};
use crate::ray::Ray;
use crate::shape::triangle::{self, RayShear, Triangle4};
use crate::shape::{PrimGeom, PrimHit};
use glam::Vec3;
use obvhs::aabb::Aabb;
use obvhs::Boundable;

/// Most triangles in one leaf: two packets. obvhs' SAH collapse decides how many a leaf takes.
const MAX_LEAF_TRIANGLES: u32 = 8;
/// Most analytic shapes in one leaf.
const MAX_LEAF_SHAPES: u32 = 4;

struct PrimBox(Aabb);

impl Boundable for PrimBox {
    fn aabb(&self) -> Aabb {
        self.0
    }
}

fn prim_box(g: &PrimGeom) -> PrimBox {
    let (lo, hi) = g.bounds();
    PrimBox(Aabb::new(lo.into(), hi.into()))
}

pub struct Bvh {
    triangles: Tree,
    packets: Vec<Triangle4>,
    shapes: Tree,
    /// Analytic shapes in leaf order, with their scene-wide ids.
    shape_geoms: Vec<PrimGeom>,
    shape_ids: Vec<u32>,
}

impl Bvh {
    pub fn build(prims: Vec<Prim>) -> Self {
        let (tris, others): (Vec<Prim>, Vec<Prim>) = prims
            .into_iter()
            .partition(|p| matches!(p.geom, PrimGeom::Triangle(_)));
        let tri_data: Vec<([Vec3; 3], u32)> = tris
            .into_iter()
            .map(|p| match p.geom {
                PrimGeom::Triangle(v) => (v, p.id),
                _ => unreachable!("partitioned above"),
            })
            .collect();
        let tri_boxes: Vec<PrimBox> = tri_data
            .iter()
            .map(|(v, _)| prim_box(&PrimGeom::Triangle(*v)))
            .collect();
        let mut packets = Vec::with_capacity(tri_data.len().div_ceil(3));
        let triangles = Tree::build(&tri_boxes, MAX_LEAF_TRIANGLES, |leaf| {
            let first = packets.len() as u32;
            let mut buf = arrayvec::ArrayVec::<_, 4>::new();
            for chunk in leaf.chunks(4) {
                buf.clear();
                buf.extend(chunk.iter().map(|&i| tri_data[i as usize]));
                packets.push(Triangle4::new(&buf));
            }
            debug_assert!(packets.len() - first as usize <= MAX_LEAF_ITEMS);
            (first, packets.len() as u32 - first)
        });
        drop(tri_boxes);
        drop(tri_data);
        packets.shrink_to_fit();

        let shape_boxes: Vec<PrimBox> = others.iter().map(|p| prim_box(&p.geom)).collect();
        let mut shape_geoms = Vec::with_capacity(others.len());
        let mut shape_ids = Vec::with_capacity(others.len());
        let shapes = Tree::build(&shape_boxes, MAX_LEAF_SHAPES, |leaf| {
            let first = shape_geoms.len() as u32;
            for &i in leaf {
                shape_geoms.push(others[i as usize].geom);
                shape_ids.push(others[i as usize].id);
            }
            (first, leaf.len() as u32)
        });
        Self {
            triangles,
            packets,
            shapes,
            shape_geoms,
            shape_ids,
        }
    }

    /// Bounds of everything (min, max); inverted (+inf, -inf) when empty.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        (
            self.triangles.lo.min(self.shapes.lo),
            self.triangles.hi.max(self.shapes.hi),
        )
    }

    /// Test hook (tests/accel.rs): the triangles in each packet of each triangle leaf.
    #[doc(hidden)]
    pub fn triangle_leaves(&self) -> Vec<Vec<usize>> {
        let used = |p: &Triangle4| p.ids.iter().filter(|&&id| id != u32::MAX).count();
        let leaves = self.triangles.leaves().into_iter();
        leaves
            .map(|(first, n)| {
                let packets = &self.packets[first as usize..(first + n) as usize];
                packets.iter().map(used).collect()
            })
            .collect()
    }

    /// Test hook (tests/accel.rs, tests/accel_planes.rs): the portable node and leaf tests,
    /// those of a CPU without AVX2, on any CPU.
    #[doc(hidden)]
    pub fn portable(mut self) -> Self {
        self.triangles.avx2 = false;
        self.shapes.avx2 = false;
        self
    }

    /// Closest hit.
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        let mut t_max = ray.t_max;
        let mut best = None;
        if !self.packets.is_empty() {
            let shear = RayShear::new(ray);
            self.triangles.traverse_isa::<true>(
                ray,
                &mut t_max,
                #[inline(always)]
                |first, count, t_max, avx2| {
                    let tris = (&shear, avx2);
                    self.closest_triangle(first, count, tris, t_max, &mut best);
                    Visit::Continue
                },
            );
        }
        if !self.shape_geoms.is_empty() {
            self.shapes.traverse::<true>(
                ray,
                &mut t_max,
                #[inline(always)]
                |first, count, t_max| {
                    for i in first as usize..(first + count) as usize {
                        if let Some(h) = self.shape_geoms[i].intersect_analytic(ray, *t_max) {
                            keep_closer(&mut best, t_max, self.shape_ids[i], h);
                        }
                    }
                    Visit::Continue
                },
            );
        }
        best
    }

    /// The nearest hit among a leaf's triangle packets, kept in `best` if nearer than `t_max`.
    /// Always inlined: it runs inside the traversal loop (its AVX2 build included), where a call
    /// per leaf cost about 5% of the rays per second (traversal benchmark, diffuse rays). In
    /// the AVX2 loop a leaf of two packets takes one 8-wide test (`intersect_pair_avx2`),
    /// whose results it keeps in the order the packet-by-packet loop would.
    #[inline(always)]
    fn closest_triangle(
        &self,
        first: u32,
        count: u32,
        (shear, avx2): (&RayShear, bool),
        t_max: &mut f32,
        best: &mut Option<Hit>,
    ) {
        let packets = &self.packets[first as usize..(first + count) as usize];
        #[cfg(target_arch = "x86_64")]
        if let ([a, b], true) = (packets, avx2) {
            // SAFETY: `avx2` is true only inside `traverse_avx2` (an AVX2 CPU, AVX2 code).
            let h = unsafe { Triangle4::intersect_pair_avx2(a, b, shear, *t_max) };
            let hit = |k: usize| PrimHit {
                t: h.t[k],
                b1: h.b1[k],
                b2: h.b2[k],
            };
            // The loop's order: `a`'s hits and redos, then `b`'s, whose in-range test is
            // applied again at the t_max `a` left (the loop tests `b` only then).
            for lane in lanes(h.mask & 0xf) {
                keep_closer(best, t_max, a.ids[lane], hit(lane));
            }
            redo_closest(shear, a, h.redo & 0xf, t_max, best);
            let t_b = *t_max;
            for lane in lanes(h.mask >> 4) {
                if h.ts[lane + 4] < t_b * h.det_abs[lane + 4] {
                    keep_closer(best, t_max, b.ids[lane], hit(lane + 4));
                }
            }
            redo_closest(shear, b, h.redo >> 4, t_max, best);
            return;
        }
        let _ = avx2;
        for p in packets {
            let h = p.intersect(shear, *t_max);
            for lane in lanes(h.mask) {
                let hit = PrimHit {
                    t: h.t[lane],
                    b1: h.b1[lane],
                    b2: h.b2[lane],
                };
                keep_closer(best, t_max, p.ids[lane], hit);
            }
            redo_closest(shear, p, h.redo, t_max, best);
        }
    }

    /// Whether any of a leaf's triangle packets blocks the ray before `t_max` (inlined as
    /// `closest_triangle` is, with the same two-packet test in the AVX2 loop).
    #[inline(always)]
    fn any_triangle(
        &self,
        first: u32,
        count: u32,
        (shear, avx2): (&RayShear, bool),
        t_max: f32,
    ) -> bool {
        let packets = &self.packets[first as usize..(first + count) as usize];
        let redo_hits = |p: &Triangle4, redo: u32| {
            lanes(redo).any(|lane| triangle::intersect(shear, t_max, &p.vertices(lane)).is_some())
        };
        #[cfg(target_arch = "x86_64")]
        if let ([a, b], true) = (packets, avx2) {
            // SAFETY: `avx2` is true only inside `traverse_avx2` (an AVX2 CPU, AVX2 code).
            let h = unsafe { Triangle4::intersect_pair_avx2(a, b, shear, t_max) };
            return h.mask != 0 || redo_hits(a, h.redo & 0xf) || redo_hits(b, h.redo >> 4);
        }
        let _ = avx2;
        // A plain loop: `Iterator::any` was not inlined into the traversal.
        for p in packets {
            let h = p.intersect(shear, t_max);
            if h.mask != 0 || redo_hits(p, h.redo) {
                return true;
            }
        }
        false
    }

    /// True if any primitive lies on the ray within (0, t_max); stops at the first one found.
    #[inline]
    pub fn occluded(&self, ray: &Ray) -> bool {
        let mut t_max = ray.t_max;
        let stop_if = |blocked: bool| {
            if blocked {
                Visit::Stop
            } else {
                Visit::Continue
            }
        };
        if !self.packets.is_empty() {
            let shear = RayShear::new(ray);
            let blocked = self.triangles.traverse_isa::<false>(
                ray,
                &mut t_max,
                #[inline(always)]
                |first, count, t_max, avx2| {
                    let tris = (&shear, avx2);
                    stop_if(self.any_triangle(first, count, tris, *t_max))
                },
            );
            if blocked {
                return true;
            }
        }
        !self.shape_geoms.is_empty()
            && self.shapes.traverse::<false>(
                ray,
                &mut t_max,
                #[inline(always)]
                |first, count, t_max| {
                    stop_if(
                        self.shape_geoms[first as usize..(first + count) as usize]
                            .iter()
                            .any(|g| g.intersect_analytic(ray, *t_max).is_some()),
                    )
                },
            )
    }
}

/// Lane indices of the set bits of a packet's hit mask, lowest first.
#[inline(always)]
fn lanes(mut mask: u32) -> impl Iterator<Item = usize> {
    std::iter::from_fn(move || {
        (mask != 0).then(|| {
            let lane = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            lane
        })
    })
}

/// The lanes of `redo` in packet `p`, tested one by one (`triangle::intersect`, with its f64
/// refinement), each kept if closer.
#[inline(always)]
fn redo_closest(
    shear: &RayShear,
    p: &Triangle4,
    redo: u32,
    t_max: &mut f32,
    best: &mut Option<Hit>,
) {
    for lane in lanes(redo) {
        if let Some(r) = triangle::intersect(shear, *t_max, &p.vertices(lane)) {
            let hit = PrimHit {
                t: r.t,
                b1: r.b1,
                b2: r.b2,
            };
            keep_closer(best, t_max, p.ids[lane], hit);
        }
    }
}

/// Makes `hit` the closest so far if it is nearer than `t_max`.
#[inline(always)]
fn keep_closer(best: &mut Option<Hit>, t_max: &mut f32, prim: u32, hit: PrimHit) {
    if hit.t < *t_max {
        *t_max = hit.t;
        *best = Some(Hit { prim, hit });
    }
}
