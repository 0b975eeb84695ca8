//! Caustic light tracing (`integrator.caustics`): its absolute scale against an analytic scene,
//! the split of paths between it and the path tracer (no path lost or counted twice), and
//! determinism across thread counts.

mod common;

use common::mean_se;
use prism::film::Film;
use prism::integrator;
use std::path::{Path, PathBuf};

fn render_at(text: &str, file: &Path, threads: usize) -> Film {
    let job = prism::scene::load_str(text, file).unwrap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| integrator::render(&job.scene, &job.settings, &job.channels, &|_| {}).0)
}

fn channel<'a>(film: &'a Film, name: &str) -> &'a [f32] {
    &film.channels.iter().find(|c| c.name == name).unwrap().data
}

/// A directional light (1 W m⁻² nm⁻¹, travelling down at 45°) on a diffuse floor (ρ) next to
/// a perfect mirror wall: where the camera looks, the floor receives the light twice, directly
/// and from the mirror, so its radiance is ρ/π · E cos 45° · 2 in every wavelength. A path
/// tracer cannot reach a directional light through a mirror, so without light tracing the
/// image shows half of that: the caustic is the light tracer's alone, and its scale (camera
/// importance, geometry terms, splatting through the Gaussian filter) is checked absolutely.
/// Tolerance: 5 standard errors of the image mean (σ from the spread of pixel values, all
/// pixels having the same expectation), and the standard error must be below 0.5%.
#[test]
fn directional_light_caustic_from_a_mirror_is_exact() {
    let rho = 0.5;
    let scene = |caustics: &str| {
        format!(
            r#"(
        camera: (fov: 10, to_world: [LookAt(origin: (-0.5, 3, 0), target: (-0.5, 0, 0), up: (0, 0, 1))]),
        film: (width: 32, height: 32),
        sampler: (spp: 16),
        integrator: (max_depth: 4{caustics}),
        materials: {{ "floor": Diffuse(reflectance: Constant({rho})), "mirror": Conductor() }},
        shapes: [
            (shape: Rectangle, material: "floor", to_world: [Scale((10, 10, 1)), Rotate(axis: (1, 0, 0), angle: -90)]),
            (shape: Rectangle, material: "mirror", to_world: [Scale((2, 0.5, 1)), Rotate(axis: (0, 1, 0), angle: -90), Translate((0, 0.5, 0))]),
        ],
        emitters: [Directional(irradiance: Constant(1), direction: (1, -1, 0))],
    )"#
        )
    };
    let direct = rho / std::f64::consts::PI * std::f64::consts::FRAC_1_SQRT_2;
    let file = Path::new("inline.ron");
    let without = render_at(&scene(""), file, 2);
    let (m0, se0) = mean_se(channel(&without, "Y"));
    assert!(
        (m0 - direct).abs() <= 5.0 * se0 + 1e-6 * direct,
        "path tracer alone: {m0} ± {se0}, expected the direct light {direct}"
    );
    let with = render_at(&scene(", caustics: Some((light_paths: 16))"), file, 2);
    let (m, se) = mean_se(channel(&with, "Y"));
    assert!(se <= 5e-3 * 2.0 * direct, "standard error {se} too large");
    assert!(
        (m - 2.0 * direct).abs() <= 5.0 * se,
        "with light tracing: {m} ± {se}, expected {}",
        2.0 * direct
    );
}

/// Writes a 32×16 environment map, 1 everywhere but a 2×2-texel "sun" of `sun`, into a fresh
/// temporary directory; returns the scene file path to load scenes from there.
fn sun_map(name: &str, sun: f32) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("prism-caustics-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    exr::prelude::write_rgb_file(dir.join("sky.exr"), 32, 16, |x, y| {
        let v = if (10..12).contains(&x) && (3..5).contains(&y) {
            sun
        } else {
            1.0
        };
        (v, v, v)
    })
    .unwrap();
    dir.join("scene.ron")
}

/// Tile means of a channel over `reps` renders of different seeds: (mean, standard error of
/// the mean over the renders) per tile of `t`×`t` pixels.
fn tile_stats(text: &str, file: &Path, reps: u64, channel_name: &str, t: usize) -> Vec<(f64, f64)> {
    let mut per_seed: Vec<Vec<f64>> = Vec::new();
    for seed in 0..reps {
        let film = render_at(&text.replace("seed: 0", &format!("seed: {seed}")), file, 2);
        let (w, h) = (film.width as usize, film.height as usize);
        let data = channel(&film, channel_name);
        let mut tiles = vec![0.0f64; (w / t) * (h / t)];
        for y in 0..h {
            for x in 0..w {
                tiles[(y / t) * (w / t) + x / t] += data[y * w + x] as f64 / (t * t) as f64;
            }
        }
        per_seed.push(tiles);
    }
    let n = reps as f64;
    (0..per_seed[0].len())
        .map(|i| {
            let m = per_seed.iter().map(|s| s[i]).sum::<f64>() / n;
            let var = per_seed.iter().map(|s| (s[i] - m).powi(2)).sum::<f64>() / (n - 1.0);
            (m, (var / n).sqrt())
        })
        .collect()
}

/// The split of paths is exact: the same scene with and without caustic light tracing has the
/// same expected image. Welch t statistics of 4×4-pixel tile means over 8 seeds each; a tile
/// fails beyond |t| = 5 (with 14 degrees of freedom P(|t| > 5) ≈ 2e-4, over 48 tiles ≈ 1% for
/// the whole test at worst; the seeds are fixed, so it passes or fails the same every run).
/// Power: with the path tracer's exclusion switched off (the light-traced paths counted twice)
/// every scene below fails, its worst tile by 23–33 standard errors.
fn split_is_unbiased(name: &str, shapes: &str, camera: &str) {
    split_is_unbiased_with(
        name,
        shapes,
        camera,
        r#"[Envmap(filename: "sky.exr", to_world: [Rotate(axis: (0, 1, 0), angle: 100)])]"#,
    )
}

fn split_is_unbiased_with(name: &str, shapes: &str, camera: &str, emitters: &str) {
    let file = sun_map(name, 400.0);
    let scene = |caustics: &str| {
        format!(
            r#"(
        camera: {camera},
        film: (width: 32, height: 24, filter: Box()),
        sampler: (spp: 48, seed: 0),
        integrator: (max_depth: 6{caustics}),
        materials: {{
            "floor": Diffuse(reflectance: Constant(0.6)),
            "mirror": Conductor(),
            "water": Dielectric(int_ior: 1.33),
            "frosted": RoughDielectric(distribution: Ggx, alpha: 0.15, int_ior: 1.5),
        }},
        shapes: [{shapes}],
        emitters: {emitters},
    )"#
        )
    };
    let reps = 8;
    let a = tile_stats(&scene(""), &file, reps, "Y", 4);
    let b = tile_stats(
        &scene(", caustics: Some((light_paths: 1, bright_ratio: 20))"),
        &file,
        reps,
        "Y",
        4,
    );
    let mut worst = (0.0f64, 0usize);
    for (i, (&(ma, sa), &(mb, sb))) in a.iter().zip(&b).enumerate() {
        let t = (ma - mb) / (sa * sa + sb * sb).sqrt().max(1e-12);
        if t.abs() > worst.0.abs() {
            worst = (t, i);
        }
    }
    let (ma, mb) = (a[worst.1].0, b[worst.1].0);
    assert!(
        worst.0.abs() < 5.0,
        "{name}: tile {} differs: {ma} without, {mb} with caustics (t = {:.2})",
        worst.1,
        worst.0
    );
}

/// The floor, a mirror sphere and a water sphere, and a camera looking at them.
const FLOOR: &str = r#"(shape: Rectangle, material: "floor", to_world: [Scale((6, 6, 1)), Rotate(axis: (1, 0, 0), angle: -90)]),"#;
const SPHERES: &str = r#"(shape: Sphere(center: (-0.6, 0.5, 0), radius: 0.5), material: "mirror"),
    (shape: Sphere(center: (0.7, 0.5, 0.2), radius: 0.5), material: "water"),"#;
const CAMERA: &str =
    "(fov: 60, to_world: [LookAt(origin: (0, 2.5, 3), target: (0, 0.2, 0), up: (0, 1, 0))])";

/// A mirror sphere and a water sphere on a diffuse floor under a sun: caustics through Dirac
/// reflection and refraction (entering and leaving the water).
#[test]
fn split_is_unbiased_for_mirror_and_glass() {
    split_is_unbiased("spheres", &format!("{FLOOR}{SPHERES}"), CAMERA);
}

/// An area light (an 80 cm square, 1.5 m up) over a mirror sphere and a water sphere, and a dim
/// constant sky: light paths leave the light in the cones the spheres subtend. (Large enough
/// for the path tracer alone to find its caustics in most tiles at this spp: a rare-event
/// estimate's spread over 8 seeds understates its error, and a smaller light fails the test
/// for that reason alone.)
#[test]
fn split_is_unbiased_for_an_area_light() {
    let light = r#"(shape: Rectangle, emitter: (radiance: Constant(8)), to_world: [Scale((0.4, 0.4, 1)), Rotate(axis: (1, 0, 0), angle: 90), Translate((0.3, 1.5, -0.5))]),"#;
    split_is_unbiased_with(
        "area",
        &format!("{FLOOR}{SPHERES}{light}"),
        CAMERA,
        "[Constant(radiance: Constant(0.2))]",
    );
}

/// A glossy chain (frosted glass, α = 0.15): light traced through microfacet refraction, and
/// the path tracer leaving out its emitter samples of the sun at such vertices.
#[test]
fn split_is_unbiased_through_frosted_glass() {
    split_is_unbiased(
        "frosted",
        &format!(
            r#"{FLOOR}(shape: Sphere(center: (0, 0.6, 0), radius: 0.5), material: "frosted"),"#
        ),
        "(fov: 50, to_world: [LookAt(origin: (0, 2.5, 2.5), target: (0, 0.2, 0), up: (0, 1, 0))])",
    );
}

/// The camera inside a water sphere, looking at a diffuse floor also inside it, lit by the sun
/// through the water surface: the light path ends inside the denser medium, where radiance and
/// flux scale differently (η²); the two estimators must still agree.
#[test]
fn split_is_unbiased_inside_water() {
    split_is_unbiased(
        "inside",
        r#"(shape: Sphere(center: (0, 0, 0), radius: 4), material: "water"),
           (shape: Rectangle, material: "floor", to_world: [Scale((2, 2, 1)), Rotate(axis: (1, 0, 0), angle: -90), Translate((0, -1, 0))]),"#,
        "(fov: 60, to_world: [LookAt(origin: (0, 1, 1.5), target: (0, -1, 0), up: (0, 1, 0))])",
    );
}

/// Light paths are traced in parallel chunks; the image is the same bit for bit whatever the
/// thread count.
#[test]
fn caustics_are_deterministic_across_threads() {
    let file = sun_map("threads", 400.0);
    let text = r#"(
        camera: (fov: 60, to_world: [LookAt(origin: (0, 2.5, 3), target: (0, 0.2, 0), up: (0, 1, 0))]),
        film: (width: 24, height: 16),
        sampler: (spp: 8),
        integrator: (caustics: Some((light_paths: 4, bright_ratio: 20))),
        materials: { "floor": Diffuse(reflectance: Constant(0.6)), "mirror": Conductor() },
        shapes: [
            (shape: Rectangle, material: "floor", to_world: [Scale((6, 6, 1)), Rotate(axis: (1, 0, 0), angle: -90)]),
            (shape: Sphere(center: (0, 0.5, 0), radius: 0.5), material: "mirror"),
        ],
        emitters: [Envmap(filename: "sky.exr")],
    )"#;
    let one = render_at(text, &file, 1);
    let two = render_at(text, &file, 2);
    for (a, b) in one.channels.iter().zip(&two.channels) {
        assert!(
            a.data
                .iter()
                .zip(&b.data)
                .all(|(x, y)| x.to_bits() == y.to_bits()),
            "channel {} differs between 1 and 2 threads",
            a.name
        );
    }
}
