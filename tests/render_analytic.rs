//! Scenes whose radiance is known exactly, rendered through the whole pipeline (config → scene
//! → integrator → film), and determinism across thread counts.
//!
//! In these scenes every pixel has the same expected value, so the spread of pixel values is
//! pure Monte Carlo noise: a channel's image mean must lie within 5 standard errors of the exact
//! value (σ estimated from that spread; P(|z| > 5) < 6e-7 per check). Each test also checks its
//! standard error is small (≤ 0.5%), so a pass means something.

mod common;
mod scratch;

use common::mean_se;
use prism::film::Film;
use prism::integrator;
use prism::math::portable;
use std::path::Path;

fn render(text: &str, threads: usize) -> Film {
    let job = prism::load::load_str(text, Path::new("inline.ron")).unwrap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| integrator::render(&job.scene, &job.settings, &job.channels, &|_| {}).0)
}

fn check(name: &str, data: &[f32], expect: f64) -> (f64, f64) {
    let (m, se) = mean_se(data);
    assert!(
        se <= 5e-3 * expect.abs().max(1e-3),
        "{name}: standard error {se} too large to test anything"
    );
    assert!(
        (m - expect).abs() <= 5.0 * se + 1e-6,
        "{name}: mean {m} ± {se}, expected {expect}"
    );
    (m, se)
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

// ---- Emitters: point, spot, directional and environment-map lights on a diffuse plane. ----
//
// The plane y = 0 (reflectance ρ, constant) faces +y. A diffuse plane lit by irradiance E(λ)
// has radiance ρ/π·E(λ) in every direction, so each spectral band must be ρ/π × the band average
// of E, and Y must be ρ/π × E's luminance. Where E varies over the plane (point and spot
// lights), the camera looks straight down at one point through a 0.01° field of view: the patch
// it sees is ±1.7e-3 wide, over which E varies by < 1e-5 relative, far below the 5σ tolerance
// (σ ≈ 0.2% here).

use prism::spectrum::Curve;

const PLANE: &str = r#"(shape: Rectangle, material: "grey", to_world: [Scale((50, 50, 1)), Rotate(axis: (1, 0, 0), angle: -90)])"#;
const RHO: f64 = 0.6;

/// A scene: the plane, `emitter`, a camera at `eye` looking at `target`, 6 bands of 60 nm (each
/// holds one or two of the 8 lanes, spaced 58.75 nm), uniform wavelength sampling.
fn plane_scene(emitter: &str, eye: [f32; 3], target: [f32; 3], fov: f32) -> String {
    format!(
        r#"(
        camera: (fov: {fov}, to_world: [LookAt(origin: ({}, {}, {}), target: ({}, {}, {}), up: (0, 0, 1))]),
        film: (width: 24, height: 24, filter: Box()),
        sampler: (spp: 64, seed: 11),
        spectral: (sampling: Uniform, wavelengths: 8),
        outputs: (bands: 6, band_range: (380, 740)),
        materials: {{ "grey": Diffuse(reflectance: Constant({RHO})) }},
        shapes: [{PLANE}],
        emitters: [{emitter}],
    )"#,
        eye[0], eye[1], eye[2], target[0], target[1], target[2]
    )
}

/// Checks each band and Y of `film` against `g` × the spectrum `s`.
fn check_spectrum(name: &str, film: &Film, g: f64, s: &Curve) {
    let bands: Vec<_> = film
        .channels
        .iter()
        .filter(|c| c.name.starts_with("S0."))
        .collect();
    assert_eq!(bands.len(), film.band_centers.len());
    for (c, center) in bands.iter().zip(&film.band_centers) {
        let avg = s.average(center - 30.0, center + 30.0) as f64;
        check(&format!("{name} {}", c.name), &c.data, g * avg);
    }
    let expect = g * s.luminance() as f64;
    let (m, se) = check(&format!("{name} Y"), film.channel("Y").unwrap(), expect);
    let z = if se > 0.0 { (m - expect) / se } else { 0.0 };
    eprintln!("{name}: Y = {m:.5} ± {se:.1e}, exact {expect:.5} ({z:+.2}σ)");
}

fn named(name: &str) -> Curve {
    prism::spectrum::data::named_illuminant(name).unwrap()
}

/// A point light of intensity I at height h: E = I cos θ / r² on the plane.
#[test]
fn point_light_on_a_plane() {
    let intensity = named("A").scaled(3.0);
    let light = r#"Point(position: (0, 2, 0), intensity: Scaled(3, Named("A")))"#;
    // Right below the light, E = I/h²; 1.5 to the side, r = 2.5 and cos θ = 0.8.
    for (x, geom) in [(0.0f32, 1.0 / 4.0), (1.5, 0.8 / 6.25)] {
        let film = render(&plane_scene(light, [x, 20.0, 0.0], [x, 0.0, 0.0], 0.01), 2);
        check_spectrum(
            &format!("point x={x}"),
            &film,
            RHO / std::f64::consts::PI * geom,
            &intensity,
        );
    }
}

/// A spot of cutoff 30° and beam width 20° at height 2, pointing down: at 10° from its axis it
/// is a point light; at 25° it gives half (linear falloff in angle); at 40° nothing.
#[test]
fn spot_light_inside_transition_and_outside() {
    let intensity = named("D65").scaled(5.0);
    let light = r#"Spot(intensity: Scaled(5, Named("D65")), cutoff_angle: 30, beam_width: 20, to_world: [LookAt(origin: (0, 2, 0), target: (0, 0, 0), up: (0, 0, 1))])"#;
    for (deg, falloff) in [(10.0f64, 1.0), (25.0, 0.5), (40.0, 0.0)] {
        let t = deg.to_radians();
        let x = (2.0 * portable::tan(t)) as f32;
        let film = render(&plane_scene(light, [x, 20.0, 0.0], [x, 0.0, 0.0], 0.01), 2);
        // E = I·falloff·cos θ / r², r = h / cos θ.
        let geom = falloff * portable::cos(t).powi(3) / 4.0;
        check_spectrum(
            &format!("spot {deg}°"),
            &film,
            RHO / std::f64::consts::PI * geom,
            &intensity,
        );
    }
}

/// A directional light 35° off the normal: E·cos θ everywhere. It is not an environment light:
/// escaping rays must not see it (that would count it twice).
#[test]
fn directional_light_at_an_angle() {
    let t = 35f32.to_radians();
    let light = format!(
        r#"Directional(irradiance: Scaled(2, Named("D65")), direction: ({}, {}, 0))"#,
        portable::sin(t),
        -portable::cos(t)
    );
    let text = plane_scene(&light, [0.0, 3.0, 0.5], [0.0, 0.0, 0.0], 40.0);
    let job = prism::load::load_str(&text, Path::new("inline.ron")).unwrap();
    assert!(job.scene.environment.is_empty());
    // The same light given by `to_world` (it travels along its local +z).
    let by_frame = plane_scene(
        &format!(
            "Directional(to_world: [LookAt(origin: (0, 0, 0), target: ({}, {}, 0), up: (0, 1, 0))])",
            portable::sin(t),
            -portable::cos(t)
        ),
        [0.0, 3.0, 0.5],
        [0.0, 0.0, 0.0],
        40.0,
    );
    let job2 = prism::load::load_str(&by_frame, Path::new("inline.ron")).unwrap();
    match (&job.scene.emitters[0], &job2.scene.emitters[0]) {
        (
            prism::emitter::Emitter::Directional { direction: a, .. },
            prism::emitter::Emitter::Directional { direction: b, .. },
        ) => assert!(a.abs_diff_eq(*b, 1e-6), "{a} vs {b}"),
        _ => panic!("not directional lights"),
    }
    let film = render(&text, 2);
    check_spectrum(
        "directional",
        &film,
        RHO / std::f64::consts::PI * portable::cos(t) as f64,
        &named("D65").scaled(2.0),
    );
}

/// Writes a `w`×`h` grey EXR (`value(row)`) to a fresh temporary directory; returns the directory.
fn grey_exr(
    name: &str,
    w: usize,
    h: usize,
    value: impl Fn(usize) -> f32 + Sync,
) -> scratch::Scratch {
    let dir = scratch::scratch("analytic", name);
    exr::prelude::write_rgb_file(dir.join("map.exr"), w, h, |_, y| {
        let v = value(y);
        (v, v, v)
    })
    .unwrap();
    dir
}

fn render_at(text: &str, file: &Path) -> Film {
    let job = prism::load::load_str(text, file).unwrap();
    integrator::render(&job.scene, &job.settings, &job.channels, &|_| {}).0
}

/// A constant grey map v is the constant emitter of the uplift of (v, v, v): v × D65 at unit
/// luminance. A convex diffuse sphere (ρ) in it shows ρ·v·D65 at every pixel (the camera sees
/// only the sphere), through environment sampling, BSDF sampling and MIS.
#[test]
fn constant_envmap_equals_constant_emitter() {
    let v = 0.7f32;
    let dir = grey_exr("constant", 10, 5, |_| v);
    // The uplift of a grey: the sigmoid of (½, ½, ½) is flat ½ to within 1e-4, so 2v·½·D65.
    let uplift = Curve::rgb_illuminant([v; 3]);
    let d65 = named("D65").scaled(v);
    for l in (360..=830).step_by(10) {
        let (a, b) = (uplift.eval_one(l as f32), d65.eval_one(l as f32));
        assert!((a / b - 1.0).abs() < 1e-4, "{l} nm: {a} vs {b}");
    }
    let scene = |emitter: &str| {
        format!(
            r#"(
            camera: (fov: 15, to_world: [LookAt(origin: (0, 0, 4), target: (0, 0, 0), up: (0, 1, 0))]),
            film: (width: 24, height: 24, filter: Box()),
            sampler: (spp: 64, seed: 4),
            spectral: (sampling: Uniform, wavelengths: 8),
            outputs: (bands: 6, band_range: (380, 740)),
            materials: {{ "grey": Diffuse(reflectance: Constant({RHO})) }},
            shapes: [(shape: Sphere(radius: 1), material: "grey")],
            emitters: [{emitter}],
        )"#
        )
    };
    let file = dir.join("scene.ron");
    for (name, emitter) in [
        ("envmap", r#"Envmap(filename: "map.exr")"#.to_string()),
        (
            "constant",
            format!(r#"Constant(radiance: Scaled({v}, Named("D65")))"#),
        ),
    ] {
        let film = render_at(&scene(&emitter), &file);
        check_spectrum(&format!("sphere in {name}"), &film, RHO, &d65);
    }
}

/// A map whose upper hemisphere is a and lower b (18×9: rows 0–4 are a, row 4 lying on the
/// horizon, as Mitsuba puts row j at θ = π j/(H − 1)): an upward plane sees only a, so it shows
/// ρ·a·D65. This pins down "+y is up" and the row placement, and exercises importance sampling of
/// a non-uniform map with MIS.
///
/// Turned upside down by `to_world`, the plane sees b, except that between the horizon (row 4,
/// a) and 22.5° above it (row 5, b) the map blends linearly in θ from a to b. The plane then
/// shows ρ·D65 × 2∫ L(θ) cos θ sin θ dθ over the hemisphere (≈ 4% below ρ·b·D65 here; texel-
/// centred rows would move that by ~2%).
#[test]
fn two_hemisphere_envmap() {
    let (a, b) = (0.4f64, 2.0f64);
    let dir = grey_exr("hemispheres", 18, 9, |row| {
        if row <= 4 {
            a as f32
        } else {
            b as f32
        }
    });
    let file = dir.join("scene.ron");
    let (edge, horizon) = (
        3.0 * std::f64::consts::FRAC_PI_8,
        std::f64::consts::FRAC_PI_2,
    );
    let upside_down = |theta: f64| {
        if theta <= edge {
            b
        } else {
            b + (a - b) * (theta - edge) / (horizon - edge)
        }
    };
    let m = 100_000;
    let flipped = (0..m)
        .map(|i| {
            let t = (i as f64 + 0.5) / m as f64 * horizon;
            2.0 * upside_down(t) * portable::cos(t) * portable::sin(t)
        })
        .sum::<f64>()
        * horizon
        / m as f64;
    for (value, to_world) in [
        (a, ""),
        (flipped, ", to_world: [Rotate(axis: (1, 0, 0), angle: 180)]"),
    ] {
        let text = plane_scene(
            &format!(r#"Envmap(filename: "map.exr"{to_world})"#),
            [0.0, 3.0, 0.5],
            [0.0, 0.0, 0.0],
            40.0,
        );
        let film = render_at(&text, &file);
        check_spectrum(
            &format!("hemisphere {value}"),
            &film,
            RHO * value,
            &named("D65"),
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
