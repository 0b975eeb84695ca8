//! Scenes whose radiance is known exactly, rendered through the whole pipeline (config → scene
//! → integrator → film), and determinism across thread counts.
//!
//! In these scenes every pixel has the same expected value, so the spread of pixel values is
//! pure Monte Carlo noise: a channel's image mean must lie within 5 standard errors of the exact
//! value (σ estimated from that spread; P(|z| > 5) < 6e-7 per check). Each test also checks its
//! standard error is small (≤ 0.5%), so a pass means something.

use prism::film::Film;
use prism::integrator;
use std::path::Path;

fn render(text: &str, threads: usize) -> Film {
    let job = prism::scene::load_str(text, Path::new("inline.ron")).unwrap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| integrator::render(&job.scene, &job.settings, &job.channels, &|_| {}).0)
}

/// Mean and standard error of the mean of a channel's pixels.
fn mean_se(data: &[f32]) -> (f64, f64) {
    let n = data.len() as f64;
    let m = data.iter().map(|&v| v as f64).sum::<f64>() / n;
    let var = data.iter().map(|&v| (v as f64 - m).powi(2)).sum::<f64>() / (n - 1.0);
    (m, (var / n).sqrt())
}

fn check(name: &str, data: &[f32], expect: f64) {
    let (m, se) = mean_se(data);
    assert!(
        se <= 5e-3 * expect.abs().max(1e-3),
        "{name}: standard error {se} too large to test anything"
    );
    assert!(
        (m - expect).abs() <= 5.0 * se + 1e-6,
        "{name}: mean {m} ± {se}, expected {expect}"
    );
}

const FURNACE: &str = r#"(
    camera: (fov: 40, to_world: [LookAt(origin: (0, 0, 4), target: (0, 0, 0), up: (0, 1, 0))]),
    film: (width: 32, height: 32),
    sampler: (kind: KIND, spp: 128, seed: 3),
    spectral: (sampling: Uniform, range: (400, 720)),
    outputs: (bands: 8, band_range: (400, 720)),
    materials: { "white": Diffuse(reflectance: Constant(1.0)) },
    shapes: [(shape: Sphere(radius: 1), material: "white")],
    emitters: [Constant(radiance: Constant(1.0))],
)"#;

/// An albedo-1 diffuse sphere in a unit constant environment: energy is conserved at every
/// bounce, so every pixel is exactly 1 in every band. (X, Y, Z are not checked: the range
/// 400–720 nm truncates the CIE curves.)
#[test]
fn white_furnace_xyz_full_range() {
    // Default spectral settings (visible sampling over 360–830 nm): X, Y, Z of a constant
    // spectrum of 1 are ∫x̄/∫ȳ, 1 and ∫z̄/∫ȳ.
    let text = FURNACE
        .replace("KIND", "Independent")
        .replace("spectral: (sampling: Uniform, range: (400, 720)),", "");
    let film = render(&text, 2);
    let cmf = prism::spectrum::color::cie1931();
    let mut sums = [0.0f64; 3];
    for i in 0..47_000 {
        let v = cmf.eval(360.0 + (i as f32 + 0.5) * 0.01);
        for c in 0..3 {
            sums[c] += v[c] as f64;
        }
    }
    for (c, name) in ["X", "Y", "Z"].iter().enumerate() {
        check(
            &format!("furnace {name}"),
            film.channel(name).unwrap(),
            sums[c] / sums[1],
        );
    }
}

#[test]
fn white_furnace() {
    for kind in ["Independent", "Sobol"] {
        let film = render(&FURNACE.replace("KIND", kind), 2);
        for c in &film.channels {
            if c.name.starts_with("S0.") {
                check(&format!("furnace {kind} {}", c.name), &c.data, 1.0);
            }
        }
    }
}

/// A diffuse plane of reflectance ρ(λ) under a constant environment L(λ): seen from above it
/// reflects ρ(λ)·L(λ), so each band is the band average of ρ·L and Y is ∫ρLȳ/∫ȳ.
#[test]
fn analytic_plane_every_band() {
    let rho = [
        (360.0, 0.1f32),
        (450.0, 0.8),
        (550.0, 0.3),
        (650.0, 0.9),
        (830.0, 0.5),
    ];
    let env = [(360.0, 2.0f32), (500.0, 0.5), (600.0, 1.5), (830.0, 1.0)];
    let fmt = |v: &[(f32, f32)]| {
        v.iter()
            .map(|(a, b)| format!("({a}, {b})"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let text = format!(
        r#"(
        camera: (fov: 30, to_world: [LookAt(origin: (0, 3, 0.5), target: (0, 0, 0), up: (0, 0, -1))]),
        film: (width: 24, height: 24, filter: Box()),
        sampler: (spp: 128, seed: 5),
        spectral: (sampling: Uniform, wavelengths: 8),
        outputs: (bands: 12, band_range: (380, 740)),
        materials: {{ "paint": Diffuse(reflectance: Tabulated([{}])) }},
        shapes: [(shape: Rectangle, material: "paint", to_world: [Scale((50, 50, 1)), Rotate(axis: (1, 0, 0), angle: -90)])],
        emitters: [Constant(radiance: Tabulated([{}]))],
    )"#,
        fmt(&rho),
        fmt(&env)
    );
    let film = render(&text, 2);
    let lerp = |t: &[(f32, f32)], x: f64| {
        let i = t.iter().position(|p| p.0 as f64 >= x).unwrap().max(1);
        let (a, b) = (t[i - 1], t[i]);
        a.1 as f64 + (x - a.0 as f64) / (b.0 - a.0) as f64 * (b.1 - a.1) as f64
    };
    let product = |x: f64| lerp(&rho, x) * lerp(&env, x);
    for (k, center) in film.band_centers.iter().enumerate() {
        let (lo, hi) = (*center as f64 - 15.0, *center as f64 + 15.0);
        let m = 3000;
        let expect = (0..m)
            .map(|i| product(lo + (i as f64 + 0.5) * (hi - lo) / m as f64))
            .sum::<f64>()
            / m as f64;
        let name = &film
            .channels
            .iter()
            .filter(|c| c.name.starts_with("S0."))
            .nth(k)
            .unwrap()
            .name;
        check(
            &format!("plane band {name}"),
            film.channel(name).unwrap(),
            expect,
        );
    }
    let cmf = prism::spectrum::color::cie1931();
    let (mut num, mut den) = (0.0, 0.0);
    for i in 0..47_000 {
        let l = 360.0 + (i as f64 + 0.5) * 0.01;
        let y = cmf.eval(l as f32)[1] as f64;
        num += product(l) * y;
        den += y;
    }
    check("plane Y", film.channel("Y").unwrap(), num / den);
}

#[test]
fn same_seed_same_bits_whatever_the_threads() {
    let cornell = std::fs::read_to_string("scenes/cornell.ron").unwrap();
    for kind in ["Independent", "Sobol"] {
        let text = cornell
            .replace(
                "film: (width: 256, height: 256, filter: Box())",
                "film: (width: 48, height: 40, filter: Gaussian())",
            )
            .replace(
                "sampler: (kind: Independent, spp: 256)",
                &format!("sampler: (kind: {kind}, spp: 8, seed: 9)"),
            );
        assert!(
            text.contains(kind) && text.contains("width: 48"),
            "the test edits the scene text"
        );
        let one = render(&text, 1);
        let two = render(&text, 2);
        let four = render(&text, 4);
        for ((a, b), c) in one.channels.iter().zip(&two.channels).zip(&four.channels) {
            let bits = |v: &Vec<f32>| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(
                bits(&a.data),
                bits(&b.data),
                "{kind} {}: 1 vs 2 threads",
                a.name
            );
            assert_eq!(
                bits(&a.data),
                bits(&c.data),
                "{kind} {}: 1 vs 4 threads",
                a.name
            );
        }
        let other_seed = render(&text.replace("seed: 9", "seed: 10"), 2);
        assert_ne!(
            one.channels[0].data, other_seed.channels[0].data,
            "the seed must matter"
        );
    }
}

/// The wavelength range is chosen at run time: over 300–1100 nm (beyond the CIE curves, into
/// the near infrared), a camera seeing only a blackbody sky records, in each band, Planck's law
/// averaged over the band.
#[test]
fn blackbody_sky_over_300_to_1100_nm() {
    let text = r#"(
        film: (width: 16, height: 16),
        sampler: (spp: 256, seed: 2),
        spectral: (sampling: Uniform, range: (300, 1100), wavelengths: 8),
        outputs: (rgb: false, xyz: false, bands: 16),
        emitters: [Constant(radiance: Blackbody(4000))],
    )"#;
    let film = render(text, 2);
    assert_eq!(film.band_centers.len(), 16);
    for (k, center) in film.band_centers.iter().enumerate() {
        let (lo, hi) = (*center as f64 - 25.0, *center as f64 + 25.0);
        let m = 5000;
        let expect = (0..m)
            .map(|i| {
                prism::spectrum::curve::planck(
                    (lo + (i as f64 + 0.5) * (hi - lo) / m as f64) as f32,
                    4000.0,
                ) as f64
            })
            .sum::<f64>()
            / m as f64;
        let name = &film.channels[k].name;
        check(
            &format!("blackbody band {name}"),
            &film.channels[k].data,
            expect,
        );
    }
}

/// A black sphere resting on a diffuse floor under a unit constant environment: a floor point
/// receives ρ·L·(1 − F), where F = cos θ·(r/D)² is the view factor of a sphere entirely above
/// the point's tangent plane (D the distance to its centre, θ the angle of that direction
/// from the normal). The floor is a rotated, scaled rectangle whose vertices carry rounding
/// error, which once made rays leaving it re-hit it (shadow acne that darkened it by 14%).
/// Tolerance: 5 standard errors, as `check`.
#[test]
fn sphere_view_factor_on_a_floor() {
    for (x, z) in [(1.5f64, 0.0f64), (0.8, 0.3)] {
        let text = format!(
            r#"(
            camera: (fov: 2, to_world: [LookAt(origin: ({x}, 0.3, {z}), target: ({x}, 0, {z}), up: (0, 0, 1))]),
            film: (width: 8, height: 8, filter: Box()),
            sampler: (spp: 2048, seed: 11),
            integrator: (max_depth: 2),
            materials: {{ "floor": Diffuse(reflectance: Constant(0.5)), "black": Diffuse(reflectance: Constant(0)) }},
            shapes: [
                (shape: Rectangle, material: "floor", to_world: [Scale((4, 4, 1)), Rotate(axis: (1, 0, 0), angle: -90)]),
                (shape: Sphere(center: (0, 0.6, 0), radius: 0.6), material: "black"),
            ],
            emitters: [Constant(radiance: Constant(1.0))],
        )"#
        );
        let film = render(&text, 2);
        let d2 = x * x + z * z + 0.36;
        let f = (0.6 / d2.sqrt()) * 0.36 / d2;
        check(
            &format!("floor at ({x}, 0, {z}), F = {f:.4}"),
            film.channel("Y").unwrap(),
            0.5 * (1.0 - f),
        );
    }
}
