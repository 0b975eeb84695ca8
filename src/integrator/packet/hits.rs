//! The trace stage: each lane's closest primitive through the BVH (one ray per lane), then the
//! surface at the hits of triangle meshes reconstructed across lanes at once (structure of
//! arrays: `[f32; W]` per component), which AVX2 runs eight lanes per instruction. Hit
//! reconstruction was 18% of a Cornell box render's instructions (`Scene::intersect`'s own).
//!
//! **Bits.** Each lane does exactly the IEEE operations of `shape::tri_surface::surface` for a
//! `Mesh` (glam's `Vec3` arithmetic written out component by component in its order: no FMA,
//! sqrt and division correctly rounded at every width), so a lane's interaction is the one
//! `Scene::intersect` returns, bit for bit (tested below on random triangles, with and without
//! normals and uvs, degenerate ones included). Lanes the arrays do not take (spheres, disks,
//! instances, normal-mapped meshes, a frame whose tangent degenerates) and scenes with
//! instances or moving shapes go through the scalar code.

use crate::interaction::SurfaceInteraction;
use crate::math::float::gamma;
use crate::math::Frame;
use crate::ray::Ray;
use crate::scene::Scene;
use crate::shape::{Mesh, PrimHit, Shape};
use glam::{Vec2, Vec3};

/// `[f(0), …, f(W − 1)]`, by a plain loop (see `V3::map`).
#[inline(always)]
fn lanes<T: Copy + Default, const W: usize>(f: impl Fn(usize) -> T) -> [T; W] {
    let mut out = [T::default(); W];
    for (i, o) in out.iter_mut().enumerate() {
        *o = f(i);
    }
    out
}

/// Three components, each over W lanes.
#[derive(Clone, Copy)]
struct V3<const W: usize>([[f32; W]; 3]);

impl<const W: usize> V3<W> {
    const ZERO: Self = V3([[0.0; W]; 3]);

    /// Component c of lane i is f(c, i). Plain loops, not `array::from_fn`, whose machinery
    /// was left out of line (and unvectorised) in the AVX2 kernel.
    #[inline(always)]
    fn map(f: impl Fn(usize, usize) -> f32) -> Self {
        let mut v = Self::ZERO;
        for c in 0..3 {
            for i in 0..W {
                v.0[c][i] = f(c, i);
            }
        }
        v
    }
    #[inline(always)]
    fn sub(&self, o: &Self) -> Self {
        Self::map(|c, i| self.0[c][i] - o.0[c][i])
    }
    /// glam's `dot`: (x·x' + y·y') + z·z'.
    #[inline(always)]
    fn dot(&self, o: &Self) -> [f32; W] {
        let (a, b) = (&self.0, &o.0);
        lanes(|i| a[0][i] * b[0][i] + a[1][i] * b[1][i] + a[2][i] * b[2][i])
    }
    /// glam's `cross`.
    #[inline(always)]
    fn cross(&self, o: &Self) -> Self {
        let (a, b) = (&self.0, &o.0);
        Self::map(|c, l| {
            let (y, z) = ((c + 1) % 3, (c + 2) % 3);
            a[y][l] * b[z][l] - b[y][l] * a[z][l]
        })
    }
    /// b0·a + b1·b + b2·c, summed left to right (glam's `b0 * a + b1 * b + b2 * c`).
    #[inline(always)]
    fn lerp3(b: &[[f32; W]; 3], a: &Self, bb: &Self, c: &Self) -> Self {
        Self::map(|k, i| b[0][i] * a.0[k][i] + b[1][i] * bb.0[k][i] + b[2][i] * c.0[k][i])
    }
    /// glam's `normalize_or_zero`: self · (1 / sqrt(dot)) if that factor is finite and > 0.
    #[inline(always)]
    fn normalize_or_zero(&self) -> Self {
        let d = self.dot(self);
        let rcp = lanes::<_, W>(|i| 1.0 / d[i].sqrt());
        Self::map(|c, i| {
            if rcp[i].is_finite() && rcp[i] > 0.0 {
                self.0[c][i] * rcp[i]
            } else {
                0.0
            }
        })
    }
    #[inline(always)]
    fn get(&self, i: usize) -> Vec3 {
        Vec3::new(self.0[0][i], self.0[1][i], self.0[2][i])
    }
    #[inline(always)]
    fn set(&mut self, i: usize, v: Vec3) {
        (self.0[0][i], self.0[1][i], self.0[2][i]) = (v.x, v.y, v.z);
    }
}

/// What the arrays read of a mesh triangle's corners, lane by lane.
struct Corners<const W: usize> {
    p: [V3<W>; 3],
    /// Vertex normals (zero where the mesh has none: then they change nothing, see `surface`).
    n: [V3<W>; 3],
    uv: [[[f32; W]; 2]; 3],
    has_n: [bool; W],
    has_uv: [bool; W],
    /// Barycentrics (b0, b1, b2), b0 = 1 − b1 − b2 as the scalar code computes it.
    b: [[f32; W]; 3],
}

impl<const W: usize> Corners<W> {
    fn new() -> Self {
        Corners {
            p: [V3::ZERO; 3],
            n: [V3::ZERO; 3],
            uv: [[[0.0; W]; 2]; 3],
            has_n: [false; W],
            has_uv: [false; W],
            b: [[0.0; W]; 3],
        }
    }

    /// Lane `i` takes triangle `tri` of `m`, hit at `h`.
    #[inline(always)]
    fn gather(&mut self, i: usize, m: &Mesh, tri: usize, h: &PrimHit) {
        let [i0, i1, i2] = m.indices[tri];
        let idx = [i0 as usize, i1 as usize, i2 as usize];
        self.has_n[i] = !m.normals.is_empty();
        self.has_uv[i] = !m.uvs.is_empty();
        for j in 0..3 {
            self.p[j].set(i, m.positions[idx[j]]);
            if self.has_n[i] {
                self.n[j].set(i, m.normals[idx[j]]);
            }
            if self.has_uv[i] {
                let uv = m.uvs[idx[j]];
                (self.uv[j][0][i], self.uv[j][1][i]) = (uv.x, uv.y);
            }
        }
        self.b[0][i] = 1.0 - h.b1 - h.b2;
        self.b[1][i] = h.b1;
        self.b[2][i] = h.b2;
    }
}

/// Surface data of every lane, as `tri_surface::surface` computes it; `None` in `frame_ok`
/// where the tangent degenerates (the scalar code then takes `Frame::from_normal`).
struct Surfaces<const W: usize> {
    p: V3<W>,
    p_error: V3<W>,
    ng: V3<W>,
    s: V3<W>,
    t: V3<W>,
    n: V3<W>,
    uv: [[f32; W]; 2],
    frame_ok: [bool; W],
}

/// `tri_surface::surface` over W lanes, operation for operation.
#[inline(always)]
fn surface<const W: usize>(c: &Corners<W>) -> Surfaces<W> {
    let b = &c.b;
    let [p0, p1, p2] = &c.p;
    // point(): position, its error bound, the geometric normal.
    let p = V3::<W>::lerp3(b, p0, p1, p2);
    let g = gamma(7);
    let p_error = V3::<W>::map(|k, i| {
        g * ((b[0][i] * p0.0[k][i]).abs()
            + (b[1][i] * p1.0[k][i]).abs()
            + (b[2][i] * p2.0[k][i]).abs())
    });
    let e1 = p1.sub(p0);
    let e2 = p2.sub(p0);
    let ng0 = e1.cross(&e2).normalize_or_zero();
    // Without vertex normals `n` is zero: ng·n = 0 never flips, as the scalar code skips it.
    let n = V3::<W>::lerp3(b, &c.n[0], &c.n[1], &c.n[2]);
    let dn = ng0.dot(&n);
    let flip = lanes::<_, W>(|i| dn[i] < 0.0);
    let ng = V3::<W>::map(|k, i| if flip[i] { -ng0.0[k][i] } else { ng0.0[k][i] });
    // uv and dp/du.
    let uvl = |j: usize| -> [[f32; W]; 2] { c.uv[j] };
    let (uv0, uv1, uv2) = (uvl(0), uvl(1), uvl(2));
    let d = |a: &[[f32; W]; 2], k: usize| lanes::<_, W>(|i| a[k][i] - uv0[k][i]);
    let (duv1, duv2) = ([d(&uv1, 0), d(&uv1, 1)], [d(&uv2, 0), d(&uv2, 1)]);
    let det = lanes::<_, W>(|i| duv1[0][i] * duv2[1][i] - duv1[1][i] * duv2[0][i]);
    let dpdu = V3::<W>::map(|k, i| {
        if c.has_uv[i] && det[i].abs() > 1e-12 {
            (e1.0[k][i] * duv2[1][i] - e2.0[k][i] * duv1[1][i]) / det[i]
        } else {
            e1.0[k][i]
        }
    });
    let uv_k = |k: usize| {
        lanes::<_, W>(|i| {
            if c.has_uv[i] {
                b[0][i] * uv0[k][i] + b[1][i] * uv1[k][i] + b[2][i] * uv2[k][i]
            } else {
                b[k + 1][i]
            }
        })
    };
    let uv = [uv_k(0), uv_k(1)];
    // The shading normal: the normalised vertex normal, else (none, or zero) the geometric.
    let nn = n.normalize_or_zero();
    let use_n = lanes::<_, W>(|i| {
        c.has_n[i] && !(nn.0[0][i] == 0.0 && nn.0[1][i] == 0.0 && nn.0[2][i] == 0.0)
    });
    let ns = V3::<W>::map(|k, i| if use_n[i] { nn.0[k][i] } else { ng.0[k][i] });
    // Frame::from_normal_tangent(ns, dpdu).
    let d = ns.dot(&dpdu);
    let s0 = V3::<W>::map(|k, i| dpdu.0[k][i] - ns.0[k][i] * d[i]);
    let len2 = s0.dot(&s0);
    let frame_ok = lanes::<_, W>(|i| len2[i] > 1e-12 && len2[i].is_finite());
    let len = lanes::<_, W>(|i| len2[i].sqrt());
    let s = V3::<W>::map(|k, i| s0.0[k][i] / len[i]);
    let t = ns.cross(&s);
    Surfaces {
        p,
        p_error,
        ng,
        s,
        t,
        n: ns,
        uv,
        frame_ok,
    }
}

/// Sets `hits[i]` to `scene.intersect(rays[i])` for every lane with a ray (None for the others).
#[inline(always)]
pub(super) fn trace<const W: usize>(
    scene: &Scene,
    rays: [Option<&Ray>; W],
    hits: &mut [Option<SurfaceInteraction>; W],
) {
    if !scene.is_flat() {
        for (ray, hit) in rays.iter().zip(hits.iter_mut()) {
            *hit = ray.and_then(|r| scene.intersect(r));
        }
        return;
    }
    let mut c = Corners::<W>::new();
    // Lanes the arrays take: (shape, triangle, hit).
    let mut mesh: [Option<(u32, u32, PrimHit)>; W] = [None; W];
    for i in 0..W {
        hits[i] = None;
        let Some(ray) = rays[i] else { continue };
        let Some((shape, local, h)) = scene.closest_prim(ray) else {
            continue;
        };
        match &scene.shapes[shape as usize] {
            Shape::Mesh(m) if m.normal_map.is_none() => {
                c.gather(i, m, local as usize, &h);
                mesh[i] = Some((shape, local, h));
            }
            _ => hits[i] = Some(scene.surface_at(ray, shape, local, &h)),
        }
    }
    if mesh.iter().all(Option::is_none) {
        return;
    }
    let s = surface(&c);
    for i in 0..W {
        let (Some((shape, prim, h)), Some(ray)) = (mesh[i], rays[i]) else {
            continue;
        };
        let n = s.n.get(i);
        let frame = if s.frame_ok[i] {
            Frame {
                s: s.s.get(i),
                t: s.t.get(i),
                n,
            }
        } else {
            Frame::from_normal(n)
        };
        hits[i] = Some(SurfaceInteraction {
            p: s.p.get(i),
            p_error: s.p_error.get(i),
            ng: s.ng.get(i),
            frame,
            uv: Vec2::new(s.uv[0][i], s.uv[1][i]),
            t: h.t,
            shape,
            prim,
            time: ray.time,
            bary: Vec2::new(h.b1, h.b2),
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::rng::Pcg32;

    /// Random triangles (some slivers, some degenerate, some with zero or opposed vertex
    /// normals, degenerate uvs) in meshes with and without normals and uvs: every lane's
    /// surface equals `Mesh::surface` bit for bit. Tolerance: none (same IEEE operations).
    #[test]
    fn lanes_match_the_scalar_surface_bit_for_bit() {
        let mut rng = Pcg32::new(3, 7);
        let mut r = |s: f32| (rng.next_f32() - 0.5) * 2.0 * s;
        let mut checked = 0;
        for case in 0..400 {
            let mut v = |s: f32| Vec3::new(r(s), r(s), r(s));
            let (a, b) = (v(10.0), v(10.0));
            let c = match case % 9 {
                0 => a + (b - a) * 0.25, // degenerate: a line
                1 => a,                  // degenerate: two corners equal
                _ => v(10.0),
            };
            let normals = match case % 4 {
                0 => vec![],
                1 => vec![Vec3::ZERO; 3],
                _ => vec![v(1.0), v(1.0), v(1.0)],
            };
            let uvs = match case % 3 {
                0 => vec![],
                1 => vec![Vec2::ZERO, Vec2::X, Vec2::X], // det 0
                _ => vec![
                    Vec2::new(r(1.0), r(1.0)),
                    Vec2::new(r(1.0), r(1.0)),
                    Vec2::ONE,
                ],
            };
            let m = Mesh {
                positions: vec![a, b, c],
                normals,
                uvs,
                indices: vec![[0, 1, 2]],
                normal_map: None,
            };
            let mut corners = Corners::<4>::new();
            let mut want = Vec::new();
            for lane in 0..4 {
                let (b1, b2) = (r(0.5) + 0.5, r(0.25) + 0.25);
                let h = PrimHit { t: 1.0, b1, b2 };
                corners.gather(lane, &m, 0, &h);
                want.push(m.surface(0, b1, b2));
            }
            let s = surface(&corners);
            for (lane, w) in want.iter().enumerate() {
                let bits = |v: Vec3| v.to_array().map(f32::to_bits);
                assert_eq!(bits(s.p.get(lane)), bits(w.p), "case {case} p");
                assert_eq!(bits(s.p_error.get(lane)), bits(w.p_error), "case {case}");
                assert_eq!(bits(s.ng.get(lane)), bits(w.ng), "case {case} ng");
                let uv = Vec2::new(s.uv[0][lane], s.uv[1][lane]);
                assert_eq!(
                    uv.to_array().map(f32::to_bits),
                    w.uv.to_array().map(f32::to_bits)
                );
                assert_eq!(bits(s.n.get(lane)), bits(w.frame.n), "case {case} n");
                if s.frame_ok[lane] {
                    assert_eq!(bits(s.s.get(lane)), bits(w.frame.s), "case {case} s");
                    assert_eq!(bits(s.t.get(lane)), bits(w.frame.t), "case {case} t");
                    checked += 1;
                } else {
                    let f = Frame::from_normal(s.n.get(lane));
                    for (x, y) in [(f.s, w.frame.s), (f.t, w.frame.t)] {
                        assert_eq!(bits(x), bits(y), "case {case} fallback frame");
                    }
                }
            }
        }
        assert!(
            checked > 1000,
            "most frames come from the tangent ({checked})"
        );
    }
}
