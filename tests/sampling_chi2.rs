//! Chi-square goodness-of-fit tests of every sampling routine: the histogram of many samples
//! must match the routine's own pdf, integrated over each histogram cell.
//!
//! Tolerance: each test passes if its p-value exceeds α = 1% / (number of tests in this file)
//! (Šidák correction), so the file as a whole has a 1% false-alarm rate. Seeds are fixed, so a
//! pass is reproducible; a wrong pdf or warp gives p-values of ~0 at these sample counts.

mod common;

use common::{alpha, chi2_test, receiver};
use glam::{Vec2, Vec3};
use prism::emitter::EnvMap;
use prism::filter::{Filter, FilterConfig};
use prism::math::portable;
use prism::math::rng::Pcg32;
use prism::math::{sampling, Frame};
use prism::spectrum::{WavelengthSampler, WavelengthSampling, Wavelengths};
use prism::texture::RgbImage;
use std::f32::consts::PI;
use std::path::Path;

// One per `assert_pass` call that runs (loops count each case).
const TESTS: usize = 20;

fn assert_pass(name: &str, (p, stat, dof): (f64, f64, usize)) {
    let a = alpha(TESTS);
    eprintln!("{name}: p = {p:.3e}, chi2 {stat:.1}, dof {dof}");
    assert!(
        p > a,
        "{name}: chi-square {stat:.1} with {dof} dof, p = {p:.3e} < α = {a:.2e}"
    );
}

/// Bins unit directions by (1 − cos θ, φ) around `axis`, for 1 − cos θ in [0, span], and compares
/// the counts of `n` samples with the integral of `pdf` (solid angle) over each cell.
/// 1 − cos θ is computed as sin²θ / (1 + cos θ), which stays accurate for tiny cones.
fn chi2_directions(
    sample: impl FnMut(&mut Pcg32) -> Option<Vec3>,
    pdf: impl Fn(Vec3) -> f64,
    axis: Vec3,
    span: f64,
    n: usize,
) -> (f64, f64, usize) {
    chi2_directions_sub(sample, pdf, axis, span, n, 12)
}

/// As `chi2_directions`, integrating the pdf over each cell with `sub`² midpoint samples (more
/// for pdfs with many discontinuities, such as a piecewise-constant environment map).
fn chi2_directions_sub(
    mut sample: impl FnMut(&mut Pcg32) -> Option<Vec3>,
    pdf: impl Fn(Vec3) -> f64,
    axis: Vec3,
    span: f64,
    n: usize,
    sub: usize,
) -> (f64, f64, usize) {
    const NT: usize = 24;
    const NP: usize = 48;
    let frame = Frame::from_normal(axis);
    let mut rng = Pcg32::new(0x5eed, 17);
    let mut observed = vec![0.0; NT * NP];
    let d_omc = span / NT as f64;
    for _ in 0..n {
        let Some(d) = sample(&mut rng) else { continue };
        let l = frame.to_local(d.normalize()).as_dvec3();
        let sin2 = l.x * l.x + l.y * l.y;
        let omc = if l.z > 0.0 {
            sin2 / (1.0 + l.z)
        } else {
            1.0 - l.z
        };
        // f32 rounding of the warp's inputs allows a 0.1% overshoot.
        assert!(
            omc <= span * (1.0 + 1e-3) + 1e-12,
            "a sample at 1 − cos θ = {omc} lies outside the tested region ({span})"
        );
        let it = ((omc / d_omc) as usize).min(NT - 1);
        let phi = portable::atan2(l.y, l.x).rem_euclid(2.0 * std::f64::consts::PI);
        let ip = ((phi / (2.0 * std::f64::consts::PI) * NP as f64) as usize).min(NP - 1);
        observed[it * NP + ip] += 1.0;
    }
    let mut expected = vec![0.0; NT * NP];
    let dphi = 2.0 * std::f64::consts::PI / NP as f64;
    for it in 0..NT {
        for ip in 0..NP {
            let mut sum = 0.0;
            for a in 0..sub {
                for b in 0..sub {
                    let omc = (it as f64 + (a as f64 + 0.5) / sub as f64) * d_omc;
                    let phi = (ip as f64 + (b as f64 + 0.5) / sub as f64) * dphi;
                    let s = (omc * (2.0 - omc)).max(0.0).sqrt();
                    let local =
                        glam::DVec3::new(s * portable::cos(phi), s * portable::sin(phi), 1.0 - omc);
                    let d = frame.to_world(local.as_vec3()).normalize();
                    sum += pdf(d);
                }
            }
            // Cell solid angle = Δ(1 − cos θ) · Δφ.
            expected[it * NP + ip] = sum / (sub * sub) as f64 * d_omc * dphi * n as f64;
        }
    }
    if std::env::var("CHI2_DEBUG").is_ok() {
        for i in 0..NT * NP {
            if (observed[i] - expected[i]).abs() > 4.0 * expected[i].sqrt().max(2.0) {
                eprintln!(
                    "cell t{} p{}: observed {} expected {:.1}",
                    i / NP,
                    i % NP,
                    observed[i],
                    expected[i]
                );
            }
        }
    }
    // Cells the pdf integration saw as empty can catch a few samples at the light's silhouette
    // (the sub-samples missed a sliver of it); they are pooled, but must hold almost nothing.
    let stray: f64 = observed
        .iter()
        .zip(&expected)
        .filter(|(_, &e)| e == 0.0)
        .map(|(o, _)| o)
        .sum();
    assert!(
        stray <= 1e-3 * n as f64,
        "{stray} samples landed where the pdf is zero"
    );
    let (o, e): (Vec<f64>, Vec<f64>) = observed
        .iter()
        .zip(&expected)
        .filter(|(_, &e)| e > 0.0)
        .unzip();
    chi2_test(&o, &e)
}

fn u2(rng: &mut Pcg32) -> Vec2 {
    Vec2::new(rng.next_f32(), rng.next_f32())
}

#[test]
fn cosine_hemisphere() {
    let r = chi2_directions(
        |rng| Some(sampling::square_to_cosine_hemisphere(u2(rng))),
        |d| sampling::cosine_hemisphere_pdf(d.z) as f64,
        Vec3::Z,
        1.0,
        300_000,
    );
    assert_pass("cosine hemisphere", r);
}

#[test]
fn uniform_sphere() {
    let r = chi2_directions(
        |rng| Some(sampling::square_to_uniform_sphere(u2(rng))),
        |_| sampling::UNIFORM_SPHERE_PDF as f64,
        Vec3::Z,
        2.0,
        300_000,
    );
    assert_pass("uniform sphere", r);
}

#[test]
fn uniform_cones_wide_and_narrow() {
    for cos_max in [0.3f32, 0.9999] {
        let r = chi2_directions(
            |rng| Some(sampling::square_to_uniform_cone(u2(rng), cos_max)),
            |d| {
                if d.z >= cos_max {
                    sampling::uniform_cone_pdf(cos_max) as f64
                } else {
                    0.0
                }
            },
            Vec3::Z,
            1.0 - cos_max as f64,
            300_000,
        );
        assert_pass(&format!("cone cos_max={cos_max}"), r);
    }
}

#[test]
fn uniform_triangle_barycentrics() {
    // Cells of the unit square in (b1, b2); the triangle b1 + b2 ≤ 1 covers the lower cells
    // fully and the diagonal cells by half.
    let k = 32;
    let n = 400_000;
    let mut obs = vec![0.0; k * k];
    let mut rng = Pcg32::new(5, 5);
    for _ in 0..n {
        let b = sampling::square_to_triangle(u2(&mut rng));
        assert!(b.x >= 0.0 && b.y >= 0.0 && b.x + b.y <= 1.0 + 1e-6);
        let (i, j) = (
            ((b.x * k as f32) as usize).min(k - 1),
            ((b.y * k as f32) as usize).min(k - 1),
        );
        obs[i * k + j] += 1.0;
    }
    let exp: Vec<f64> = (0..k * k)
        .map(|c| {
            let (i, j) = (c / k, c % k);
            let frac = if i + j + 1 < k {
                1.0
            } else if i + j + 1 == k {
                0.5
            } else {
                0.0
            };
            frac / (k * k) as f64 / 0.5 * n as f64
        })
        .collect();
    assert_pass("triangle", chi2_test(&obs, &exp));
}

#[test]
fn concentric_disk_is_uniform() {
    // Equal-area polar cells: r² in k rings, φ in k sectors.
    let k = 24;
    let n = 300_000;
    let mut obs = vec![0.0; k * k];
    let mut rng = Pcg32::new(6, 6);
    for _ in 0..n {
        let p = sampling::square_to_disk_concentric(u2(&mut rng));
        let r2 = p.length_squared();
        assert!(r2 <= 1.0 + 1e-6);
        let i = ((r2 * k as f32) as usize).min(k - 1);
        let j = ((portable::atan2(p.y, p.x).rem_euclid(2.0 * PI) / (2.0 * PI) * k as f32) as usize)
            .min(k - 1);
        obs[i * k + j] += 1.0;
    }
    let exp = vec![n as f64 / (k * k) as f64; k * k];
    assert_pass("concentric disk", chi2_test(&obs, &exp));
}

#[test]
fn wavelength_sampling() {
    for (kind, lo, hi) in [
        (WavelengthSampling::Visible, 360.0, 830.0),
        (WavelengthSampling::Visible, 300.0, 1100.0),
        (WavelengthSampling::Uniform, 360.0, 830.0),
    ] {
        let s = WavelengthSampler::new(kind, lo, hi);
        let bins = 94;
        let n = 100_000;
        let mut obs = vec![0.0; bins];
        let mut rng = Pcg32::new(7, 7);
        let w = (hi - lo) / bins as f32;
        for _ in 0..n {
            // Every lane has the same marginal distribution; test all four.
            let wl: Wavelengths<4> = s.sample(rng.next_f32());
            for &l in &wl.lambda {
                obs[(((l - lo) / w) as usize).min(bins - 1)] += 1.0;
            }
        }
        let exp: Vec<f64> = (0..bins)
            .map(|b| {
                let (a, c) = (lo + b as f32 * w, lo + (b + 1) as f32 * w);
                // Integrate the pdf (not the CDF) so the test checks pdf against the warp.
                let m = 64;
                let mass: f64 = (0..m)
                    .map(|i| s.pdf(a + (i as f32 + 0.5) * (c - a) / m as f32) as f64)
                    .sum::<f64>()
                    * (c - a) as f64
                    / m as f64;
                mass * 4.0 * n as f64
            })
            .collect();
        assert_pass(
            &format!("wavelengths {kind:?} {lo}-{hi}"),
            chi2_test(&obs, &exp),
        );
    }
}

/// Checks an emitter's `sample_li` against its `pdf_li_hit`, in directions from `p`.
fn check_emitter(name: &str, shapes_ron: &str, p: Vec3, axis: Vec3, span: f64) {
    let text =
        format!("(film: (width: 4, height: 4), shapes: [{shapes_ron}], outputs: (bands: 0))");
    let job = prism::load::load_str(&text, Path::new("inline.ron")).unwrap();
    let scene = &job.scene;
    let wl: Wavelengths<4> =
        WavelengthSampler::new(WavelengthSampling::Visible, 360.0, 830.0).sample(0.3);
    let si = receiver(p);
    let em = &scene.emitters[0];
    let r = chi2_directions(
        |rng| em.sample_li(&si, u2(rng), &wl, &scene.shapes).map(|s| s.wi),
        |d| match scene.intersect(&prism::ray::Ray::new(p, d)) {
            Some(hit) if scene.shape_emitter[hit.shape as usize] == Some(0) => {
                em.pdf_li_hit(p, &hit, &scene.shapes) as f64
            }
            _ => 0.0,
        },
        axis,
        span,
        300_000,
    );
    assert_pass(name, r);
}

#[test]
fn rectangle_emitter_sampling() {
    // A 2×1 rectangle 1 unit above, tilted; its front side faces the receiver.
    check_emitter(
        "rectangle emitter",
        "(shape: Rectangle, emitter: (radiance: Constant(1)), to_world: [Scale((1, 0.5, 1)), Rotate(axis: (1, 0, 0), angle: 110), Translate((0.2, 1, 0))])",
        Vec3::ZERO,
        Vec3::new(0.2, 1.0, 0.0).normalize(),
        0.8,
    );
}

#[test]
fn mesh_emitter_with_unequal_triangles() {
    // A cube light (12 triangles, 6 faces of equal area but hit from different angles) seen
    // from close by, so several faces show.
    check_emitter(
        "cube emitter",
        "(shape: Cube, emitter: (radiance: Constant(1)), to_world: [Scale((0.5, 0.2, 0.3)), Rotate(axis: (1, 1, 0), angle: 30), Translate((0.3, 1.2, 0.1))])",
        Vec3::ZERO,
        Vec3::new(0.3, 1.2, 0.1).normalize(),
        0.4,
    );
}

#[test]
fn disk_emitter_sampling() {
    check_emitter(
        "disk emitter",
        "(shape: Disk, emitter: (radiance: Constant(1)), to_world: [Scale((0.8, 0.4, 1)), Rotate(axis: (1, 0, 0), angle: 100), Translate((0, 1, 0.3))])",
        Vec3::ZERO,
        Vec3::new(0.0, 1.0, 0.3).normalize(),
        0.7,
    );
}

/// 1 − cos θmax of a sphere of radius r seen from distance d, in f64 (the test region then ends
/// exactly at the cone's edge, so no ring of cells straddles it).
fn cone_span(r: f64, d: f64) -> f64 {
    let sin2 = (r / d) * (r / d);
    sin2 / (1.0 + (1.0 - sin2).sqrt())
}

#[test]
fn sphere_emitter_from_outside_and_inside() {
    // Outside: sampling the subtended cone, wide and tiny.
    check_emitter(
        "sphere emitter (outside, near)",
        "(shape: Sphere(center: (0, 2, 0), radius: 1.2), emitter: (radiance: Constant(1)))",
        Vec3::ZERO,
        Vec3::Y,
        cone_span(1.2, 2.0),
    );
    check_emitter(
        "sphere emitter (outside, tiny)",
        "(shape: Sphere(center: (0, 5, 0), radius: 0.01), emitter: (radiance: Constant(1)))",
        Vec3::ZERO,
        Vec3::Y,
        cone_span(0.01, 5.0),
    );
    // Inside, normals flipped so the inside emits: uniform area sampling.
    check_emitter(
        "sphere emitter (inside)",
        "(shape: Sphere(center: (0, 0.3, 0), radius: 1), flip_normals: true, emitter: (radiance: Constant(1)))",
        Vec3::ZERO,
        Vec3::Y,
        2.0,
    );
}

#[test]
fn gaussian_filter_importance_sampling() {
    let f = Filter::new(&FilterConfig::Gaussian { stddev: 0.5 });
    let r = f.radius();
    let bins = 64;
    let n = 200_000;
    let mut obs = vec![0.0; bins];
    let mut rng = Pcg32::new(9, 9);
    for _ in 0..n {
        let o = f.sample(u2(&mut rng));
        assert!(o.x.abs() <= r && o.y.abs() <= r);
        obs[(((o.x + r) / (2.0 * r) * bins as f32) as usize).min(bins - 1)] += 1.0;
    }
    // Mitsuba's kernel: exp(−x²/2σ²) − exp(−r²/2σ²), clamped at 0, integrated per bin.
    let kernel =
        |x: f64| (portable::exp(-x * x / 0.5) - portable::exp(-(r as f64).powi(2) / 0.5)).max(0.0);
    let m = 256;
    let mass: Vec<f64> = (0..bins)
        .map(|b| {
            (0..m)
                .map(|i| {
                    kernel(
                        -r as f64
                            + 2.0 * r as f64 * (b as f64 + (i as f64 + 0.5) / m as f64)
                                / bins as f64,
                    )
                })
                .sum::<f64>()
        })
        .collect();
    let total: f64 = mass.iter().sum();
    let exp: Vec<f64> = mass.iter().map(|v| v / total * n as f64).collect();
    assert_pass("gaussian filter", chi2_test(&obs, &exp));
}

/// A 64×33 sky (any size suits `EnvMap` itself; scene files must be 2:1): a gradient from a bright horizon to a deeper zenith, a dim ground, and a sun
/// (a Gaussian blob 30× the sky, σ ≈ 4°) at 40° elevation; in the map's own frame (+y up).
fn sky_image() -> RgbImage {
    let (w, h) = (64, 33);
    let sun = {
        let (t, p) = (50f32.to_radians(), 1.1f32);
        Vec3::new(
            portable::sin(p) * portable::sin(t),
            portable::cos(t),
            -portable::cos(p) * portable::sin(t),
        )
    };
    let pixels = (0..h)
        .flat_map(|j| (0..w).map(move |i| (i, j)))
        .map(|(i, j)| {
            let theta = PI * j as f32 / (h - 1) as f32;
            let phi = 2.0 * PI * (i as f32 + 0.5) / w as f32;
            let d = Vec3::new(
                portable::sin(phi) * portable::sin(theta),
                portable::cos(theta),
                -portable::cos(phi) * portable::sin(theta),
            );
            let sky = if d.y >= 0.0 {
                let t = 1.0 - d.y;
                [0.2 + 0.6 * t, 0.35 + 0.5 * t, 0.9]
            } else {
                [0.05, 0.04, 0.03]
            };
            let a = portable::acos(d.dot(sun).clamp(-1.0, 1.0));
            let blob = 30.0 * portable::exp(-0.5 * (a / 4f32.to_radians()).powi(2));
            sky.map(|c| c + blob)
        })
        .collect();
    RgbImage {
        width: w,
        height: h,
        pixels,
        source: None,
    }
}

/// Environment-map sampling against `pdf` (the density MIS uses), over the whole sphere, with
/// the map in its own frame and rotated.
#[test]
fn envmap_sampling() {
    let img = sky_image();
    let rotation = glam::Mat3::from_mat4(prism::math::rotation::axis_angle(
        Vec3::new(0.3, 1.0, -0.6).normalize(),
        2.0,
    ));
    for (name, m) in [
        ("envmap", glam::Mat3::IDENTITY),
        ("envmap rotated", rotation),
    ] {
        let map = EnvMap::new(&img, 1.0, m);
        let r = chi2_directions_sub(
            |rng| map.sample(u2(rng)).map(|(d, _)| d),
            |d| map.pdf(d) as f64,
            Vec3::new(0.2, 1.0, 0.1).normalize(),
            2.0,
            300_000,
            48,
        );
        assert_pass(name, r);
    }
}

/// The first emitter of a scene with only `emitter_ron`.
fn lone_emitter(emitter_ron: &str) -> prism::emitter::Emitter {
    let text =
        format!("(film: (width: 4, height: 4), emitters: [{emitter_ron}], outputs: (bands: 0))");
    let job = prism::load::load_str(&text, Path::new("inline.ron")).unwrap();
    job.scene.emitters[0].clone()
}

/// A spot light is a delta light: `sample_li` from a point has nothing random to test. What can
/// be wrong is the angular profile it emits, so that is tested as a distribution: directions
/// drawn uniformly over the sphere are kept with probability I(d)/I_max, the fraction of the
/// peak intensity `sample_li` delivers at unit distance along d, which makes the kept directions
/// distributed as the emitted intensity. They must match the profile Mitsuba's `spot` defines
/// (1 within the beam, (cutoff − θ)/(cutoff − beam) in the transition, 0 beyond) about the
/// `to_world` axis, normalised analytically: ∫ profile dω = 2π [1 − (sin c − sin b)/(c − b)]
/// (2π (1 − cos c) for a hard edge, b = c). The region tested reaches 10% past the cutoff in
/// 1 − cos θ, and no kept direction may lie beyond it: nothing leaks outside the cone.
#[test]
fn spot_emission_profile() {
    let (origin, target) = (Vec3::new(0.4, 2.0, -0.3), Vec3::new(-0.5, 0.0, 0.6));
    let axis = (target - origin).normalize();
    for (name, cutoff, beam) in [
        ("spot profile", 30.0f64, 20.0f64),
        ("spot profile, hard edge", 12.0, 12.0),
    ] {
        let spot = lone_emitter(&format!(
            "Spot(intensity: Constant(1), cutoff_angle: {cutoff}, beam_width: {beam}, \
             to_world: [LookAt(origin: ({}, {}, {}), target: ({}, {}, {}), up: (0, 1, 0))])",
            origin.x, origin.y, origin.z, target.x, target.y, target.z
        ));
        let (c, b) = (cutoff.to_radians(), beam.to_radians());
        let norm = if c > b {
            2.0 * std::f64::consts::PI * (1.0 - (portable::sin(c) - portable::sin(b)) / (c - b))
        } else {
            2.0 * std::f64::consts::PI * (1.0 - portable::cos(c))
        };
        let profile = |d: Vec3| {
            let t = portable::acos((d.as_dvec3().dot(axis.as_dvec3())).clamp(-1.0, 1.0));
            if t >= c {
                0.0
            } else if t <= b {
                1.0
            } else {
                (c - t) / (c - b)
            }
        };
        let wl = Wavelengths::<1> {
            lambda: [550.0],
            pdf: [1.0],
        };
        let r = chi2_directions(
            |rng| loop {
                let d = sampling::square_to_uniform_sphere(u2(rng));
                // A receiver at unit distance along d: L = I(d) / 1².
                let si = receiver(origin + d);
                let keep = spot
                    .sample_li(&si, u2(rng), &wl, &[])
                    .map_or(0.0, |s| s.radiance[0]);
                if rng.next_f32() < keep {
                    return Some(d);
                }
            },
            |d| profile(d) / norm,
            axis,
            1.1 * (1.0 - portable::cos(c)),
            200_000,
        );
        assert_pass(name, r);
    }
}

/// A directional light is a delta in direction: `sample_li` must return, from every point, the
/// same direction (towards the light) with pdf 1 and the `delta` flag, and the light must be
/// invisible to escaping rays (no radiance, no pdf), so MIS never counts it twice. There is no
/// distribution to fit, so this is checked exactly rather than with a chi-square test.
#[test]
fn directional_sampling_is_a_single_direction() {
    let light = lone_emitter("Directional(irradiance: Constant(2), direction: (1, -2, 0.5))");
    assert!(!light.is_environment());
    let to_light = -Vec3::new(1.0, -2.0, 0.5).normalize();
    let wl = Wavelengths::<1> {
        lambda: [600.0],
        pdf: [1.0],
    };
    let mut rng = Pcg32::new(9, 9);
    for _ in 0..1000 {
        let p = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 20.0 - 10.0;
        let s = light
            .sample_li(&receiver(p), u2(&mut rng), &wl, &[])
            .unwrap();
        assert!(s.wi.abs_diff_eq(to_light, 1e-6), "{} at {p}", s.wi);
        assert!(s.delta && s.pdf == 1.0 && s.radiance[0] == 2.0);
        assert!(s.shadow.d.normalize().abs_diff_eq(s.wi, 1e-6));
        assert_eq!(light.pdf_li_env(to_light), 0.0);
        assert_eq!(light.le_env(to_light, &wl)[0], 0.0);
    }
}
