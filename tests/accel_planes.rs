//! Rays in the planes of BVH boxes (issue 26). A ray with a zero direction component whose
//! origin lies exactly in a plane of a box once lost the box, and the triangle in it: the slab
//! distance there is (plane − o) · (1/d) = 0 · ∞ = NaN, and the tiny reciprocal that avoided
//! the NaN moved the ray off the plane to one side, so the box on the other side exited at t = 0.
//! Such rays are an orthographic camera looking along an axis at geometry on a grid, or an
//! axis-aligned shadow ray. Here: grids of triangles whose boxes' planes hold the rays' origins,
//! rays along every axis both ways with +0 and −0 in the other components, through the BVH
//! (the AVX2 node and leaf code this CPU runs, and the portable code of a CPU without it), the
//! instance level and the moving-shape level, against brute force; and a render of such a grid
//! through an orthographic camera whose pixel-centre rays run along the triangles' edges.
//!
//! Tolerance: exact. Both sides run the same triangle code, and every triangle lies at its own
//! depth, so the nearest hit is unique and its distance decides it.

use glam::{Mat4, Vec3};
use prism::accel::instances::Instances;
use prism::accel::moving::Moving;
use prism::accel::{Accel, AccelKind, BruteForce, Bvh, Prim};
use prism::math::Transform;
use prism::ray::Ray;
use prism::shape::{Instance, Mesh, Shape};
use std::sync::Arc;

/// A `n`×`n` grid of unit cells on the integer lattice, in the plane normal to axis `a`, two
/// triangles per cell, triangle k at depth 0.5 + k/64 along `a` (each its own vertices; a
/// depth an integer translation moves exactly, so instances match their flattened copies).
fn grid(a: usize, n: u32) -> Mesh {
    let (b, c) = ((a + 1) % 3, (a + 2) % 3);
    let mut mesh = Mesh::default();
    let point = |u: u32, v: u32, depth: f32| {
        let mut p = Vec3::ZERO;
        (p[a], p[b], p[c]) = (depth, u as f32, v as f32);
        p
    };
    for v in 0..n {
        for u in 0..n {
            let corners = [(u, v), (u + 1, v), (u + 1, v + 1), (u, v + 1)];
            for tri in [[0, 1, 2], [0, 2, 3]] {
                let depth = 0.5 + mesh.indices.len() as f32 / 64.0;
                let first = mesh.positions.len() as u32;
                let at = |k: usize| point(corners[k].0, corners[k].1, depth);
                mesh.positions.extend(tri.map(at));
                mesh.indices.push([first, first + 1, first + 2]);
            }
        }
    }
    mesh
}

fn prims(shapes: &[Shape]) -> Vec<Prim> {
    let mut out = Vec::new();
    for s in shapes {
        for i in 0..s.prim_count() {
            let geom = s.prim_geom(i);
            out.push(Prim {
                id: out.len() as u32,
                geom,
            });
        }
    }
    out
}

/// Rays along axis `a`, both ways, from every point of the lattice of half-integers in the
/// other two axes over [-0.5, n + 0.5] (integers: box planes), with +0 and −0 in the other
/// direction components; starting before, inside and behind the grid's depths along `a`.
fn axis_rays(a: usize, n: u32) -> Vec<Ray> {
    let (b, c) = ((a + 1) % 3, (a + 2) % 3);
    let mut rays = Vec::new();
    let steps = 2 * n + 3;
    for s in [1.0f32, -1.0] {
        for start in [-1.0f32, 0.5, 0.75, 3.0] {
            for (zb, zc) in [(0.0f32, 0.0f32), (-0.0, 0.0), (0.0, -0.0), (-0.0, -0.0)] {
                for i in 0..steps {
                    for j in 0..steps {
                        let (mut o, mut d) = (Vec3::ZERO, Vec3::ZERO);
                        (o[a], o[b], o[c]) = (start, i as f32 * 0.5 - 0.5, j as f32 * 0.5 - 0.5);
                        (d[a], d[b], d[c]) = (s, zb, zc);
                        rays.push(Ray::new(o, d));
                    }
                }
            }
        }
    }
    rays
}

/// `fast` (closest distance, occlusion) against `brute` on `rays`; returns the hits.
fn agree(
    what: &str,
    rays: &[Ray],
    fast: impl Fn(&Ray) -> (Option<f32>, bool),
    brute: &BruteForce,
) -> usize {
    let mut hits = 0;
    for ray in rays {
        let want = (brute.intersect(ray).map(|h| h.hit.t), brute.occluded(ray));
        let got = fast(ray);
        assert_eq!(
            (got.0.map(f32::to_bits), got.1),
            (want.0.map(f32::to_bits), want.1),
            "{what}: ray from {} along {:?}: {got:?} against brute force's {want:?}",
            ray.o,
            ray.d.to_array()
        );
        hits += want.0.is_some() as usize;
    }
    hits
}

/// The BVH, with this CPU's code and with the portable code, along every axis.
#[test]
fn bvh_meets_triangles_along_box_planes_on_every_axis() {
    for a in 0..3 {
        let shapes = [Shape::Mesh(grid(a, 4))];
        let p = prims(&shapes);
        let brute = BruteForce::new(p.clone());
        let rays = axis_rays(a, 4);
        for (name, bvh) in [
            ("this CPU's BVH code", Bvh::build(p.clone())),
            ("the portable BVH code", Bvh::build(p.clone()).portable()),
        ] {
            let fast = |r: &Ray| (bvh.intersect(r).map(|h| h.hit.t), bvh.occluded(r));
            let hits = agree(&format!("{name}, axis {a}"), &rays, fast, &brute);
            // Rays starting before the grid (or behind, going back) over its 5×5 lattice points
            // and 4×4 cells: 2 · 2 · 4 · 81 at least.
            assert!(hits >= 1296, "{name}, axis {a}: only {hits} hits");
        }
        // Through `Accel` as the renderer builds it.
        let accel = Accel::build(p, AccelKind::Bvh);
        let fast = |r: &Ray| (accel.intersect(r).map(|h| h.hit.t), accel.occluded(r));
        agree(&format!("Accel, axis {a}"), &rays, fast, &brute);
    }
}

/// Instances of one grid, each carried by a cyclic permutation of the axes (exact: entries
/// 0 and 1; cyclic, so the triangle test's axis order maps too) and an integer translation, so
/// world rays along each axis are object rays along the grid's normal in the bottom level's box
/// planes; brute force gets the flattened copies.
#[test]
fn instances_meet_triangles_along_box_planes() {
    let mesh = Arc::new(grid(2, 4));
    let cycle = |k: usize| {
        let e = [Vec3::X, Vec3::Y, Vec3::Z];
        // Object axis i goes to world axis (i + k) % 3.
        Mat4::from_cols(
            e[k % 3].extend(0.0),
            e[(k + 1) % 3].extend(0.0),
            e[(k + 2) % 3].extend(0.0),
            glam::Vec4::W,
        )
    };
    let mut list = Vec::new();
    for k in 0..3 {
        for (dx, dy) in [(0.0, 0.0), (4.0, 0.0), (0.0, 4.0)] {
            let m = Mat4::from_translation(Vec3::new(dx, dy, 0.0)) * cycle(k);
            list.push(Instance {
                mesh: mesh.clone(),
                to_world: Transform::from_matrix(m).unwrap(),
                negate_normals: false,
                swap_winding: false,
            });
        }
    }
    let indexed: Vec<(u32, &Instance)> = (0..).zip(&list).collect();
    let inst = Instances::build(&indexed).unwrap();
    let flat: Vec<Shape> = list.iter().map(|i| Shape::Mesh(i.flatten())).collect();
    let brute = BruteForce::new(prims(&flat));
    for a in 0..3 {
        let rays = axis_rays(a, 8);
        let fast = |r: &Ray| (inst.intersect(r).map(|h| h.1.hit.t), inst.occluded(r));
        let hits = agree(&format!("instances, axis {a}"), &rays, fast, &brute);
        assert!(hits > 1000, "instances, axis {a}: only {hits} hits");
    }
}

/// A still shape on the moving-shape level (its own bottom level under the top-level tree).
#[test]
fn moving_shapes_meet_triangles_along_box_planes() {
    for a in 0..3 {
        let shapes = [Shape::Mesh(grid(a, 4))];
        let moving = Moving::build(
            vec![(0, &shapes[0], prism::motion::Motion::still())],
            0.0,
            1.0,
        )
        .unwrap();
        let brute = BruteForce::new(prims(&shapes));
        let fast = |r: &Ray| {
            let hit = moving.intersect(r, r.t_max, &shapes).map(|h| h.t);
            (hit, moving.occluded(r))
        };
        let hits = agree(&format!("moving, axis {a}"), &axis_rays(a, 4), fast, &brute);
        assert!(hits >= 1296, "moving, axis {a}: only {hits} hits");
    }
}

/// An orthographic camera looking straight down -z at a grid whose triangle edges (every
/// one: the cells' sides and diagonals) lie on pixel-centre rays: film 8×8 over 8×8 scene
/// units, pixel centres at half-integers, the grid's 3×3 cells of 2 units from -3.5 to 2.5,
/// each triangle at its own height. The depth layer (pixel-centre rays) and every other
/// channel must be brute force's, bit for bit, with the scalar integrator and at every packet
/// width this CPU runs: in particular no pixel shows the background where brute force shows
/// the grid.
#[test]
fn orthographic_render_along_grid_edges_matches_brute_force() {
    let dir = std::env::temp_dir().join(format!("prism_accel_planes_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut obj = String::new();
    let mut k = 0;
    for v in 0..3 {
        for u in 0..3 {
            let (x, y) = (-3.5 + 2.0 * u as f32, -3.5 + 2.0 * v as f32);
            let c = [(x, y), (x + 2.0, y), (x + 2.0, y + 2.0), (x, y + 2.0)];
            for tri in [[0, 1, 2], [0, 2, 3]] {
                let z = 0.05 * k as f32;
                for i in tri {
                    obj += &format!("v {} {} {z}\n", c[i].0, c[i].1);
                }
                obj += &format!("f {} {} {}\n", 3 * k + 1, 3 * k + 2, 3 * k + 3);
                k += 1;
            }
        }
    }
    std::fs::write(dir.join("grid.obj"), obj).unwrap();
    let scene = |accel: &str| {
        format!(
            r#"(
    camera: (model: Orthographic(width: 8), to_world: [LookAt(origin: (0, 0, 5), target: (0, 0, 0), up: (0, 1, 0))]),
    film: (width: 8, height: 8, filter: Box()),
    sampler: (spp: 2, seed: 3),
    spectral: (wavelengths: 4),
    aovs: ["depth"],
    accel: {accel},
    materials: {{ "white": Diffuse(reflectance: Constant(0.5)) }},
    shapes: [(shape: Mesh(path: "grid.obj"), material: "white")],
    emitters: [Constant(radiance: Constant(1.0))],
)"#
        )
    };
    let load = |accel: &str| prism::load::load_str(&scene(accel), &dir.join("s.ron")).unwrap();
    let (mut bvh, mut brute) = (load("Bvh"), load("BruteForce"));
    use prism::integrator::packet::{self, Simd};
    let widths = [(Simd::Off, 0), (Simd::W1, 1), (Simd::W4, 4), (Simd::W8, 8)];
    let widths = widths.into_iter().chain([(Simd::W16, 16)]);
    let mut background = None;
    for (simd, w) in widths.filter(|&(_, w)| w == 0 || packet::runs(w)) {
        let w = if w == 0 {
            "off".to_string()
        } else {
            w.to_string()
        };
        bvh.settings.simd = simd;
        brute.settings.simd = simd;
        let (a, b) = (channels(&bvh), channels(&brute));
        let depth = |c: &[(String, Vec<u32>)]| {
            let z = c.iter().find(|(n, _)| n == "depth.Z");
            let z = z.unwrap_or_else(|| panic!("no depth channel in {c:?}"));
            z.1.iter()
                .filter(|v| f32::from_bits(**v).is_infinite())
                .count()
        };
        let (empty, want) = (depth(&a), depth(&b));
        assert_eq!(
            empty, want,
            "--simd {w}: {empty} background pixels against brute force's {want}"
        );
        for ((name, x), (_, y)) in a.iter().zip(&b) {
            let i = x.iter().zip(y).position(|(p, q)| p != q);
            assert_eq!(
                i, None,
                "--simd {w}: channel {name} differs from brute force"
            );
        }
        background = Some(want);
    }
    // The grid covers 6 of the 8 pixel columns and rows (7 with its far edges).
    assert_eq!(
        background,
        Some(64 - 49),
        "the grid should cover 7×7 pixel centres"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// Every channel's bits, rendered on one thread.
fn channels(job: &prism::load::Job) -> Vec<(String, Vec<u32>)> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let r = pool.install(|| prism::pipeline::render(job, 1.0, &|_| {}));
    let film = &r.film;
    let floats = film.channels.iter().map(|c| {
        let bits = c.data.iter().map(|v| v.to_bits()).collect();
        (c.name.clone(), bits)
    });
    let uints = film.uint_channels.iter();
    floats
        .chain(uints.map(|c| (c.name.clone(), c.data.clone())))
        .collect()
}
