//! Tests of the watertight triangle test (`shape::triangle`) and its 4-lane form.

use super::*;
use crate::math::portable;

#[test]
fn hits_inside_misses_outside() {
    let tri = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
    ];
    let r = Ray::new(Vec3::new(0.25, 0.25, 1.0), -Vec3::Z);
    let h = intersect(&RayShear::new(&r), f32::INFINITY, &tri).unwrap();
    assert!((h.t - 1.0).abs() < 1e-6);
    assert!((h.b1 - 0.25).abs() < 1e-6 && (h.b2 - 0.25).abs() < 1e-6);
    let miss = Ray::new(Vec3::new(0.75, 0.75, 1.0), -Vec3::Z);
    assert!(intersect(&RayShear::new(&miss), f32::INFINITY, &tri).is_none());
    assert!(
        intersect(&RayShear::new(&r), 0.5, &tri).is_none(),
        "beyond t_max"
    );
    let behind = Ray::new(Vec3::new(0.25, 0.25, 1.0), Vec3::Z);
    assert!(intersect(&RayShear::new(&behind), f32::INFINITY, &tri).is_none());
}

/// Rays leaving a point of a large, rotated triangle (interpolated from its vertices, so off
/// its plane by rounding) must not re-hit it: their t would be pure rounding error.
#[test]
fn no_self_hits_leaving_a_rotated_triangle() {
    let rot = crate::math::rotation::quat(Vec3::new(1.0, 0.3, -0.2).normalize(), 1.3);
    let tri = [
        rot * Vec3::new(-4.0, -4.0, 0.0),
        rot * Vec3::new(4.0, -4.0, 0.0),
        rot * Vec3::new(4.0, 4.0, 0.0),
    ];
    let n = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalize();
    let mut state = 7u32;
    let mut next = || {
        state = state.wrapping_mul(747796405).wrapping_add(2891336453);
        (state >> 8) as f32 / (1u32 << 24) as f32
    };
    let mut self_hits = 0;
    for _ in 0..20000 {
        let (b1, b2) = (next() * 0.5, next() * 0.5);
        let p = tri[0] * (1.0 - b1 - b2) + tri[1] * b1 + tri[2] * b2;
        let z = 0.1 + 0.9 * next();
        let phi = std::f32::consts::TAU * next();
        let frame = crate::math::frame::Frame::from_normal(n);
        let r = (1.0 - z * z).sqrt();
        for side in [1.0f32, -1.0] {
            let d = frame.to_world(Vec3::new(
                r * portable::cos(phi),
                r * portable::sin(phi),
                z * side,
            ));
            let ray = Ray::new(p, d);
            if intersect(&RayShear::new(&ray), f32::INFINITY, &tri).is_some() {
                self_hits += 1;
            }
        }
    }
    assert_eq!(self_hits, 0, "rays re-hit the triangle they leave");
}

/// Every lane of the packet test agrees bit for bit with the scalar test, or is handed back
/// for it (`redo`, an edge function exactly zero). Rays aim at edges and vertices (where
/// rounding decides) as well as inside; some lanes are degenerate, some unused.
#[test]
fn packet_test_matches_scalar_test() {
    let mut state = 11u32;
    let mut next = || {
        state = state.wrapping_mul(747796405).wrapping_add(2891336453);
        (state >> 8) as f32 / (1u32 << 24) as f32
    };
    let (mut hits, mut redone) = (0, 0);
    for _ in 0..20000 {
        let mut tris = Vec::new();
        for id in 0..4 {
            let mut v = [0; 3].map(|_| Vec3::new(next(), next(), next()) * 4.0 - 2.0);
            if id == 3 && next() < 0.3 {
                v[2] = v[1]; // degenerate
            }
            tris.push((v, id));
        }
        let n = 1 + (next() * 4.0) as usize;
        let packet = Triangle4::new(&tris[..n]);
        let target = tris[(next() * n as f32) as usize % n].0;
        let (b1, b2) = match (next() * 3.0) as u32 {
            0 => (0.0, next()), // on an edge
            1 => (1.0, 0.0),    // at a vertex
            _ => (next() * 0.6, next() * 0.4),
        };
        let aim = target[0] * (1.0 - b1 - b2) + target[1] * b1 + target[2] * b2;
        // Origins sometimes on the target itself (rays leaving a surface).
        let o = if next() < 0.1 {
            aim
        } else {
            Vec3::new(next(), next(), next()) * 8.0 - 4.0
        };
        let d = if next() < 0.1 {
            Vec3::new(next(), next(), next()) - 0.5
        } else {
            aim - o
        };
        if d.length_squared() == 0.0 {
            continue;
        }
        let ray = Ray::new(o, d.normalize());
        let shear = RayShear::new(&ray);
        let t_max = if next() < 0.2 {
            next() * 4.0
        } else {
            f32::INFINITY
        };
        let h = packet.intersect(&shear, t_max);
        assert_eq!((h.mask | h.redo) >> n, 0, "an unused lane was hit");
        assert_eq!(h.mask & h.redo, 0);
        for (lane, (v, _)) in tris[..n].iter().enumerate() {
            let bit = 1 << lane;
            if h.redo & bit != 0 {
                redone += 1;
                continue;
            }
            let scalar = intersect(&shear, t_max, v);
            let packet = (h.mask & bit != 0).then(|| TriHit {
                t: h.t[lane],
                b1: h.b1[lane],
                b2: h.b2[lane],
            });
            assert_eq!(packet, scalar, "lane {lane} of {v:?}, ray {ray:?}");
            hits += scalar.is_some() as u32;
        }
    }
    assert!(hits > 5000, "too few hits ({hits}) to test anything");
    assert!(
        redone > 100,
        "edge and vertex cases not exercised ({redone})"
    );
}

#[test]
fn shared_edge_is_watertight() {
    // Two triangles sharing the diagonal of the unit square; rays along the diagonal must
    // hit one of them.
    let t1 = [
        Vec3::ZERO,
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
    ];
    let t2 = [
        Vec3::ZERO,
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
    ];
    for i in 0..1000 {
        let x = i as f32 / 1000.0 * 0.98 + 0.01;
        let r = Ray::new(
            Vec3::new(x, x, 3.0),
            Vec3::new(0.001, -0.002, -1.0).normalize(),
        );
        let s = RayShear::new(&r);
        let r2 = Ray::new(r.o - r.d * 0.0, r.d);
        let hit = intersect(&s, r2.t_max, &t1).is_some() || intersect(&s, r2.t_max, &t2).is_some();
        assert!(hit, "ray {i} leaked through the shared edge");
    }
}

/// The axis choice is the nested comparisons' (x against y, the winner against z, ties to the
/// later axis, NaN to z), with the swap for a negative z: checked on ties, signs, zeros and NaN.
#[test]
fn ray_shear_picks_the_axes_of_the_nested_comparisons() {
    use Axis::{X, Y, Z};
    let reference = |d: Vec3| {
        let a = d.abs();
        let kz = if a.x > a.y {
            if a.x > a.z {
                X
            } else {
                Z
            }
        } else if a.y > a.z {
            Y
        } else {
            Z
        };
        let neg = d.to_array()[kz as usize] < 0.0;
        let (kx, ky) = match (kz, neg) {
            (X, false) => (Y, Z),
            (Y, false) => (Z, X),
            (Z, false) => (X, Y),
            (X, true) => (Z, Y),
            (Y, true) => (X, Z),
            (Z, true) => (Y, X),
        };
        [kx, ky, kz]
    };
    let values = [0.0, -0.0, 1.0, -1.0, 2.0, -2.0, 0.5, f32::NAN];
    let mut seen = Vec::new();
    for &x in &values {
        for &y in &values {
            for &z in &values {
                let d = Vec3::new(x, y, z);
                let k = RayShear::new(&Ray::new(Vec3::ZERO, d)).k;
                assert_eq!(k, reference(d), "direction {d}");
                if !seen.contains(&k) {
                    seen.push(k);
                }
            }
        }
    }
    assert_eq!(seen.len(), 6, "every permutation is reached");
}
