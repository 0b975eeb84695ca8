//! Caustic light tracing with the per-pixel error measures: the `stderr` layer counts the light
//! tracer's noise, and adaptive sampling keeps the light tracer (its light paths per camera
//! sample of the estimates) and stays unbiased.
//!
//! The scene is the analytic one of `tests/caustics.rs`: a directional light on a diffuse floor
//! beside a mirror wall, where the floor the camera sees receives the light directly (the path
//! tracer's part, which is noise-free there: a delta light, a uniform floor) and from the
//! mirror (the light tracer's part: a caustic a path tracer cannot find). Every pixel has the
//! same expectation, ρ/π · E cos 45° · 2, so the spread of the pixel values is each pixel's own
//! noise, measured without trusting the renderer's figures.

mod common;

use common::mean_se;
use prism::integrator::render_film;
use std::path::Path;

const RHO: f64 = 0.5;

fn job(spp: &str, light_paths: f32) -> prism::load::Job {
    let text = format!(
        r#"(
        camera: (fov: 10, to_world: [LookAt(origin: (-0.5, 3, 0), target: (-0.5, 0, 0), up: (0, 0, 1))]),
        film: (width: 32, height: 32),
        sampler: (spp: {spp}, seed: 3),
        integrator: (max_depth: 4, caustics: Some((light_paths: {light_paths}))),
        materials: {{ "floor": Diffuse(reflectance: Constant({RHO})), "mirror": Conductor() }},
        shapes: [
            (shape: Rectangle, material: "floor", to_world: [Scale((10, 10, 1)), Rotate(axis: (1, 0, 0), angle: -90)]),
            (shape: Rectangle, material: "mirror", to_world: [Scale((2, 0.5, 1)), Rotate(axis: (0, 1, 0), angle: -90), Translate((0, 0.5, 0))]),
        ],
        emitters: [Directional(irradiance: Constant(1), direction: (1, -1, 0))],
    )"#
    );
    prism::load::load_str(&text, Path::new("inline.ron")).unwrap()
}

/// Y and each pixel's reported standard error of Y.
fn render(job: &prism::load::Job) -> (Vec<f32>, Vec<f64>, Vec<u32>) {
    let (film, _, e) = render_film(&job.scene, &job.settings, &job.channels, true, &|_| {});
    let y = film.channel("Y").unwrap().to_vec();
    let slots = e.stderr.len() / y.len();
    let se = (0..y.len())
        .map(|i| e.stderr[i * slots + 1] as f64)
        .collect();
    (y, se, e.spp)
}

fn expected() -> f64 {
    2.0 * RHO / std::f64::consts::PI * std::f64::consts::FRAC_1_SQRT_2
}

/// The reported standard error of Y, as a root mean square over the pixels, matches the
/// spread of the pixel values (their sample standard deviation: all pixels have one
/// expectation). With 1024 pixels the spread is known to about 1/√2048 = 2.2% (neighbouring
/// pixels share splats through the filter, which correlates them and widens that a little),
/// and each pixel's reported variance is itself an estimate from ~16k light paths: a ratio
/// within [0.85, 1.15] is well outside chance. Before the light tracer's variance was counted
/// the layer reported the camera samples' spread alone, here ~0 (a ratio below 0.1).
#[test]
fn stderr_counts_the_light_tracers_noise() {
    for light_paths in [1.0, 4.0] {
        let (y, se, _) = render(&job("4", light_paths));
        let (m, se_mean) = mean_se(&y);
        let spread = se_mean * (y.len() as f64).sqrt();
        let reported = (se.iter().map(|s| s * s).sum::<f64>() / se.len() as f64).sqrt();
        let ratio = reported / spread;
        println!("light_paths {light_paths}: mean {m}, pixel spread {spread}, reported {reported}, ratio {ratio}");
        assert!(
            (0.85..=1.15).contains(&ratio),
            "light_paths {light_paths}: stderr.Y reports {reported} (RMS over pixels) where the pixels spread by {spread}"
        );
        assert!(
            (m - expected()).abs() <= 5.0 * se_mean,
            "mean {m} ± {se_mean}, expected {}",
            expected()
        );
    }
}

/// Adaptive sampling with caustic light tracing (refused before). Here the path tracer's part
/// has no noise, so every pixel stops at its 4-sample pilot, and the image is the fixed 4-spp
/// render's bit for bit: the light tracer ran with its light paths per camera sample of the
/// estimates (per the `max` of 64 it would have traced 16 times as many, and the bits would
/// differ), and the reported errors include its noise. The unbiasedness of adaptive counts is
/// tested in tests/adaptive.rs; the light tracer's part does not depend on them.
#[test]
fn adaptive_sampling_keeps_the_light_tracer() {
    let (y, se, spp) = render(&job("Adaptive(rel_error: 0.02, min: 4, max: 64)", 4.0));
    assert!(spp.iter().all(|&n| n == 4), "counts {:?}", &spp[..8]);
    let (fixed, fixed_se, _) = render(&job("4", 4.0));
    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&y), bits(&fixed));
    assert_eq!(se, fixed_se);
    let (m, se_mean) = mean_se(&y);
    assert!(
        (m - expected()).abs() <= 5.0 * se_mean,
        "adaptive with caustics: mean {m} ± {se_mean}, expected {}",
        expected()
    );
}
