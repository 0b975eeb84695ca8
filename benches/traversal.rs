//! Ray throughput of prism's acceleration backends on the same mesh and the same rays.
//!
//!     cargo bench --bench traversal                        # prism's BVH only
//!     cargo bench --bench traversal --features embree     # BVH and Embree
//!     cargo bench --bench traversal --features embree -- --quick
//!     cargo bench --bench traversal -- --tris 20000 --rays 262144
//!
//! Meshes: the bumpy sphere of tools/bench/make_mesh.py (same construction, generated here so
//! the bench needs no files) at about 20 thousand and 1 million triangles. Rays, generated once
//! and given to every backend: primary rays from a pinhole camera (coherent), diffuse-bounce
//! rays leaving the primary hits with cosine-distributed directions (incoherent; spawned with
//! prism's own offsets), and shadow rays from the bounce origins to a point light (`occluded`).
//! Backends: prism's BVH, Embree as prism uses it (Embree's traversal, prism's triangle test
//! confirming each candidate), and Embree with its own triangle test only (the filter's cost).
//! Reported: build time, and Mrays/s on one thread and on all threads (rayon), best of 3. The
//! hit count of each set is printed too: backends must agree on it (a cheap sanity check; the
//! exact comparison is tests/accel.rs).

use glam::{Vec2, Vec3};
use prism::accel::{Accel, AccelKind, Prim};
use prism::math::portable;
use prism::math::rng::Pcg32;
use prism::math::{sampling, Frame};
use prism::ray::{spawn, Ray};
use prism::shape::{Mesh, Shape};
use rayon::prelude::*;
use std::f32::consts::PI;
use std::time::Instant;

/// A latitude-longitude sphere displaced by a few sine octaves (as tools/bench/make_mesh.py).
fn bumpy_sphere(triangles: usize) -> Mesh {
    let nv = ((triangles as f64 / 4.0).sqrt().ceil() as usize + 1).max(4);
    let nu = 2 * nv;
    let mut m = Mesh::default();
    for i in 0..=nv {
        let th = PI * i as f32 / nv as f32;
        for j in 0..nu {
            let ph = 2.0 * PI * j as f32 / nu as f32;
            // Exact poles (sin π is not 0 in floats), so each pole's row of vertices coincides.
            let n = match i {
                0 => Vec3::Y,
                _ if i == nv => -Vec3::Y,
                _ => Vec3::new(
                    portable::sin(th) * portable::cos(ph),
                    portable::cos(th),
                    portable::sin(th) * portable::sin(ph),
                ),
            };
            let bump = portable::sin(th)
                * (0.06 * portable::sin(7.0 * th) * portable::cos(5.0 * ph)
                    + 0.03 * portable::sin(23.0 * th + 1.0) * portable::sin(19.0 * ph)
                    + 0.012 * portable::cos(71.0 * th) * portable::sin(67.0 * ph + 0.5));
            m.positions.push(n * (1.0 + bump));
        }
    }
    let at = |i: usize, j: usize| (i * nu + j % nu) as u32;
    for i in 0..nv {
        for j in 0..nu {
            let (a, b, c, d) = (at(i, j), at(i, j + 1), at(i + 1, j), at(i + 1, j + 1));
            if i > 0 {
                m.indices.push([a, b, c]);
            }
            if i + 1 < nv {
                m.indices.push([b, d, c]);
            }
        }
    }
    m
}

struct RaySets {
    primary: Vec<Ray>,
    bounce: Vec<Ray>,
    shadow: Vec<Ray>,
}

/// Rays for `mesh`, traced with `reference` to place the secondary ones.
fn make_rays(mesh: &Mesh, reference: &Accel, n: usize) -> RaySets {
    let side = (n as f32).sqrt() as usize;
    let eye = Vec3::new(0.0, 0.4, 3.0);
    let cam = Frame::from_normal((Vec3::ZERO - eye).normalize());
    let tan = portable::tan((20.0f32).to_radians());
    let mut rng = Pcg32::new(7, 3);
    let mut primary = Vec::with_capacity(side * side);
    for y in 0..side {
        for x in 0..side {
            let sx = ((x as f32 + rng.next_f32()) / side as f32 * 2.0 - 1.0) * tan;
            let sy = ((y as f32 + rng.next_f32()) / side as f32 * 2.0 - 1.0) * tan;
            primary.push(Ray::new(
                eye,
                cam.to_world(Vec3::new(sx, sy, 1.0)).normalize(),
            ));
        }
    }
    let light = Vec3::new(2.0, 3.0, 2.0);
    let (mut bounce, mut shadow) = (Vec::new(), Vec::new());
    for r in &primary {
        let Some(h) = reference.intersect(r) else {
            continue;
        };
        let s = mesh.surface(h.prim as usize, h.hit.b1, h.hit.b2);
        let n = if s.ng.dot(r.d) < 0.0 { s.ng } else { -s.ng };
        let u = Vec2::new(rng.next_f32(), rng.next_f32());
        let d = Frame::from_normal(n).to_world(sampling::square_to_cosine_hemisphere(u));
        bounce.push(spawn(s.p, s.p_error, n, d));
        shadow.push(prism::ray::spawn_to(
            s.p,
            s.p_error,
            n,
            light,
            Vec3::ZERO,
            None,
        ));
    }
    RaySets {
        primary,
        bounce,
        shadow,
    }
}

/// Embree without the filter that applies prism's triangle test: what that exactness costs.
#[cfg(feature = "embree")]
fn unfiltered_embree(prims: &[Prim]) -> Option<(String, Accel, f64)> {
    let t = Instant::now();
    let a = Accel::Embree(prism::accel::Embree::build_with(prims.to_vec(), false));
    Some((
        "Embree, its own triangle test".into(),
        a,
        t.elapsed().as_secs_f64(),
    ))
}

#[cfg(not(feature = "embree"))]
fn unfiltered_embree(_: &[Prim]) -> Option<(String, Accel, f64)> {
    None
}

/// Best of 3 of tracing every ray; returns (Mrays/s, number of hits).
fn throughput(rays: &[Ray], parallel: bool, trace: impl Fn(&Ray) -> bool + Sync) -> (f64, usize) {
    let mut best = f64::INFINITY;
    let mut hits = 0;
    for _ in 0..3 {
        let t = Instant::now();
        hits = if parallel {
            rays.par_chunks(4096)
                .map(|c| c.iter().filter(|r| trace(r)).count())
                .sum()
        } else {
            rays.iter().filter(|r| trace(r)).count()
        };
        best = best.min(t.elapsed().as_secs_f64());
    }
    (rays.len() as f64 / best / 1e6, hits)
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let (mut sizes, mut n_rays) = if quick {
        (vec![20_000usize], 1 << 14)
    } else {
        (vec![20_000, 1_000_000], 1 << 20)
    };
    // `--tris N` and `--rays N` override the sizes (for quick experiments).
    let args: Vec<String> = std::env::args().collect();
    for w in args.windows(2) {
        let n = || w[1].parse::<usize>().expect("a number after --tris/--rays");
        match w[0].as_str() {
            "--tris" => sizes = vec![n()],
            "--rays" => n_rays = n(),
            _ => {}
        }
    }
    let kinds = [
        AccelKind::Bvh,
        #[cfg(feature = "embree")]
        AccelKind::Embree,
    ];
    println!(
        "traversal benchmark: {} threads available, {n_rays} primary rays{}",
        rayon::current_num_threads(),
        if quick { " (--quick)" } else { "" }
    );
    println!("| triangles | backend | build s | ray set | rays | hits | Mrays/s 1 thread | Mrays/s all threads |");
    println!("|---|---|---|---|---|---|---|---|");
    for &size in &sizes {
        let mesh = bumpy_sphere(size);
        let shape = Shape::Mesh(mesh.clone());
        let prims: Vec<Prim> = (0..shape.prim_count())
            .map(|i| Prim {
                id: i as u32,
                geom: shape.prim_geom(i),
            })
            .collect();
        let built: Vec<(String, Accel, f64)> = kinds
            .iter()
            .map(|&k| {
                let t = Instant::now();
                let a = Accel::build(prims.clone(), k);
                (format!("{k:?}"), a, t.elapsed().as_secs_f64())
            })
            .chain(unfiltered_embree(&prims))
            .collect();
        let rays = make_rays(&mesh, &built[0].1, n_rays);
        for (kind, accel, build_s) in &built {
            let sets: [(&str, &[Ray], bool); 3] = [
                ("primary", &rays.primary, false),
                ("diffuse bounce", &rays.bounce, false),
                ("shadow (occluded)", &rays.shadow, true),
            ];
            for (name, set, occlusion) in sets {
                let trace = |r: &Ray| {
                    if occlusion {
                        accel.occluded(r)
                    } else {
                        accel.intersect(r).is_some()
                    }
                };
                let (one, hits) = throughput(set, false, trace);
                let (all, _) = throughput(set, true, trace);
                println!(
                    "| {} | {kind} | {build_s:.3} | {name} | {} | {hits} | {one:.2} | {all:.2} |",
                    mesh.indices.len(),
                    set.len()
                );
            }
        }
    }
}
