//! Stability where methods fail: scale-robust ray offsets (no acne, no light leaks), the Monte
//! Carlo convergence rate, and the opt-in firefly clamp's bias. Figures print with
//! `cargo test --release --test stability -- --nocapture`.

use prism::film::Film;
use prism::integrator::{self, RenderStats};
use prism::math::portable;
use std::path::Path;

fn render(text: &str) -> (Film, RenderStats) {
    let job = prism::load::load_str(text, Path::new("inline.ron")).unwrap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    pool.install(|| integrator::render(&job.scene, &job.settings, &job.channels, &|_| {}))
}

/// The acceleration backends of this build: scale robustness must not depend on the backend.
fn backends() -> impl Iterator<Item = &'static str> {
    [
        "Bvh",
        #[cfg(feature = "embree")]
        "Embree",
    ]
    .into_iter()
}

fn mean(data: &[f32]) -> f64 {
    data.iter().map(|&v| v as f64).sum::<f64>() / data.len() as f64
}

/// The floor-and-black-sphere scene of render_analytic.rs at every scale from 1e-4 to 1e5: a
/// floor point receives ρ·L·(1 − F) with F = cos θ·(r/D)², whatever the scale. Self-intersection
/// (acne) darkens it, offsets too large for the scale brighten it (rays start past the sphere).
/// Tolerance 5 standard errors of the pixel mean.
#[test]
fn view_factor_at_every_scale() {
    let (x, z) = (0.8f64, 0.3f64);
    let d2 = x * x + z * z + 0.36;
    let expect = 0.5 * (1.0 - (0.6 / d2.sqrt()) * 0.36 / d2);
    for (kind, s) in backends().flat_map(|k| [1e-4f64, 1e-2, 1.0, 1e3, 1e5].map(|s| (k, s))) {
        let text = format!(
            r#"(
            camera: (fov: 2, near_clip: {}, far_clip: {}, to_world: [LookAt(origin: ({}, {}, {}), target: ({}, 0, {}), up: (0, 0, 1))]),
            film: (width: 8, height: 8, filter: Box()),
            sampler: (spp: 1024, seed: 4),
            integrator: (max_depth: 2),
            outputs: (bands: 0, rgb: false),
            materials: {{ "floor": Diffuse(reflectance: Constant(0.5)), "black": Diffuse(reflectance: Constant(0)) }},
            shapes: [
                (shape: Rectangle, material: "floor", to_world: [Scale(({f}, {f}, 1)), Rotate(axis: (1, 0, 0), angle: -90)]),
                (shape: Sphere(center: (0, {c}, 0), radius: {c}), material: "black"),
            ],
            emitters: [Constant(radiance: Constant(1.0))],
            accel: {kind},
        )"#,
            0.01 * s,
            1e4 * s,
            x * s,
            0.3 * s,
            z * s,
            x * s,
            z * s,
            f = 4.0 * s,
            c = 0.6 * s,
        );
        let (film, stats) = render(&text);
        let y = film.channel("Y").unwrap();
        let m = mean(y);
        let var = y.iter().map(|&v| (v as f64 - m).powi(2)).sum::<f64>() / (y.len() - 1) as f64;
        let se = (var / y.len() as f64).sqrt();
        println!("{kind} scale {s:e}: {m:.5} ± {se:.5} (expected {expect:.5})");
        assert_eq!(stats.invalid_samples, 0);
        assert!(
            (m - expect).abs() <= 5.0 * se + 1e-6,
            "{kind} scale {s:e}: {m} ± {se}, expected {expect}"
        );
    }
}

/// A closed cube (two-sided, so every wall scatters) under a bright environment, the camera
/// inside: any light inside leaked through a crack or past a badly offset ray. A sphere and a
/// thin rotated box inside add more surfaces to leave from.
///
/// Not exactly zero: a hit within rounding error of a cube edge is an f32 point, which can lie
/// up to half an ulp outside the neighbouring face's plane (the true point is inside), and a
/// ray leaving it away from that face never crosses it. About 3 in 100 000 ray segments leave
/// that way at every scale (1e-4 to 1e5 alike: the offsets scale with the scene); here that is
/// 1 to 3 escaping paths of 36 864, each adding about 1.3·10⁻⁵ of the outside radiance to the
/// image mean. pbrt and Mitsuba share this floor. Bound: the mean inside radiance ≤ 10⁻⁴ of
/// the outside's (8 such paths); a crack, or an offset too small or too large for the scale,
/// leaks orders of magnitude more (most paths escape).
#[test]
fn closed_box_leaks_no_light_at_any_scale() {
    for (kind, s) in backends().flat_map(|k| [1e-4f64, 1.0, 1e5].map(|s| (k, s))) {
        let text = format!(
            r#"(
            camera: (fov: 100, near_clip: {near}, far_clip: {far}, to_world: [LookAt(origin: (0, 0, {cam}), target: (0, 0, 0), up: (0, 1, 0))]),
            film: (width: 24, height: 24),
            sampler: (spp: 64, seed: 9),
            outputs: (bands: 0),
            materials: {{ "wall": Twosided(bsdf: Diffuse(reflectance: Constant(0.9))) }},
            shapes: [
                (shape: Cube, material: "wall", to_world: [Scale(({s}, {s}, {s})), Rotate(axis: (1, 1, 0), angle: 17)]),
                (shape: Sphere(center: (0, {sc}, 0), radius: {sr}), material: "wall"),
                (shape: Cube, material: "wall", to_world: [Scale(({tw}, {tw}, {tt})), Rotate(axis: (0, 1, 1), angle: 33)]),
            ],
            emitters: [Constant(radiance: Constant(1000.0))],
            accel: {kind},
        )"#,
            cam = 0.9 * s,
            near = 0.01 * s,
            far = 1e4 * s,
            sc = -0.5 * s,
            sr = 0.3 * s,
            tw = 0.5 * s,
            tt = 1e-3 * s,
        );
        let (film, stats) = render(&text);
        assert_eq!(stats.invalid_samples, 0);
        let y = film.channel("Y").unwrap();
        let lit = y.iter().filter(|&&v| v != 0.0).count();
        let leak = mean(y) / 1000.0;
        println!(
            "{kind} scale {s:e}: {lit} of {} pixels lit, mean inside/outside radiance {leak:.2e}",
            y.len()
        );
        assert!(
            leak <= 1e-4,
            "{kind} scale {s:e}: light leaks into the box ({leak:.2e} of outside)"
        );
    }
}

/// A diffuse sphere on a floor under an environment and a small area light, small enough to
/// render many times.
fn small_scene(kind: &str, spp: u32, seed: u64) -> String {
    format!(
        r#"(
        camera: (fov: 35, to_world: [LookAt(origin: (0, 1.3, 4), target: (0, 0.55, 0), up: (0, 1, 0))]),
        film: (width: 16, height: 12, filter: Box()),
        sampler: (kind: {kind}, spp: {spp}, seed: {seed}),
        integrator: (max_depth: 6),
        outputs: (bands: 0, rgb: false),
        materials: {{ "floor": Diffuse(reflectance: Constant(0.5)), "ball": Diffuse(reflectance: Rgb(0.2, 0.45, 0.8)) }},
        shapes: [
            (shape: Rectangle, material: "floor", to_world: [Scale((4, 4, 1)), Rotate(axis: (1, 0, 0), angle: -90)]),
            (shape: Sphere(center: (0, 0.6, 0), radius: 0.6), material: "ball"),
            (shape: Rectangle, emitter: (radiance: Scaled(8, Named("D65"))), to_world: [Scale((0.3, 0.3, 1)), Rotate(axis: (1, 0, 0), angle: 90), Translate((1, 2.5, 1))]),
        ],
        emitters: [Constant(radiance: Scaled(0.4, Named("D65")))],
    )"#
    )
}

/// MSE of a render at `spp`, estimated without a reference: for independent unbiased renders A
/// and B, E|A − B|² = 2 Var = 2 MSE. Averaged over `pairs` pairs and all pixels of Y.
fn mse(kind: &str, spp: u32, pairs: u64) -> f64 {
    let mut acc = 0.0;
    for p in 0..pairs {
        let a = render(&small_scene(kind, spp, 1000 + 2 * p)).0;
        let b = render(&small_scene(kind, spp, 1001 + 2 * p)).0;
        let (a, b) = (a.channel("Y").unwrap(), b.channel("Y").unwrap());
        acc += a
            .iter()
            .zip(b)
            .map(|(&x, &y)| (x as f64 - y as f64).powi(2))
            .sum::<f64>()
            / (2.0 * a.len() as f64);
    }
    acc / pairs as f64
}

/// Least-squares slope of log MSE against log spp.
fn slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (mx, my) = points.iter().fold((0.0, 0.0), |(a, b), &(x, y)| {
        (a + portable::ln(x) / n, b + portable::ln(y) / n)
    });
    let (num, den) = points.iter().fold((0.0, 0.0), |(a, b), &(x, y)| {
        let dx = portable::ln(x) - mx;
        (a + dx * (portable::ln(y) - my), b + dx * dx)
    });
    num / den
}

/// Independent sampling converges as 1/spp exactly (its samples are i.i.d.), so the log-log
/// slope of MSE against spp must be −1. Each MSE is a mean over 192 pixels × 6 pairs, so its
/// relative error is about √(2/1152) ≈ 4%; over two decades of spp that moves the fitted slope
/// by about ±0.02, and the tolerance ±0.1 (the issue's) is 5 of those. Sobol's (Owen-scrambled)
/// slope must be the rate the README claims for it, −1.25, within the same ±0.1 margin on the
/// side that matters (shallower fails; a steeper one is no defect): a Sobol sampler no better
/// than white noise (slope −1) fails by 2.5 margins.
#[test]
fn mse_falls_as_one_over_spp() {
    let spps = [4u32, 16, 64, 256];
    let mut slopes = Vec::new();
    for kind in ["Independent", "Sobol"] {
        let pts: Vec<(f64, f64)> = spps.iter().map(|&n| (n as f64, mse(kind, n, 6))).collect();
        let k = slope(&pts);
        println!("{kind}: MSE {pts:?}, log-log slope {k:.3}");
        slopes.push(k);
    }
    assert!(
        (slopes[0] + 1.0).abs() <= 0.1,
        "independent sampler slope {} (expected −1 ± 0.1)",
        slopes[0]
    );
    assert!(
        slopes[1] <= -1.25 + 0.1,
        "Sobol slope {} shallower than the −1.25 ± 0.1 claimed (independent: {})",
        slopes[1],
        slopes[0]
    );
}

/// The clamp is off by default (bit-identical to not mentioning it), and when on it darkens
/// the image: its bias is the energy it cuts, never negative. A tiny bright light makes
/// fireflies on the floor to clamp.
#[test]
fn clamp_is_opt_in_and_only_removes_energy() {
    let base =
        small_scene("Independent", 64, 3).replace("Scale((0.3, 0.3, 1))", "Scale((0.02, 0.02, 1))");
    let base = base.replace("Scaled(8, Named(\"D65\"))", "Scaled(1800, Named(\"D65\"))");
    let (plain, s0) = render(&base);
    let explicit = base.replace("max_depth: 6", "max_depth: 6, clamp: None");
    let (same, _) = render(&explicit);
    assert_eq!(
        plain.channels, same.channels,
        "clamp: None changed the image"
    );
    assert_eq!(s0.clamped_samples, 0);
    let (clamped, s1) = render(&base.replace("max_depth: 6", "max_depth: 6, clamp: 0.5"));
    let (a, b) = (
        mean(plain.channel("Y").unwrap()),
        mean(clamped.channel("Y").unwrap()),
    );
    println!(
        "clamp 0.5: {} of {} samples clamped, Y mean {b:.5} vs {a:.5} unclamped ({:+.2}%)",
        s1.clamped_samples,
        s1.samples,
        100.0 * (b / a - 1.0)
    );
    assert!(s1.clamped_samples > 0);
    assert!(b < a, "clamping did not darken the image");
    for (p, c) in plain
        .channel("Y")
        .unwrap()
        .iter()
        .zip(clamped.channel("Y").unwrap())
    {
        assert!(c <= p, "a clamped pixel is brighter: {c} > {p}");
    }
}

/// An index-matched smooth dielectric (IOR 1 inside and out) is invisible: the image equals
/// the scene without it within noise, tile by tile. Each side is 6 renders with independent
/// seeds; a pixel's noise is its spread across them, a tile's (8 × 8 pixels) the sum of its
/// pixels'. Tolerance |z| ≤ 4.5 over 12 tiles: a correct renderer exceeds it with probability
/// below 1e-4. An index of 1.02 (a sphere that reflects 0.01% at normal incidence and bends
/// light by ~1°) fails it.
#[test]
fn index_matched_sphere_is_invisible() {
    let worst = index_matched_worst_z("1.0");
    println!("index-matched sphere: largest tile |z| {worst:.2}");
    assert!(
        worst <= 4.5,
        "the index-matched sphere is visible (|z| = {worst:.2})"
    );
}

fn index_matched_worst_z(ior: &str) -> f64 {
    let scene = |sphere: bool, seed: u32| {
        format!(
            r#"(
            camera: (fov: 35, to_world: [LookAt(origin: (0, 1.3, 4), target: (0, 0.55, 0), up: (0, 1, 0))]),
            film: (width: 32, height: 24, filter: Box()),
            sampler: (spp: 32, seed: {seed}),
            integrator: (max_depth: 8),
            outputs: (bands: 0, rgb: false),
            materials: {{ "matched": Dielectric(int_ior: {ior}, ext_ior: 1.0), "floor": Diffuse(reflectance: Constant(0.6)) }},
            shapes: [
                (shape: Rectangle, material: "floor", to_world: [Scale((4, 4, 1)), Rotate(axis: (1, 0, 0), angle: -90)]),
                {s}
                (shape: Rectangle, emitter: (radiance: Scaled(8, Named("D65"))), to_world: [Scale((0.3, 0.3, 1)), Rotate(axis: (1, 0, 0), angle: 90), Translate((1, 2.5, 1))]),
            ],
            emitters: [Constant(radiance: Scaled(0.4, Named("D65")))],
        )"#,
            s = if sphere {
                r#"(shape: Sphere(center: (0, 0.6, 0), radius: 0.55), material: "matched"),"#
            } else {
                ""
            }
        )
    };
    const K: u32 = 6;
    // Per pixel: mean over the K renders and the variance of that mean.
    let stats = |sphere: bool| {
        let imgs: Vec<Vec<f64>> = (0..K)
            .map(|k| {
                let (f, _) = render(&scene(sphere, 10 + k + if sphere { 0 } else { K }));
                f.channel("Y").unwrap().iter().map(|&v| v as f64).collect()
            })
            .collect();
        (0..imgs[0].len())
            .map(|i| {
                let m = imgs.iter().map(|im| im[i]).sum::<f64>() / K as f64;
                let v = imgs.iter().map(|im| (im[i] - m).powi(2)).sum::<f64>() / (K - 1) as f64;
                (m, v / K as f64)
            })
            .collect::<Vec<_>>()
    };
    let (a, b) = (stats(true), stats(false));
    let mut worst = 0.0f64;
    for ty in 0..3 {
        for tx in 0..4 {
            let tile = |px: &[(f64, f64)]| {
                (0..64).fold((0.0, 0.0), |(m, v), i| {
                    let (pm, pv) = px[(ty * 8 + i / 8) * 32 + tx * 8 + i % 8];
                    (m + pm / 64.0, v + pv / 4096.0)
                })
            };
            let ((ma, va), (mb, vb)) = (tile(&a), tile(&b));
            worst = worst.max(((ma - mb) / (va + vb).sqrt().max(1e-12)).abs());
        }
    }
    worst
}

/// The test above has the power to see a nearly index-matched sphere.
#[test]
fn index_matched_test_sees_a_weak_sphere() {
    let worst = index_matched_worst_z("1.02");
    println!("IOR 1.02 sphere: largest tile |z| {worst:.2}");
    assert!(
        worst > 4.5,
        "an IOR 1.02 sphere went unnoticed (|z| = {worst:.2})"
    );
}
