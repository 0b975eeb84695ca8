//! Caustic light tracing (`integrator.caustics`): its absolute scale against an analytic scene,
//! the split of paths between it and the path tracer (no path lost or counted twice), and
//! determinism across thread counts.

mod common;
mod scratch;

use common::mean_se;
use prism::film::Film;
use prism::integrator;
use prism::math::portable;
use std::path::{Path, PathBuf};

fn render_at(text: &str, file: &Path, threads: usize) -> Film {
    let job = prism::load::load_str(text, file).unwrap();
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
/// temporary directory; returns the directory (removed when dropped) and the scene file path to
/// load scenes from there.
fn sun_map(name: &str, sun: f32) -> (scratch::Scratch, PathBuf) {
    let dir = scratch::scratch("caustics", name);
    exr::prelude::write_rgb_file(dir.join("sky.exr"), 32, 16, |x, y| {
        let v = if (10..12).contains(&x) && (3..5).contains(&y) {
            sun
        } else {
            1.0
        };
        (v, v, v)
    })
    .unwrap();
    let scene = dir.join("scene.ron");
    (dir, scene)
}

/// Tile means of a channel over `reps` renders with seeds `first_seed..first_seed + reps`:
/// (mean, standard error of the mean over the renders) per tile of `t`×`t` pixels. `edit` may
/// change the built settings (the power check's `count_twice`).
fn tile_stats(
    text: &str,
    file: &Path,
    first_seed: u64,
    reps: u64,
    channel_name: &str,
    t: usize,
    edit: &dyn Fn(&mut prism::integrator::RenderSettings),
) -> Vec<(f64, f64)> {
    let mut per_seed: Vec<Vec<f64>> = Vec::new();
    for seed in first_seed..first_seed + reps {
        let text = text.replace("seed: 0", &format!("seed: {seed}"));
        let mut job = prism::load::load_str(&text, file).unwrap();
        edit(&mut job.settings);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let film = pool
            .install(|| integrator::render(&job.scene, &job.settings, &job.channels, &|_| {}).0);
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

/// Family-wise significance of each split test: noise alone fails a scene with probability
/// 1e-3 (all seeds fixed, so a given build passes or fails the same every run).
const SPLIT_ALPHA: f64 = 1e-3;
const REPS: u64 = 8;

/// The worst tile of a split comparison: the smallest p-value, where, and the test's verdict.
struct Split {
    p: f64,
    t: f64,
    dof: f64,
    tile: usize,
    without: f64,
    with: f64,
    /// The per-tile threshold (Šidák over all tiles).
    threshold: f64,
}

impl Split {
    fn fails(&self) -> bool {
        self.p < self.threshold
    }
}

/// The split of paths is exact: the same scene with and without caustic light tracing has the
/// same expected image. Each arm is `REPS` renders on seeds of its own (0–7 and 100–107: the
/// arms are independent). Per 4×4-pixel tile, Welch's t of the two arms' means with
/// Welch–Satterthwaite degrees of freedom (between 7 and 14 here, from each arm's spread),
/// and every tile counts: Šidák's correction over the 48 tiles, family-wise α = 1e-3. The
/// standard error of a tile's difference is floored at 1e-4 of its mean (below that, rounding
/// of f32 sums, not noise), and each arm's image mean must be known to 2% (the precision floor,
/// as render_analytic.rs: a test too noisy to see anything fails instead of passing). Power:
/// with the path tracer's exclusion switched off (`count_twice`: the light-traced paths
/// counted twice) every scene must fail (`split_power_*` tests).
fn split(
    name: &str,
    shapes: &str,
    camera: &str,
    emitters: &str,
    extra: &str,
    twice: bool,
) -> Split {
    let (_dir, file) = sun_map(name, 400.0);
    if shapes.contains("ball.obj") {
        std::fs::write(file.with_file_name("ball.obj"), uv_sphere_obj(6, 12)).unwrap();
    }
    let scene = |caustics: &str| {
        format!(
            r#"(
        camera: {camera},
        film: (width: 32, height: 24, filter: Box()),
        sampler: (spp: 48, seed: 0),
        integrator: (max_depth: 6{caustics}),
        {extra}
        materials: {{
            "floor": Diffuse(reflectance: Constant(0.6)),
            "mirror": Conductor(),
            "water": Dielectric(int_ior: 1.33),
            "frosted": RoughDielectric(distribution: Ggx, alpha: 0.15, int_ior: 1.5),
            "bk7": Dielectric(int_ior: Glass("BK7")),
        }},
        shapes: [{shapes}],
        emitters: {emitters},
    )"#
        )
    };
    let a = tile_stats(&scene(""), &file, 0, REPS, "Y", 4, &|_| {});
    let b = tile_stats(
        &scene(", caustics: Some((light_paths: 1, bright_ratio: 20))"),
        &file,
        100,
        REPS,
        "Y",
        4,
        &|s| {
            if let Some(c) = s.path.caustics.as_mut() {
                c.count_twice = twice;
            }
        },
    );
    for (arm, tiles) in [("without", &a), ("with", &b)] {
        let m = tiles.iter().map(|t| t.0).sum::<f64>() / tiles.len() as f64;
        let se = tiles.iter().map(|t| t.1 * t.1).sum::<f64>().sqrt() / tiles.len() as f64;
        assert!(
            se <= 0.02 * m,
            "{name} {arm} caustics: image mean {m} ± {se}, too noisy to test the split"
        );
    }
    let m = a.len() as f64;
    let threshold = 1.0 - portable::powf(1.0 - SPLIT_ALPHA, 1.0 / m);
    let n = REPS as f64;
    let mut worst: Option<Split> = None;
    for (i, (&(ma, sa), &(mb, sb))) in a.iter().zip(&b).enumerate() {
        let floor = 1e-4 * ma.abs().max(mb.abs());
        let (sa, sb) = (sa.max(floor), sb.max(floor));
        let (t, dof, p) = common::welch(ma, sa, n, mb, sb, n);
        if worst.as_ref().is_none_or(|w| p < w.p) {
            worst = Some(Split {
                p,
                t,
                dof,
                tile: i,
                without: ma,
                with: mb,
                threshold,
            });
        }
    }
    let w = worst.unwrap();
    println!(
        "{name}{}: worst tile {} (t = {:.2}, {:.1} dof, p = {:.2e}, threshold {:.2e}): {} without, {} with",
        if twice { " (counted twice)" } else { "" },
        w.tile,
        w.t,
        w.dof,
        w.p,
        w.threshold,
        w.without,
        w.with
    );
    w
}

fn split_is_unbiased(name: &str, shapes: &str, camera: &str) {
    split_is_unbiased_with(name, shapes, camera, SUN, "")
}

fn split_is_unbiased_with(name: &str, shapes: &str, camera: &str, emitters: &str, extra: &str) {
    let w = split(name, shapes, camera, emitters, extra, false);
    assert!(
        !w.fails(),
        "{name}: tile {} differs: {} without, {} with caustics (t = {:.2}, {:.1} dof, p = {:.2e} < {:.2e})",
        w.tile, w.without, w.with, w.t, w.dof, w.p, w.threshold
    );
}

/// The power check: the same comparison with the light-traced paths counted twice must fail.
fn split_detects_double_counting(
    name: &str,
    shapes: &str,
    camera: &str,
    emitters: &str,
    extra: &str,
) {
    let w = split(name, shapes, camera, emitters, extra, true);
    assert!(
        w.fails(),
        "{name}: double counting went unnoticed (worst p = {:.2e}, threshold {:.2e})",
        w.p,
        w.threshold
    );
}

const SUN: &str =
    r#"[Envmap(filename: "sky.exr", to_world: [Rotate(axis: (0, 1, 0), angle: 100)])]"#;

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
    split_is_unbiased_with(
        "area",
        &format!("{FLOOR}{SPHERES}{AREA_LIGHT}"),
        CAMERA,
        AREA_SKY,
        "",
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

const AREA_LIGHT: &str = r#"(shape: Rectangle, emitter: (radiance: Constant(8)), to_world: [Scale((0.4, 0.4, 1)), Rotate(axis: (1, 0, 0), angle: 90), Translate((0.3, 1.5, -0.5))]),"#;
const AREA_SKY: &str = "[Constant(radiance: Constant(0.2))]";

/// The power of the split tests: counting the light-traced paths twice fails them, under the
/// sun and under the area light.
#[test]
fn split_power_sun() {
    split_detects_double_counting(
        "spheres-twice",
        &format!("{FLOOR}{SPHERES}"),
        CAMERA,
        SUN,
        "",
    );
}

#[test]
fn split_power_area_light() {
    split_detects_double_counting(
        "area-twice",
        &format!("{FLOOR}{SPHERES}{AREA_LIGHT}"),
        CAMERA,
        AREA_SKY,
        "",
    );
}

/// A dispersive glass sphere (BK7, Sellmeier) under the sun: the light tracer's dispersive
/// path, where it keeps the hero wavelength alone at a dispersive refraction, and the path
/// tracer's, which keeps every wavelength by spectral MIS (the default) or only the hero
/// (`TerminateSecondary`): both splits must be exact.
#[test]
fn split_is_unbiased_through_dispersive_glass() {
    let glass = r#"(shape: Sphere(center: (0, 0.6, 0), radius: 0.5), material: "bk7"),"#;
    for (name, mode) in [
        ("bk7-mis", "SpectralMis"),
        ("bk7-hero", "TerminateSecondary"),
    ] {
        split_is_unbiased_with(
            name,
            &format!("{FLOOR}{glass}"),
            CAMERA,
            SUN,
            &format!("spectral: (dispersion: {mode}),"),
        );
    }
}

/// A mirror and a water sphere as coarse triangle meshes with smooth vertex normals: shading
/// normals differ from the geometric ones by up to ~15°, so the adjoint BSDF's correction
/// (Veach 1997, §5.3: |wo·ns||wi·ng| / |wo·ng||wi·ns| on light paths) is not 1, and the split
/// must still be exact.
#[test]
fn split_is_unbiased_with_shading_normals() {
    // `split` writes ball.obj beside the scene.
    let shapes = format!(
        r#"{FLOOR}(shape: Mesh(path: "ball.obj"), material: "mirror", to_world: [Scale((0.5, 0.5, 0.5)), Translate((-0.6, 0.5, 0))]),
        (shape: Mesh(path: "ball.obj"), material: "water", to_world: [Scale((0.5, 0.5, 0.5)), Translate((0.7, 0.5, 0.2))]),"#
    );
    split_is_unbiased_with("normals", &shapes, CAMERA, SUN, "");
}

/// A unit UV sphere as OBJ text: `rings` latitude bands, `segments` longitudes, with the
/// sphere's normal at each vertex (`vn`), counter-clockwise seen from outside.
fn uv_sphere_obj(rings: usize, segments: usize) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    for r in 0..=rings {
        let theta = std::f64::consts::PI * r as f64 / rings as f64;
        for k in 0..=segments {
            let phi = 2.0 * std::f64::consts::PI * k as f64 / segments as f64;
            let (x, y, z) = (
                portable::sin(theta) * portable::cos(phi),
                portable::cos(theta),
                portable::sin(theta) * portable::sin(phi),
            );
            writeln!(s, "v {x:.6} {y:.6} {z:.6}\nvn {x:.6} {y:.6} {z:.6}").unwrap();
        }
    }
    let idx = |r: usize, k: usize| r * (segments + 1) + k + 1;
    for r in 0..rings {
        for k in 0..segments {
            let (a, b, c, d) = (idx(r, k), idx(r, k + 1), idx(r + 1, k + 1), idx(r + 1, k));
            if r > 0 {
                writeln!(s, "f {a}//{a} {b}//{b} {c}//{c}").unwrap();
            }
            if r + 1 < rings {
                writeln!(s, "f {a}//{a} {c}//{c} {d}//{d}").unwrap();
            }
        }
    }
    s
}

/// Light paths are traced in parallel chunks; the image is the same bit for bit whatever the
/// thread count.
#[test]
fn caustics_are_deterministic_across_threads() {
    let (_dir, file) = sun_map("threads", 400.0);
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
    same_at_1_and_2_threads(text, &file);
}

/// As above with enough light paths for several batches of chunks (64 chunks of 4096 paths a
/// batch: 24·16·16·100 = 614 400 paths, 3 batches, the last one partial), and an area light
/// too: the batches' order of accumulation must not depend on the threads either.
#[test]
fn caustics_are_deterministic_over_several_batches() {
    let (_dir, file) = sun_map("batches", 400.0);
    let text = format!(
        r#"(
        camera: (fov: 60, to_world: [LookAt(origin: (0, 2.5, 3), target: (0, 0.2, 0), up: (0, 1, 0))]),
        film: (width: 24, height: 16),
        sampler: (spp: 16),
        integrator: (caustics: Some((light_paths: 100, bright_ratio: 20))),
        materials: {{ "floor": Diffuse(reflectance: Constant(0.6)), "mirror": Conductor(), "water": Dielectric(int_ior: 1.33) }},
        shapes: [{FLOOR}{SPHERES}{AREA_LIGHT}],
        emitters: [Envmap(filename: "sky.exr")],
    )"#
    );
    same_at_1_and_2_threads(&text, &file);
}

fn same_at_1_and_2_threads(text: &str, file: &Path) {
    let one = render_at(text, file, 1);
    let two = render_at(text, file, 2);
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
