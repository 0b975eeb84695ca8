//! The BVH must return exactly what testing every primitive returns: the same closest primitive
//! at the same distance, and the same occlusion answer, for random rays through a random soup
//! of triangles (including slivers), spheres and disks.
//!
//! Tolerance: both backends run the same primitive intersection code, so hits must agree
//! exactly; where two primitives are hit at the same distance (shared edges, coincident
//! surfaces) either may win, so a different primitive at a distance equal to 1e-6 relative is
//! accepted.

use glam::{Mat4, Vec3};
use prism::accel::{Accel, AccelKind, Bvh, Prim};
use prism::math::rng::Pcg32;
use prism::math::Transform;
use prism::ray::Ray;
use prism::shape::triangle::{RayShear, Triangle4};
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
            * prism::math::rotation::axis_angle(v3(rng, 1.0).normalize(), rng.next_f32() * 6.0)
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

/// Compares `kind` with brute force on 20,000 random rays in each of three random scenes.
/// `edge_misses` is how many rays per scene may hit in one and miss in the other: zero for the
/// BVH (same primitive code); for Embree, whose own triangle test picks the candidates that
/// prism's test then confirms, a ray through a shared edge or vertex can be a candidate for
/// neither triangle in Embree's arithmetic while prism's watertight test hits one.
fn matches_brute_force(kind: AccelKind, edge_misses: usize) {
    let mut rng = Pcg32::new(11, 1);
    for (scene_no, n_tris) in [(0, 1usize), (1, 50), (2, 5000)] {
        let shapes = random_shapes(&mut rng, n_tris);
        let p = prims(&shapes);
        let fast = Accel::build(p.clone(), kind);
        let brute = Accel::build(p, AccelKind::BruteForce);
        let (mut hits, mut mismatched, mut one_sided) = (0, 0, 0);
        for r in 0..20_000 {
            let o = v3(&mut rng, 14.0);
            let d = v3(&mut rng, 1.0).normalize_or(Vec3::X);
            let t_max = if r % 3 == 0 {
                rng.next_f32() * 20.0
            } else {
                f32::INFINITY
            };
            let ray = Ray {
                o,
                d,
                t_max,
                time: 0.0,
            };
            let (a, b) = (fast.intersect(&ray), brute.intersect(&ray));
            match (a, b) {
                (None, None) => {}
                (Some(x), Some(y)) => {
                    hits += 1;
                    if x.prim != y.prim || x.hit != y.hit {
                        let tie = (x.hit.t - y.hit.t).abs() <= 1e-6 * y.hit.t;
                        assert!(
                            tie,
                            "scene {scene_no} ray {r}: {kind:?} {x:?} vs brute {y:?}"
                        );
                        mismatched += 1;
                    }
                }
                _ => {
                    one_sided += 1;
                    assert!(
                        one_sided <= edge_misses,
                        "scene {scene_no} ray {r}: {kind:?} {a:?} vs brute {b:?}"
                    );
                }
            }
            if fast.occluded(&ray) != brute.occluded(&ray) {
                one_sided += 1;
                assert!(
                    one_sided <= edge_misses,
                    "scene {scene_no} ray {r}: {kind:?} occlusion differs"
                );
            }
        }
        assert!(
            hits > 1000 || n_tris < 100,
            "scene {scene_no}: too few hits ({hits}) to test anything"
        );
        assert!(mismatched <= 5, "scene {scene_no}: {mismatched} ties");
    }
}

#[test]
fn bvh_matches_brute_force_on_random_rays() {
    matches_brute_force(AccelKind::Bvh, 0);
}

#[test]
#[cfg_attr(
    not(feature = "embree"),
    ignore = "needs prism built with --features embree (Debian: libembree-dev)"
)]
fn embree_matches_brute_force_on_random_rays() {
    matches_brute_force(AccelKind::Embree, 2);
}

/// A ray with a NaN or infinite component, given to the BVH directly, meets nothing (it once
/// panicked: NaN slab distances let every lane of a node through, unused lanes included, whose
/// empty child then read as a leaf past the end of the triangles). A zero direction, a zero or
/// negative `t_max`, and rays through the scene's middle must agree with brute force.
///
/// Tolerance: exact. Both backends run the same primitive code.
#[test]
fn bvh_is_safe_on_nan_infinite_and_degenerate_rays() {
    let mut rng = Pcg32::new(5, 9);
    let shapes = random_shapes(&mut rng, 500);
    let p = prims(&shapes);
    let bvh = Accel::build(p.clone(), AccelKind::Bvh);
    let brute = Accel::build(p, AccelKind::BruteForce);
    let (nan, inf) = (f32::NAN, f32::INFINITY);
    let bad = [
        Vec3::new(nan, 0.0, 0.0),
        Vec3::new(0.0, nan, 1.0),
        Vec3::new(0.0, 0.0, nan),
        Vec3::splat(nan),
        Vec3::new(inf, 0.0, 0.0),
        Vec3::new(0.0, -inf, 0.0),
        Vec3::new(inf, -inf, inf),
    ];
    let good = [Vec3::ZERO, Vec3::new(0.3, -0.2, 0.1), Vec3::X, Vec3::NEG_Z];
    let mut rays = Vec::new();
    for &b in &bad {
        for &g in &good {
            let d = g.normalize_or(Vec3::Y);
            rays.push(Ray::new(b, d)); // bad origin
            rays.push(Ray::new(g, b)); // bad direction
        }
    }
    for r in &rays {
        assert_eq!(bvh.intersect(r), None, "{r:?}");
        assert!(!bvh.occluded(r), "{r:?}");
    }
    let mut odd = Vec::new();
    for &o in &good {
        odd.push(Ray::new(o, Vec3::ZERO));
        // A NaN t_max: the BVH's box test meets nothing (brute force's analytic shapes
        // ignore it): only no panic is asked.
        let mut r = Ray::new(o, Vec3::new(0.6, 0.0, 0.8));
        r.t_max = nan;
        let _ = (bvh.intersect(&r), bvh.occluded(&r));
        for t_max in [-1.0, 0.0, -inf] {
            let mut r = Ray::new(o, Vec3::new(0.6, 0.0, 0.8));
            r.t_max = t_max;
            odd.push(r);
        }
    }
    for _ in 0..200 {
        odd.push(Ray::new(
            v3(&mut rng, 3.0),
            v3(&mut rng, 1.0).normalize_or(Vec3::X),
        ));
    }
    for r in &odd {
        assert_eq!(bvh.intersect(r), brute.intersect(r), "{r:?}");
        assert_eq!(bvh.occluded(r), brute.occluded(r), "{r:?}");
    }
}

/// Rays leaving a large, rotated rectangle (whose vertices carry rounding error: the floor of
/// `render_analytic`'s view-factor test, where this once darkened the floor by 14%) must not
/// re-hit it with any backend: prism rejects hits within t's rounding-error bound, and the
/// Embree backend must apply the same rule to its candidates.
#[test]
fn no_self_hits_leaving_a_rotated_rectangle() {
    let kinds = [
        AccelKind::Bvh,
        #[cfg(feature = "embree")]
        AccelKind::Embree,
    ];
    for kind in kinds {
        let job = prism::load::load_str(
            &format!(
                r#"(
                    shapes: [(shape: Rectangle, to_world: [Scale((4, 4, 1)), Rotate(axis: (1, 0, 0), angle: -90)])],
                    emitters: [Constant(radiance: Constant(1.0))],
                    accel: {kind:?},
                )"#
            ),
            std::path::Path::new("rotated.ron"),
        )
        .unwrap();
        let scene = &job.scene;
        let mut rng = Pcg32::new(3, 5);
        let (mut hits, mut self_hits) = (0, 0);
        for _ in 0..20_000 {
            // A ray from above onto the floor, then rays leaving the hit point to both sides.
            let target = Vec3::new(v3(&mut rng, 2.0).x, 0.0, v3(&mut rng, 2.0).z);
            let o = target + Vec3::new(v3(&mut rng, 0.1).x, 0.3, v3(&mut rng, 0.1).z);
            let Some(si) = scene.intersect(&Ray::new(o, (target - o).normalize())) else {
                continue;
            };
            hits += 1;
            // Directions uniform over the sphere: the grazing ones are those that can meet the
            // rectangle's other triangle, which rounding leaves slightly out of plane.
            for _ in 0..2 {
                let d = v3(&mut rng, 1.0).normalize_or(si.ng);
                let out = prism::ray::spawn(si.p, si.p_error, si.ng, d);
                if scene.intersect(&out).is_some() || scene.occluded(&out) {
                    self_hits += 1;
                }
            }
        }
        assert!(hits > 19_000, "{kind:?}: only {hits} primary hits");
        assert_eq!(
            self_hits, 0,
            "{kind:?}: rays re-hit the rectangle they leave"
        );
    }
}

#[test]
fn empty_scene_misses() {
    let a = Accel::build(Vec::new(), AccelKind::Bvh);
    let ray = Ray::new(Vec3::ZERO, Vec3::X);
    assert!(a.intersect(&ray).is_none() && !a.occluded(&ray));
}

/// The two-packet AVX2 test finds in each lane exactly what `Triangle4::intersect` finds for
/// that lane's packet at the same `t_max`: the same hit and redo masks, the same t and
/// barycentrics bit for bit, and `ts < t_max · |det|` agreeing with the in-range test at a
/// smaller `t_max` (what the BVH re-applies to the second packet). Rays aim at edges and
/// vertices; some lanes are degenerate, some unused, some rays NaN.
#[test]
#[cfg(target_arch = "x86_64")]
#[cfg_attr(
    not(prism_host_avx2),
    ignore = "this CPU lacks AVX2: only the portable path runs"
)]
fn pair_test_matches_packet_test() {
    assert!(std::is_x86_feature_detected!("avx2"), "rebuild on this CPU");
    let mut state = 29u32;
    let mut next = || {
        state = state.wrapping_mul(747796405).wrapping_add(2891336453);
        (state >> 8) as f32 / (1u32 << 24) as f32
    };
    let (mut hits, mut redone, mut shrunk) = (0, 0, 0);
    for i in 0..20000 {
        let mut tris = Vec::new();
        for id in 0..8 {
            let mut v = [0; 3].map(|_| Vec3::new(next(), next(), next()) * 4.0 - 2.0);
            if id % 4 == 3 && next() < 0.3 {
                v[2] = v[1]; // degenerate
            }
            tris.push((v, id));
        }
        let (na, nb) = (4, 1 + (next() * 4.0) as usize);
        let a = Triangle4::new(&tris[..na]);
        let b = Triangle4::new(&tris[4..4 + nb]);
        let target = tris[(next() * 8.0) as usize % (4 + nb)].0;
        let (b1, b2) = match (next() * 3.0) as u32 {
            0 => (0.0, next()),
            1 => (1.0, 0.0),
            _ => (next() * 0.6, next() * 0.4),
        };
        let aim = target[0] * (1.0 - b1 - b2) + target[1] * b1 + target[2] * b2;
        let o = Vec3::new(next(), next(), next()) * 8.0 - 4.0;
        let d = if i % 500 == 0 {
            Vec3::new(f32::NAN, 1.0, 0.0)
        } else {
            aim - o
        };
        if d.length_squared() == 0.0 {
            continue;
        }
        let ray = Ray::new(o, d.normalize());
        let s4 = RayShear::new(&ray);
        let t_max = if next() < 0.2 {
            next() * 8.0
        } else {
            f32::INFINITY
        };
        // SAFETY: checked above that the CPU has AVX2.
        let h = unsafe { Triangle4::intersect_pair_avx2(&a, &b, &s4, t_max) };
        for (half, p) in [(0, &a), (1, &b)] {
            let want = p.intersect(&s4, t_max);
            let (mask, redo) = ((h.mask >> (4 * half)) & 0xf, (h.redo >> (4 * half)) & 0xf);
            assert_eq!((mask, redo), (want.mask, want.redo), "ray {i} half {half}");
            for lane in 0..4 {
                if mask & (1 << lane) == 0 {
                    continue;
                }
                let k = 4 * half + lane;
                let got = [h.t[k], h.b1[k], h.b2[k]].map(f32::to_bits);
                let exp = [want.t[lane], want.b1[lane], want.b2[lane]].map(f32::to_bits);
                assert_eq!(got, exp, "ray {i} lane {k}");
                hits += 1;
                // A smaller t_max, as the first packet's hits leave it for the second.
                let t2 = h.t[k] * (0.5 + next());
                let again = p.intersect(&s4, t2).mask & (1 << lane) != 0;
                assert_eq!(
                    h.ts[k] < t2 * h.det_abs[k],
                    again,
                    "ray {i} lane {k} at {t2}"
                );
                shrunk += again as u32;
            }
            redone += redo.count_ones();
        }
    }
    assert!(
        hits > 5000 && shrunk > 1000,
        "too few hits ({hits}, {shrunk})"
    );
    assert!(
        redone > 100,
        "edge and vertex cases not exercised ({redone})"
    );
}

/// One BVH leaf of two 4-triangle packets (so, on AVX2 CPUs, the two-packet test inside the
/// traversal, `Triangle4::intersect_pair_avx2`; elsewhere the packet-by-packet loop): the four
/// halves of a 2×2 square (cut along either diagonal), each twice, each triangle at its own
/// height; and the same 8 again 10 units away (obvhs merges no leaves in a tree of fewer than
/// 10 primitives). Every box of a group is its square, so the builder keeps each group in one
/// leaf (asserted through `Bvh::triangle_leaves`). Rays straight down through the diagonals, the sides and the
/// corners make edge functions exactly zero (the redo lanes, tested one by one) in both
/// packets at once, and which triangle is nearest then depends on each packet's lanes being its
/// own; oblique random rays cover the plain lanes. Six orders of the heights, so the nearest
/// triangle falls in either packet and in different lanes. The BVH must give brute force's
/// nearest distance and occlusion answer for each ray, with this CPU's code and the portable
/// code.
///
/// Tolerance: exact (the same primitive code on both sides; the heights differ, so the nearest
/// triangle is unique and its t decides it). Broken on purpose, giving the second packet the
/// first's redo lanes in the two-packet leaf (`redo_closest(.., b, h.redo & 0xf, ..)`), it fails.
#[test]
fn bvh_matches_brute_force_in_a_two_packet_leaf_at_different_depths() {
    let halves = [
        [(0.0, 0.0), (2.0, 0.0), (0.0, 2.0)],
        [(2.0, 0.0), (2.0, 2.0), (0.0, 2.0)],
        [(0.0, 0.0), (2.0, 0.0), (2.0, 2.0)],
        [(0.0, 0.0), (2.0, 2.0), (0.0, 2.0)],
    ];
    let orders: [[usize; 8]; 6] = [
        [0, 1, 2, 3, 4, 5, 6, 7],
        [7, 6, 5, 4, 3, 2, 1, 0],
        [3, 1, 6, 0, 7, 5, 2, 4],
        [4, 2, 5, 7, 0, 6, 1, 3],
        [1, 7, 0, 5, 2, 4, 3, 6],
        [6, 0, 4, 2, 5, 3, 7, 1],
    ];
    let mut rays = Vec::new();
    let mut rng = Pcg32::new(7, 11);
    for dx in [0.0, 10.0] {
        // Straight down on a 9×9 lattice over the square: its sides, diagonals and corners.
        for i in 0..9 {
            for j in 0..9 {
                let (x, y) = (dx + 0.25 * i as f32, 0.25 * j as f32);
                rays.push(Ray::new(Vec3::new(x, y, 3.0), -Vec3::Z));
            }
        }
        for _ in 0..1000 {
            let (x, y) = (0.1 + 1.8 * rng.next_f32(), 0.1 + 1.8 * rng.next_f32());
            let target = Vec3::new(dx + x, y, 0.15);
            let from = Vec3::new(rng.next_f32() - 0.5, rng.next_f32() - 0.5, 1.0).normalize();
            rays.push(Ray::new(target + from * 3.0, -from));
        }
    }
    for n in 0..orders.len() {
        let (mut positions, mut indices) = (Vec::new(), Vec::new());
        for (group, dx) in [(0, 0.0), (1, 10.0)] {
            for (k, &rank) in orders[(n + 3 * group) % 6].iter().enumerate() {
                // Heights 0.1 to 0.17: close, so no split of the leaf pays.
                let z = 0.1 + 0.01 * rank as f32;
                let first = positions.len() as u32;
                positions.extend(halves[k % 4].map(|(x, y)| Vec3::new(dx + x, y, z)));
                indices.push([first, first + 1, first + 2]);
            }
        }
        let mesh = Shape::Mesh(Mesh {
            positions,
            normals: vec![],
            uvs: vec![],
            indices,
            normal_map: None,
        });
        let p = prims(&[mesh]);
        let brute = Accel::build(p.clone(), AccelKind::BruteForce);
        for (code, bvh) in [
            ("this CPU's", Bvh::build(p.clone())),
            ("portable", Bvh::build(p.clone()).portable()),
        ] {
            assert_eq!(
                bvh.triangle_leaves(),
                vec![vec![4, 4]; 2],
                "order {n}: not two leaves of two full packets"
            );
            let mut hits = 0;
            for ray in &rays {
                let (a, b) = (bvh.intersect(ray), brute.intersect(ray));
                assert_eq!(
                    a.map(|h| h.hit.t.to_bits()),
                    b.map(|h| h.hit.t.to_bits()),
                    "order {n}, {code} code: ray from {} along {}: {a:?} against {b:?}",
                    ray.o,
                    ray.d
                );
                let occluded = bvh.occluded(ray);
                assert_eq!(occluded, brute.occluded(ray), "{} {}", ray.o, ray.d);
                hits += b.is_some() as u32;
            }
            // All 81 straight rays, and most oblique ones (those near the sides may pass beside).
            assert!(
                hits > 1800,
                "order {n}: the rays miss the leaves ({hits} hits)"
            );
        }
    }
}

/// A flat mesh's hits take the frame the scene keeps per triangle (`Scene::intersect`,
/// `Mesh::flat_surface`); they must carry exactly what `Shape::surface` computes at the same
/// barycentrics: point, error bound, normal, frame and uv bit for bit. The Cornell box (flat
/// rectangles and cubes with uvs) and a soup of flat triangles without uvs, 20,000 rays each
/// from random points in random directions (most meet the box, about 1,700 the soup).
/// Tolerance: none (the kept frame is the one `surface` builds).
#[test]
fn flat_mesh_hits_match_the_shapes_surface_bit_for_bit() {
    use prism::shape::PrimHit;
    let path = std::path::Path::new("scenes/cornell.ron");
    let text = std::fs::read_to_string(path).unwrap();
    let scene = prism::load::load_str(&text, path).unwrap().scene;
    let mut rng = Pcg32::new(5, 9);
    let soup = random_shapes(&mut rng, 300).remove(0);
    let Shape::Mesh(m) = &soup else { panic!() };
    assert!(m.uvs.is_empty() && m.is_flat());
    let (cam, mats) = (scene.camera.clone(), scene.materials.clone());
    let shapes = vec![soup.clone()];
    let soup_scene = prism::scene::Scene::new(
        cam,
        shapes,
        vec![0],
        vec![None],
        mats,
        vec![],
        AccelKind::Bvh,
    );
    for (name, scene, size, min) in [
        ("cornell", &scene, 1.0, 10000),
        ("soup", &soup_scene, 10.0, 1000),
    ] {
        let mut hits = 0;
        for _ in 0..20000 {
            let ray = Ray::new(v3(&mut rng, size), v3(&mut rng, 1.0).normalize_or(Vec3::X));
            let Some(si) = scene.intersect(&ray) else {
                continue;
            };
            let shape = &scene.shapes[si.shape as usize];
            let h = PrimHit {
                t: si.t,
                b1: si.bary.x,
                b2: si.bary.y,
            };
            let want = shape.surface(si.prim as usize, &ray, &h);
            let bits = |v: Vec3| v.to_array().map(f32::to_bits);
            let got = [si.p, si.p_error, si.ng, si.frame.s, si.frame.t, si.frame.n].map(bits);
            let exp = [
                want.p,
                want.p_error,
                want.ng,
                want.frame.s,
                want.frame.t,
                want.frame.n,
            ];
            assert_eq!(
                got,
                exp.map(bits),
                "{name}: shape {} triangle {}",
                si.shape,
                si.prim
            );
            assert_eq!(
                si.uv.to_array().map(f32::to_bits),
                want.uv.to_array().map(f32::to_bits)
            );
            hits += 1;
        }
        assert!(hits > min, "{name}: too few hits ({hits})");
    }
}
