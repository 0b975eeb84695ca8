//! Area lights keep each mesh triangle's unit normal (`AreaEmitter`, issue 26 item 3) instead
//! of computing it at every sample. A sampled point's normal must be, bit for bit, what
//! `Mesh::point` computes on its triangle (the edges' cross product normalised, turned to the
//! vertex normals' side where the mesh has them), on meshes of triangles facing every way.
//!
//! Tolerance: exact. The kept normal comes from the same function `Mesh::point` calls, so any
//! difference is another triangle's normal or another computation.

use glam::{Vec2, Vec3};
use prism::emitter::AreaEmitter;
use prism::math::rng::Pcg32;
use prism::shape::{Mesh, Shape};
use prism::spectrum::Curve;

/// `n` triangles of random orientation and size about 1, their centres 10 units apart or more
/// (on a lattice), so a point identifies its triangle by the nearest plane; with per-vertex
/// normals (all three along or against the face's own) when `normals`.
fn scattered(rng: &mut Pcg32, n: usize, normals: bool) -> Mesh {
    let mut mesh = Mesh::default();
    let mut r = || rng.next_f32() - 0.5;
    for i in 0..n {
        let c = Vec3::new((i % 5) as f32, (i / 5 % 5) as f32, (i / 25) as f32) * 10.0;
        let v = [0; 3].map(|_| c + Vec3::new(r(), r(), r()) * 2.0);
        let first = mesh.positions.len() as u32;
        mesh.positions.extend(v);
        mesh.indices.push([first, first + 1, first + 2]);
        if normals {
            let face = (v[1] - v[0]).cross(v[2] - v[0]).normalize();
            let side = if r() < 0.0 { -1.0 } else { 1.0 };
            mesh.normals.extend([face * side; 3]);
        }
    }
    mesh
}

#[test]
fn sampled_normals_are_the_triangles_own() {
    let mut rng = Pcg32::new(17, 3);
    for normals in [false, true] {
        let mesh = scattered(&mut rng, 60, normals);
        let shape = Shape::Mesh(mesh.clone());
        let light = AreaEmitter::new(0, &shape, Curve::Constant(1.0));
        let mut seen = vec![false; mesh.indices.len()];
        for _ in 0..20_000 {
            let u = Vec2::new(rng.next_f32(), rng.next_f32());
            let s = light.sample_area_uv(u, &shape).0;
            // The triangle whose plane holds the point.
            let distance = |i: usize| {
                let [a, b, c] = mesh.indices[i].map(|k| mesh.positions[k as usize]);
                (b - a).cross(c - a).normalize().dot(s.p - a).abs()
            };
            let tri = (0..mesh.indices.len())
                .min_by(|&i, &j| distance(i).total_cmp(&distance(j)))
                .unwrap();
            assert!(distance(tri) < 1e-4, "{:?} lies on no triangle", s.p);
            seen[tri] = true;
            // `Mesh::point`'s normal does not depend on the barycentrics here (the vertex
            // normals of a triangle are equal).
            let want = mesh.point(tri, 0.25, 0.25).2;
            assert_eq!(
                s.n.to_array().map(f32::to_bits),
                want.to_array().map(f32::to_bits),
                "normals {normals}: triangle {tri}: {} against {want}",
                s.n
            );
        }
        assert!(seen.iter().all(|&s| s), "some triangles never sampled");
    }
}
