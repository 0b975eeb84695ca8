//! Chi-square goodness-of-fit tests of the light tracer's emission samplers: the histogram of
//! many sampled light-path origins (directional light: points on the disks facing the light),
//! directions (environment map: its bright cells) or both (area light: a point on it and a
//! direction into the targets' cones) against the density the sampler reports, integrated
//! numerically over each histogram cell. Cells expecting < 5 samples are pooled.
//!
//! Tolerance: each test passes if its p-value exceeds α = 1e-4 / TESTS (Bonferroni), and the
//! density the sampler reports at each sample must match the density the histogram is tested
//! against (relative 1e-3, f32 rounding), so a warp error fails the χ² and a pdf error the
//! match. Seeds are fixed, so a pass is reproducible.

use super::*;
use crate::emitter::EnvMap;
use crate::math::chi2::chi2_test;
use crate::math::portable;
use crate::math::rng::Pcg32;
use crate::math::Frame;
use crate::spectrum::Spectrum;
use crate::texture::RgbImage;
use glam::Mat3;
use std::f64::consts::PI;

const TESTS: usize = 3;
const ALPHA: f64 = 1e-4 / TESTS as f64;

fn assert_pass(name: &str, (p, stat, dof): (f64, f64, usize)) {
    eprintln!("{name}: p = {p:.3e}, chi2 {stat:.1}, dof {dof}");
    assert!(
        p > ALPHA,
        "{name}: chi-square {stat:.1} with {dof} dof, p = {p:.3e} < α = {ALPHA:.2e}"
    );
}

/// A `Caustics` with no sources (the emission samplers take theirs as arguments) and `targets`
/// (center, radius).
fn caustics(targets: &[(Vec3, f32)]) -> Caustics<'static> {
    let areas: Vec<f32> = targets
        .iter()
        .map(|t| std::f32::consts::PI * t.1 * t.1)
        .collect();
    Caustics {
        sources: Vec::new(),
        targets: targets
            .iter()
            .map(|&(center, radius)| Target { center, radius })
            .collect(),
        by_area: Distribution1D::new(&areas),
        total_area: areas.iter().sum(),
        center: Vec3::ZERO,
        radius: 10.0,
        settings: CausticSettings::default(),
    }
}

/// Directional light: light-path origins, projected on the plane facing the light, must be
/// distributed as the union of the targets' disks weighted by how many disks cover each point
/// (Σ of uniform densities on each disk by its area share) = covering / total area, which is
/// also the density the sampler reports through its throughput total_area / covering.
#[test]
fn directional_light_origins_match_their_density() {
    // Two overlapping targets (their disks overlap seen from the light) and one apart.
    let targets = [
        (Vec3::new(0.0, 0.0, 0.0), 1.0),
        (Vec3::new(0.8, 0.3, 0.2), 0.6),
        (Vec3::new(-2.5, 0.0, 0.5), 0.3),
    ];
    let c = caustics(&targets);
    let dir = Vec3::new(0.3, -1.0, 0.2).normalize();
    let frame = Frame::from_normal(dir);
    let disks: Vec<(f64, f64, f64)> = targets
        .iter()
        .map(|&(p, r)| {
            let l = frame.to_local(p).as_dvec3();
            (l.x, l.y, r as f64)
        })
        .collect();
    let total: f64 = disks.iter().map(|d| PI * d.2 * d.2).sum();
    let density = |x: f64, y: f64| {
        disks
            .iter()
            .filter(|d| (x - d.0).powi(2) + (y - d.1).powi(2) <= d.2 * d.2)
            .count() as f64
            / total
    };
    let (x0, x1) = disks.iter().fold((f64::MAX, f64::MIN), |(lo, hi), d| {
        (lo.min(d.0 - d.2), hi.max(d.0 + d.2))
    });
    let (y0, y1) = disks.iter().fold((f64::MAX, f64::MIN), |(lo, hi), d| {
        (lo.min(d.1 - d.2), hi.max(d.1 + d.2))
    });
    const NB: usize = 40;
    const SUB: usize = 32;
    let n = 400_000;
    let (dx, dy) = ((x1 - x0) / NB as f64, (y1 - y0) / NB as f64);
    let mut observed = vec![0.0; NB * NB];
    let mut rng = Pcg32::new(0x5eed, 3);
    let mut u2 = || Vec2::new(rng.next_f32(), rng.next_f32());
    let mut worst = 0.0f64;
    for _ in 0..n {
        let (ray, beta) = c
            .emit_from_infinity::<1>(dir, Spectrum([1.0]), 1.0, &mut u2)
            .expect("a light path");
        assert!((ray.d - dir).length() < 1e-6);
        let l = frame.to_local(ray.o).as_dvec3();
        // The reported density (throughput = 1 / density for unit radiance and pdf_dir = 1);
        // points within f32 rounding of a disk's edge may count one disk more or fewer.
        let (reported, expected) = (1.0 / beta[0] as f64, density(l.x, l.y));
        let edge = disks
            .iter()
            .any(|d| (((l.x - d.0).powi(2) + (l.y - d.1).powi(2)).sqrt() - d.2).abs() < 1e-4);
        if !edge {
            worst = worst.max((reported / expected - 1.0).abs());
        }
        let ix = (((l.x - x0) / dx) as usize).min(NB - 1);
        let iy = (((l.y - y0) / dy) as usize).min(NB - 1);
        observed[iy * NB + ix] += 1.0;
    }
    assert!(
        worst < 1e-3,
        "reported density off the union-of-disks density by {worst:.3e} (relative)"
    );
    let mut expected = vec![0.0; NB * NB];
    for iy in 0..NB {
        for ix in 0..NB {
            let mut s = 0.0;
            for sy in 0..SUB {
                for sx in 0..SUB {
                    let x = x0 + (ix as f64 + (sx as f64 + 0.5) / SUB as f64) * dx;
                    let y = y0 + (iy as f64 + (sy as f64 + 0.5) / SUB as f64) * dy;
                    s += density(x, y);
                }
            }
            expected[iy * NB + ix] = n as f64 * s * dx * dy / (SUB * SUB) as f64;
        }
    }
    assert_pass("directional disks", chi2_test(&observed, &expected));
}

/// Environment map: directions from its bright cells (a 3×3-pixel sun on a dim sky) must be
/// distributed as the map's own sampling density `EnvMap::pdf` restricted to those cells and
/// renormalised; the sampler's reported pdf must equal that density. Bins in (1 − cos θ, φ)
/// around the sun, over the cap that holds every bright cell.
#[test]
fn environment_bright_cells_match_their_density() {
    let (w, h) = (32, 16);
    let img = RgbImage {
        width: w,
        height: h,
        pixels: (0..h)
            .flat_map(|j| (0..w).map(move |i| (i, j)))
            .map(|(i, j): (usize, usize)| {
                let sun = (9..12).contains(&i) && (4..7).contains(&j);
                [if sun { 1000.0 } else { 1.0 }; 3]
            })
            .collect(),
        source: None,
    };
    let map = EnvMap::new(&img, 1.0, Mat3::IDENTITY);
    let cells = map.bright_cells(10.0).expect("bright cells");
    let bright = |d: Vec3| cells.contains(map.cell(d));
    let dense = |d: Vec3| if bright(d) { map.pdf(d) as f64 } else { 0.0 };
    // The sun's axis (pixel centres: u = (i + 0.5) / w, v = (j + 0.5) / h, the map's layout
    // with local = (sin φ sin θ, cos θ, −cos φ sin θ)).
    let (th, ph) = (PI * 5.5 / h as f64, 2.0 * PI * 10.5 / w as f64);
    let axis = Vec3::new(
        (portable::sin(ph) * portable::sin(th)) as f32,
        portable::cos(th) as f32,
        (-portable::cos(ph) * portable::sin(th)) as f32,
    );
    let frame = Frame::from_normal(axis);
    let dir = |omc: f64, phi: f64| {
        let ct = 1.0 - omc;
        let st = (1.0 - ct * ct).max(0.0).sqrt();
        frame.to_world(Vec3::new(
            (st * portable::cos(phi)) as f32,
            (st * portable::sin(phi)) as f32,
            ct as f32,
        ))
    };
    // The cap holding every bright cell, found on a fine grid over the whole sphere.
    let mut span = 0.0f64;
    for a in 0..800 {
        for b in 0..800 {
            let omc = 2.0 * (a as f64 + 0.5) / 800.0;
            if omc > span && bright(dir(omc, 2.0 * PI * (b as f64 + 0.5) / 800.0)) {
                span = omc;
            }
        }
    }
    let span = (span * 1.1).min(2.0);
    const NT: usize = 24;
    const NP: usize = 48;
    const SUB: usize = 12;
    let n = 400_000;
    let (dt, dp) = (span / NT as f64, 2.0 * PI / NP as f64);
    let mut mass = vec![0.0; NT * NP];
    for it in 0..NT {
        for ip in 0..NP {
            let mut s = 0.0;
            for a in 0..SUB {
                for b in 0..SUB {
                    let omc = (it as f64 + (a as f64 + 0.5) / SUB as f64) * dt;
                    let phi = (ip as f64 + (b as f64 + 0.5) / SUB as f64) * dp;
                    s += dense(dir(omc, phi));
                }
            }
            mass[it * NP + ip] = s * dt * dp / (SUB * SUB) as f64;
        }
    }
    // The bright cells' share of the map's sampling probability.
    let p_bright: f64 = mass.iter().sum();
    let mut observed = vec![0.0; NT * NP];
    let mut rng = Pcg32::new(0x5eed, 5);
    let mut ratios = (f64::MAX, f64::MIN);
    for _ in 0..n {
        let u = Vec2::new(rng.next_f32(), rng.next_f32());
        let Some((d, pdf)) = map.sample_bright(&cells, u) else {
            continue;
        };
        let r = pdf as f64 * p_bright / map.pdf(d) as f64;
        ratios = (ratios.0.min(r), ratios.1.max(r));
        let l = frame.to_local(d).as_dvec3();
        let omc = (l.x * l.x + l.y * l.y) / (1.0 + l.z);
        assert!(omc <= span, "a sample outside the bright cells' cap");
        let it = ((omc / dt) as usize).min(NT - 1);
        let ip = ((portable::atan2(l.y, l.x).rem_euclid(2.0 * PI) / dp) as usize).min(NP - 1);
        observed[it * NP + ip] += 1.0;
    }
    // Midpoint integration of a piecewise-constant density: its total is good to ~0.5%.
    assert!(
        ratios.0 > 0.995 && ratios.1 < 1.005,
        "reported pdf / (EnvMap::pdf / P(bright)) in [{:.4}, {:.4}], not 1",
        ratios.0,
        ratios.1
    );
    let expected: Vec<f64> = mass.iter().map(|m| m / p_bright * n as f64).collect();
    assert_pass("environment bright cells", chi2_test(&observed, &expected));
}

/// Area light: a light path's origin is uniform on the light and its direction is drawn from
/// the union of the targets' cones seen from that origin (each cone chosen by its 1 − cos θ),
/// so the joint density is 1/A · covering(p, d) / (2π Σ (1 − cos θᵢ(p))). The histogram is
/// joint: the light's four quadrants × (1 − cos θ, φ) bins around its normal; the expected
/// mass of each bin integrates that density over a grid of points in the quadrant and of
/// directions in the bin. Two targets' cones overlap (the count matters) and a third lies
/// off-axis; every cone lies in the light's front hemisphere, so no sample is refused.
#[test]
fn area_light_points_and_directions_match_their_density() {
    // A 1 × 1 light at y = 2 facing down (Mitsuba's rectangle spans [−1, 1]², normal +z).
    let text = r#"(
        camera: (fov: 40, to_world: [LookAt(origin: (0, 1, 6), target: (0, 0, 0), up: (0, 1, 0))]),
        film: (width: 4, height: 4),
        shapes: [
            (shape: Rectangle, emitter: (radiance: Constant(1)),
             to_world: [Scale((0.5, 0.5, 1)), Rotate(axis: (1, 0, 0), angle: 90), Translate((0, 2, 0))]),
        ],
    )"#;
    let job = crate::load::load_str(text, std::path::Path::new("area_chi2.ron")).unwrap();
    let scene = &job.scene;
    let light = scene
        .emitters
        .iter()
        .find_map(|e| match e {
            Emitter::Area(l) => Some(l),
            _ => None,
        })
        .expect("the area light");
    let targets = [
        (Vec3::new(0.0, 0.0, 0.0), 0.6),
        (Vec3::new(0.5, 0.1, 0.3), 0.4),
        (Vec3::new(-1.2, 0.3, -0.4), 0.3),
    ];
    let c = caustics(&targets);
    let area = 1.0f64;
    let density = |p: [f64; 3], d: [f64; 3]| {
        let (mut total, mut covering) = (0.0, 0usize);
        for &(t, r) in &targets {
            let v = [t.x as f64 - p[0], t.y as f64 - p[1], t.z as f64 - p[2]];
            let l2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
            let s2 = (r as f64).powi(2) / l2;
            let omc = s2 / (1.0 + (1.0 - s2).sqrt());
            total += omc;
            let cos = (v[0] * d[0] + v[1] * d[1] + v[2] * d[2]) / l2.sqrt();
            if 1.0 - cos <= omc {
                covering += 1;
            }
        }
        covering as f64 / (2.0 * PI * total) / area
    };
    let frame = Frame::from_normal(Vec3::NEG_Y);
    let dir = |omc: f64, phi: f64| {
        let ct = 1.0 - omc;
        let st = (1.0 - ct * ct).max(0.0).sqrt();
        let w = frame.to_world(Vec3::new(
            (st * portable::cos(phi)) as f32,
            (st * portable::sin(phi)) as f32,
            ct as f32,
        ));
        [w.x as f64, w.y as f64, w.z as f64]
    };
    // 1 − cos 70°: beyond every cone from every point of the light (the off-axis target's
    // cone reaches ~52° from the normal). Integration grid: 16² points per quadrant and 12²
    // directions per bin; at 24² and 24² the five bins farthest from their expectation moved
    // by under 1%, well under their Poisson spread: the test is not limited by integration.
    let span = 1.0 - portable::cos((70.0f64).to_radians());
    const NT: usize = 16;
    const NP: usize = 32;
    const SUB: usize = 12;
    const SUBP: usize = 16;
    let n = 600_000;
    let (dt, dp) = (span / NT as f64, 2.0 * PI / NP as f64);
    let quadrant = |x: f64, z: f64| (x >= 0.0) as usize + 2 * (z >= 0.0) as usize;
    let bin = |q: usize, it: usize, ip: usize| (q * NT + it) * NP + ip;
    let mut expected = vec![0.0; 4 * NT * NP];
    for q in 0..4 {
        let (x0, z0) = (0.5 * (q & 1) as f64 - 0.5, 0.5 * (q >> 1) as f64 - 0.5);
        for a in 0..SUBP {
            for b in 0..SUBP {
                let p = [
                    x0 + 0.5 * (a as f64 + 0.5) / SUBP as f64,
                    2.0,
                    z0 + 0.5 * (b as f64 + 0.5) / SUBP as f64,
                ];
                // This point's share of the light's area: (0.5 / SUBP)².
                let w_p = (0.5 / SUBP as f64).powi(2);
                for it in 0..NT {
                    for ip in 0..NP {
                        let mut s = 0.0;
                        for i in 0..SUB {
                            for j in 0..SUB {
                                let omc = (it as f64 + (i as f64 + 0.5) / SUB as f64) * dt;
                                let phi = (ip as f64 + (j as f64 + 0.5) / SUB as f64) * dp;
                                s += density(p, dir(omc, phi));
                            }
                        }
                        expected[bin(q, it, ip)] +=
                            n as f64 * w_p * s * dt * dp / (SUB * SUB) as f64;
                    }
                }
            }
        }
    }
    let wl = crate::spectrum::WavelengthSampler::new(
        crate::spectrum::WavelengthSampling::Uniform,
        360.0,
        830.0,
    )
    .sample::<1>(0.37);
    let le = light.radiance.eval(Vec2::ZERO, &wl)[0] as f64;
    let mut rng = Pcg32::new(0x5eed, 7);
    let mut u2 = || Vec2::new(rng.next_f32(), rng.next_f32());
    let mut observed = vec![0.0; 4 * NT * NP];
    let mut worst = 0.0f64;
    for _ in 0..n {
        let (ray, beta) = c
            .emit_from_area::<1>(scene, light, &wl, &mut u2)
            .expect("every cone lies in the light's front hemisphere");
        let (o, d) = (ray.o.as_dvec3(), ray.d.normalize().as_dvec3());
        assert!((o.y - 2.0).abs() < 1e-4 && o.x.abs() <= 0.5 + 1e-4 && o.z.abs() <= 0.5 + 1e-4);
        // Throughput = Le cos / (pdf_area pdf_dir): the reported joint density. Directions
        // within f32 rounding of a cone's edge may count one cone more or fewer.
        let reported = le * (-d.y) / beta[0] as f64;
        let on_edge = targets.iter().any(|&(t, r)| {
            let v = t.as_dvec3() - o;
            let s2 = (r as f64).powi(2) / v.length_squared();
            let omc = s2 / (1.0 + (1.0 - s2).sqrt());
            (1.0 - v.normalize().dot(d) - omc).abs() < 1e-4
        });
        if !on_edge {
            let e = density([o.x, o.y, o.z], [d.x, d.y, d.z]);
            worst = worst.max((reported / e - 1.0).abs());
        }
        let l = frame.to_local(ray.d.normalize()).as_dvec3();
        let omc = (l.x * l.x + l.y * l.y) / (1.0 + l.z);
        assert!(omc <= span, "a direction outside every cone");
        let it = ((omc / dt) as usize).min(NT - 1);
        let ip = ((portable::atan2(l.y, l.x).rem_euclid(2.0 * PI) / dp) as usize).min(NP - 1);
        observed[bin(quadrant(o.x, o.z), it, ip)] += 1.0;
    }
    assert!(
        worst < 1e-3,
        "reported density off the cone-union density by {worst:.3e} (relative)"
    );
    let total: f64 = expected.iter().sum();
    assert!(
        (total / n as f64 - 1.0).abs() < 5e-3,
        "the expected histogram holds {:.4} of the samples: the density does not integrate to 1",
        total / n as f64
    );
    assert_pass("area light cones", chi2_test(&observed, &expected));
}
