//! A uniform light whose mesh is one parallelogram (two triangles on a shared diagonal: every
//! `Rectangle` shape, most quads from files), sampled as the parallelogram: the point is an
//! affine map of the unit square. Picking a triangle by area and folding the square onto it
//! took a table walk, a division and a square root on the way from the sample to the shadow
//! ray (8% of a Cornell render's time in `sample_area`); this takes neither, and keeps the
//! sampler's stratification whole instead of cutting it at the fold.
//!
//! The density is the same (uniform by area, 1 / the mesh's area), so `pdf_li` and MIS are
//! unchanged. The point lies on the first triangle's plane; on the second half it can miss
//! the second triangle by as much as the corners miss a true parallelogram (rounding of the
//! loaded vertices: a few ulps), and that distance joins the point's error bound, which keeps
//! shadow rays off the light's own surface.

use crate::math::float::gamma;
use crate::shape::{AreaSample, Mesh};
use glam::{Vec2, Vec3};

/// Corners `q0`, `s1`, `s2` of the first triangle (`s1`, `s2` the shared diagonal): the point
/// at (u, v) is q0 + u·(s1 − q0) + v·(s2 − q0), on the first triangle where u + v ≤ 1.
#[derive(Clone, Copy, Debug)]
pub(super) struct Parallelogram {
    q0: Vec3,
    s1: Vec3,
    s2: Vec3,
    /// The two triangles' winding normals (as `Mesh::winding_normal` gives them).
    n0: Vec3,
    n1: Vec3,
    /// How far the second triangle's free corner may lie from the parallelogram's.
    fold_error: Vec3,
    /// 1 / the mesh's area, kept so a sample divides nothing.
    pdf_area: f32,
}

impl Parallelogram {
    /// The parallelogram a two-triangle mesh forms, or None if it forms none (within a few
    /// ulps of its coordinates: anything farther would be sampled off the light); its points
    /// have density `pdf_area`.
    pub(super) fn of(m: &Mesh, pdf_area: f32) -> Option<Self> {
        let [t0, t1] = m.indices.as_slice() else {
            return None;
        };
        if !m.normals.is_empty() {
            // Vertex normals choose the light's front side (`tri_surface::point_with_normal`).
            return None;
        }
        // The vertex of each triangle that the other lacks; the two others are the diagonal.
        let free = |a: &[u32; 3], b: &[u32; 3]| {
            let mut k = (0..3).filter(|&k| !b.contains(&a[k]));
            match (k.next(), k.next()) {
                (Some(k), None) => Some(k),
                _ => None,
            }
        };
        let (k0, k1) = (free(t0, t1)?, free(t1, t0)?);
        let p = |i: u32| m.positions.get(i as usize).copied();
        // The first triangle in its own winding, from its free corner: (q0, s1, s2).
        let (q0, s1, s2) = (p(t0[k0])?, p(t0[(k0 + 1) % 3])?, p(t0[(k0 + 2) % 3])?);
        let q1 = p(t1[k1])?;
        let (n0, n1) = (m.winding_normal(0), m.winding_normal(1));
        // One orientation: the second triangle's winding agrees with the first's.
        if n0 == Vec3::ZERO || n0.dot(n1) <= 0.0 {
            return None;
        }
        let size = q0.abs() + s1.abs() + s2.abs() + q1.abs();
        // The corner q1 the parallelogram has, and a bound on the rounding of that sum.
        let gap = (q1 - (s1 + s2 - q0)).abs() + gamma(4) * size;
        if gap.max_element() > 64.0 * f32::EPSILON * size.max_element() || !gap.is_finite() {
            return None;
        }
        Some(Self {
            q0,
            s1,
            s2,
            n0,
            n1,
            fold_error: gap,
            pdf_area,
        })
    }

    /// A uniform point (density 1 / the mesh's area).
    #[inline(always)]
    pub(super) fn sample(&self, u: Vec2) -> AreaSample {
        let b0 = 1.0 - u.x - u.y;
        // Barycentric form, as `tri_surface::point_with_normal` computes a point (b0 < 0 on
        // the second half, which the error bound's absolute values cover).
        let p = b0 * self.q0 + u.x * self.s1 + u.y * self.s2;
        // The fold's gap joins the bound on both halves: a few ulps more on the first, and no
        // branch on a coin flip (adding it on the second half only cost a misprediction in two).
        let p_error = gamma(7)
            * ((b0 * self.q0).abs() + (u.x * self.s1).abs() + (u.y * self.s2).abs())
            + self.fold_error;
        AreaSample {
            p,
            p_error,
            n: if b0 >= 0.0 { self.n0 } else { self.n1 },
            pdf_area: self.pdf_area,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::rng::Pcg32;
    use crate::math::Transform;
    use glam::Mat4;

    fn rect(m: Mat4, flip: bool) -> Mesh {
        Mesh::rectangle().transformed(&Transform::from_matrix(m).unwrap(), flip)
    }

    /// Every sample lies on the mesh within its error bound, on the triangle whose normal it
    /// reports, and the samples cover the two triangles in proportion to their areas.
    #[test]
    fn samples_lie_on_the_mesh_uniformly() {
        let cornell = Mat4::from_cols_array_2d(&[
            [0.23, 0.0, 0.0, 0.0],
            [0.0, -8.30516e-09, 0.19, 0.0],
            [0.0, -0.19, -8.30516e-09, 0.0],
            [0.0, 0.99, 0.01, 1.0],
        ]);
        let skew = Mat4::from_cols_array_2d(&[
            [3.0, 0.5, 0.1, 0.0],
            [1.0, 0.2, 2.0, 0.0],
            [0.3, 4.0, 0.7, 0.0],
            [1e3, -2e3, 5e2, 1.0],
        ]);
        let mut rng = Pcg32::new(7, 11);
        for (m, flip, nudge) in [
            (cornell, false, false),
            (cornell, true, false),
            (skew, false, false),
            (skew, true, false),
            (skew, false, true),
        ] {
            let mut mesh = rect(m, flip);
            if nudge {
                // The second triangle's free corner 40 ulps off the parallelogram, more than
                // the point's rounding bound; its normal then differs in the last bits.
                let q = &mut mesh.positions[3];
                *q = Vec3::from_array(q.to_array().map(|c| f32::from_bits(c.to_bits() + 40)));
                assert_ne!(mesh.winding_normal(0), mesh.winding_normal(1));
            }
            let par = Parallelogram::of(&mesh, 1.0).expect("a rectangle is a parallelogram");
            let (a0, a1) = (mesh.triangle_area(0), mesh.triangle_area(1));
            // In the plane, a point may miss the triangles by the fold's gap (as a fraction
            // of the shortest edge) and rounding.
            let edge = (par.s1 - par.q0).length().min((par.s2 - par.q0).length());
            let slack = par.fold_error.length() / edge + 1e-5;
            let mut on_first = 0u32;
            let n = 200_000;
            for _ in 0..n {
                let u = Vec2::new(rng.next_f32(), rng.next_f32());
                let s = par.sample(u);
                // Which triangle holds the point: its barycentrics in each.
                let inside = |t: usize| {
                    let [a, b, c] = mesh.vertices(t);
                    let nrm = (b - a).cross(c - a);
                    let w =
                        |x: Vec3, y: Vec3| (y - x).cross(s.p - x).dot(nrm) / nrm.length_squared();
                    let (wa, wb, wc) = (w(b, c), w(c, a), w(a, b));
                    let dist = (s.p - a).dot(nrm.normalize()).abs();
                    (wa.min(wb).min(wc), dist)
                };
                let ((m0, d0), (m1, d1)) = (inside(0), inside(1));
                let (t, d) = if m0 >= m1 { (0, d0) } else { (1, d1) };
                assert!(m0.max(m1) > -slack, "{:?} lies outside both triangles", s.p);
                // Off the plane by no more than the bound says (along the normal).
                assert!(
                    d <= s.p_error.length(),
                    "{:?}: {d:e} off, bound {:?}",
                    s.p,
                    s.p_error
                );
                assert_eq!(
                    s.n,
                    mesh.winding_normal(t),
                    "the normal of the triangle hit"
                );
                on_first += (t == 0) as u32;
            }
            // Binomial: share a0 / (a0 + a1) = 1/2, σ = 0.5/√n ≈ 0.0011; 5σ.
            let share = on_first as f64 / n as f64;
            let want = a0 as f64 / (a0 + a1) as f64;
            assert!(
                (share - want).abs() < 5.0 * 0.5 / (n as f64).sqrt(),
                "{share} vs {want}"
            );
        }
    }

    #[test]
    fn other_meshes_are_not_parallelograms() {
        let mut m = rect(Mat4::IDENTITY, false);
        assert!(Parallelogram::of(&m, 1.0).is_some());
        m.positions[3].x += 1e-3; // a trapezoid
        assert!(Parallelogram::of(&m, 1.0).is_none());
        let mut m = rect(Mat4::IDENTITY, false);
        m.indices[1] = [3, 1, 0]; // the other diagonal, triangles overlapping
        assert!(Parallelogram::of(&m, 1.0).is_none());
        let mut m = rect(Mat4::IDENTITY, false);
        m.indices[1] = [2, 0, 3]; // the second triangle wound the other way
        assert!(Parallelogram::of(&m, 1.0).is_none());
        let mut m = rect(Mat4::IDENTITY, false);
        m.indices.push([0, 1, 3]);
        assert!(Parallelogram::of(&m, 1.0).is_none());
        let mut m = rect(Mat4::IDENTITY, false);
        m.normals = vec![-Vec3::Z; 4]; // vertex normals: they pick the front side
        assert!(Parallelogram::of(&m, 1.0).is_none());
    }
}
