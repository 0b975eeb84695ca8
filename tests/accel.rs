//! The BVH must return exactly what testing every primitive returns: the same closest primitive
//! at the same distance, and the same occlusion answer, for random rays through a random soup
//! of triangles (including slivers), spheres and disks.
//!
//! Tolerance: both backends run the same primitive intersection code, so hits must agree
//! exactly; where two primitives are hit at the same distance (shared edges, coincident
//! surfaces) either may win, so a different primitive at a distance equal to 1e-6 relative is
//! accepted.

use glam::{Mat4, Vec3};
use prism::accel::{Accel, AccelKind, Prim};
use prism::math::rng::Pcg32;
use prism::math::Transform;
use prism::ray::Ray;
use prism::shape::{Disk, Mesh, Shape, Sphere};

fn v3(rng: &mut Pcg32, s: f32) -> Vec3 {
    Vec3::new(
        rng.next_f32() - 0.5,
        rng.next_f32() - 0.5,
        rng.next_f32() - 0.5,
    ) * 2.0
        * s
}

fn random_shapes(rng: &mut Pcg32, n_tris: usize) -> Vec<Shape> {
    let mut mesh = Mesh::default();
    for i in 0..n_tris {
        let c = v3(rng, 10.0);
        let size = if i % 10 == 0 { 3.0 } else { 0.4 };
        let a = c + v3(rng, size);
        let b = c + v3(rng, size);
        // Every 7th triangle is a sliver: its third vertex almost on the first edge.
        let d = if i % 7 == 0 {
            a + (b - a) * 0.37 + v3(rng, 1e-5)
        } else {
            c + v3(rng, size)
        };
        let base = mesh.positions.len() as u32;
        mesh.positions.extend([a, b, d]);
        mesh.indices.push([base, base + 1, base + 2]);
    }
    let mut shapes = vec![Shape::Mesh(mesh), Shape::Mesh(Mesh::cube())];
    for _ in 0..20 {
        shapes.push(Shape::Sphere(Sphere {
            center: v3(rng, 10.0),
            radius: 0.2 + rng.next_f32(),
            flip: false,
        }));
    }
    for _ in 0..10 {
        let m = Mat4::from_translation(v3(rng, 10.0))
            * Mat4::from_axis_angle(v3(rng, 1.0).normalize(), rng.next_f32() * 6.0)
            * Mat4::from_scale(Vec3::new(0.5 + rng.next_f32(), 0.5 + rng.next_f32(), 1.0));
        shapes.push(Shape::Disk(Disk {
            to_world: Transform::from_matrix(m).unwrap(),
            flip: false,
        }));
    }
    shapes
}

fn prims(shapes: &[Shape]) -> Vec<Prim> {
    let mut out = Vec::new();
    for s in shapes {
        for i in 0..s.prim_count() {
            out.push(Prim {
                id: out.len() as u32,
                geom: s.prim_geom(i),
            });
        }
    }
    out
}

#[test]
fn bvh_matches_brute_force_on_random_rays() {
    let mut rng = Pcg32::new(11, 1);
    for (scene_no, n_tris) in [(0, 1usize), (1, 50), (2, 5000)] {
        let shapes = random_shapes(&mut rng, n_tris);
        let p = prims(&shapes);
        let bvh = Accel::build(p.clone(), AccelKind::Bvh);
        let brute = Accel::build(p, AccelKind::BruteForce);
        let (mut hits, mut mismatched) = (0, 0);
        for r in 0..20_000 {
            let o = v3(&mut rng, 14.0);
            let d = v3(&mut rng, 1.0).normalize_or(Vec3::X);
            let t_max = if r % 3 == 0 {
                rng.next_f32() * 20.0
            } else {
                f32::INFINITY
            };
            let ray = Ray { o, d, t_max };
            let (a, b) = (bvh.intersect(&ray), brute.intersect(&ray));
            match (a, b) {
                (None, None) => {}
                (Some(x), Some(y)) => {
                    hits += 1;
                    if x.prim != y.prim || x.hit.t != y.hit.t {
                        let tie = (x.hit.t - y.hit.t).abs() <= 1e-6 * y.hit.t;
                        assert!(tie, "scene {scene_no} ray {r}: bvh {x:?} vs brute {y:?}");
                        mismatched += 1;
                    }
                }
                _ => panic!("scene {scene_no} ray {r}: bvh {a:?} vs brute {b:?}"),
            }
            assert_eq!(
                bvh.occluded(&ray),
                brute.occluded(&ray),
                "scene {scene_no} ray {r} occlusion"
            );
        }
        assert!(
            hits > 1000 || n_tris < 100,
            "scene {scene_no}: too few hits ({hits}) to test anything"
        );
        assert!(mismatched <= 5, "scene {scene_no}: {mismatched} ties");
    }
}

#[test]
fn empty_scene_misses() {
    let a = Accel::build(Vec::new(), AccelKind::Bvh);
    let ray = Ray::new(Vec3::ZERO, Vec3::X);
    assert!(a.intersect(&ray).is_none() && !a.occluded(&ray));
}
