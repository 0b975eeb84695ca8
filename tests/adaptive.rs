//! Adaptive sampling (`spp: Adaptive(...)`, `integrator::adaptive`): unbiased, its counts and
//! errors reported, deterministic at any thread count.
//!
//! The scene is `scenes/cornell.ron` on a 16×16 film (its independent sampler and 4
//! wavelengths: noisy per sample, so a biased stopping rule shows within a second of
//! rendering).

use prism::config::{AdaptiveSpp, ErrorTarget, Spp};
use prism::integrator::{render_film, PixelErrors};
use std::path::Path;

const SIZE: u32 = 16;
/// Tiles of 4×4 pixels: 16 of them.
const T: u32 = 4;

fn adaptive(rel_error: f32, min: u32, max: u32) -> Spp {
    Spp::Adaptive(AdaptiveSpp {
        rel_error,
        min,
        max,
        target: ErrorTarget::Y,
        floor: 1e-3,
    })
}

fn job(spp: Spp, seed: u64) -> prism::load::Job {
    prism::load::load(Path::new("scenes/cornell.ron"), |cfg| {
        cfg.film.width = SIZE;
        cfg.film.height = SIZE;
        cfg.sampler.spp = spp;
        cfg.sampler.seed = seed;
    })
    .unwrap()
}

/// Renders the scene at `spp` and `seed`: Y, and the per-pixel counts and standard errors.
fn render(spp: Spp, seed: u64) -> (Vec<f32>, PixelErrors) {
    let job = job(spp, seed);
    let (film, _, errors) = render_film(&job.scene, &job.settings, &job.channels, true, &|_| {});
    (film.channel("Y").unwrap().to_vec(), errors)
}

/// Mean of Y over each 4×4 tile.
fn tile_means(y: &[f32]) -> Vec<f64> {
    let n = (SIZE / T) as usize;
    let mut out = vec![0.0; n * n];
    for (i, v) in y.iter().enumerate() {
        let (x, r) = (i % SIZE as usize, i / SIZE as usize);
        out[(r / T as usize) * n + x / T as usize] += *v as f64 / (T * T) as f64;
    }
    out
}

/// The stopping rule is unbiased: the mean over 48 seeds of adaptive renders (rel_error 0.1,
/// min 4, max 64: counts from 4 to 64, set by the neighbours' 4-sample pilots, so a count that
/// depended on the samples it averages would move the mean) equals a fixed 2048 spp reference, tile by
/// tile. Each of the 16 tiles passes a z-test |z| < 4.2 (two-sided α = 1e-3 over the 16 tests,
/// Bonferroni), σ² being the spread of the tile's 48 adaptive means over seeds / 48 plus the
/// reference's own squared standard error (from its per-pixel standard errors; pixels are
/// independent). Broken on purpose (each pixel's count from its own pilot, which its estimate
/// averages in), it fails with |z| = 9.3; as written, the largest |z| is 1.6. (A pixel's own
/// pilot counted among its eight neighbours' is a bias too weak for this test to see.)
#[test]
fn adaptive_mean_matches_the_fixed_reference() {
    let (reference, ref_err) = render(Spp::Fixed(2048), 1_000_003);
    let ref_tiles = tile_means(&reference);
    // Variance of a tile's mean: the sum of its pixels' squared standard errors / 16².
    let se_y = |e: &PixelErrors, i: usize| e.stderr[i * e.stderr.len() / reference.len() + 1];
    let ref_var = tile_means(
        &(0..reference.len())
            .map(|i| se_y(&ref_err, i).powi(2) / (T * T) as f32)
            .collect::<Vec<_>>(),
    );
    let seeds = 48;
    let runs: Vec<Vec<f64>> = (0..seeds)
        .map(|s| tile_means(&render(adaptive(0.1, 4, 64), 7 + s).0))
        .collect();
    let mut worst = 0.0f64;
    for t in 0..ref_tiles.len() {
        let xs: Vec<f64> = runs.iter().map(|r| r[t]).collect();
        let mean = xs.iter().sum::<f64>() / seeds as f64;
        let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (seeds - 1) as f64;
        let z = (mean - ref_tiles[t]) / (var / seeds as f64 + ref_var[t]).sqrt();
        eprintln!(
            "tile {t:2}: adaptive {mean:.5} reference {:.5} z {z:+.2}",
            ref_tiles[t]
        );
        worst = worst.max(z.abs());
    }
    assert!(
        worst < 4.2,
        "a tile's adaptive mean is off: |z| = {worst:.2}"
    );
}

/// A pixel's adaptive value is the fixed render of its own count, bit for bit: the estimate is
/// the first n samples of the pixel's ordinary stream, its pilot (the first `min`) included. So is its
/// `alpha` (coverage of those very rays). Counts span 2..8 here (rel_error 0.02, min 2, max 8).
#[test]
fn a_pixel_is_the_fixed_render_of_its_count() {
    let (y, e) = render(adaptive(0.02, 2, 8), 5);
    let coverage = |j: &prism::load::Job, counts| {
        prism::integrator::aov::coverage(&j.scene, &j.settings, counts)
    };
    let alpha = coverage(&job(adaptive(0.02, 2, 8), 5), Some(&e.spp));
    assert!(e.spp.iter().all(|&n| (2..=8).contains(&n)));
    let mut checked = 0;
    for n in 2..=8u32 {
        if !e.spp.contains(&n) {
            continue;
        }
        let (fixed, _) = render(Spp::Fixed(n), 5);
        let fixed_alpha = coverage(&job(Spp::Fixed(n), 5), None);
        for (i, _) in e.spp.iter().enumerate().filter(|(_, &c)| c == n) {
            assert_eq!(y[i].to_bits(), fixed[i].to_bits(), "pixel {i} at {n} spp");
            assert_eq!(alpha[i], fixed_alpha[i], "alpha of pixel {i} at {n} spp");
            checked += 1;
        }
    }
    assert_eq!(checked, y.len());
    // Not every pixel took the same count: the pilot did decide something.
    assert!(e.spp.iter().any(|&n| n != e.spp[0]));
}

/// The error target is met where `max` allows it: the achieved standard error of Y (the
/// `stderr` values) over Y, pooled as a root mean square over pixels that stopped below `max`,
/// is within 1.5× the target. (Each pixel's count comes from its neighbours' 64-sample pilots, so
/// single pixels scatter about the target; the pool does not.) With a fixed spp the `spp`
/// counts are that spp everywhere.
#[test]
fn the_error_target_is_met() {
    let target = 0.1;
    let (y, e) = render(adaptive(target, 64, 4096), 11);
    let slots = e.stderr.len() / y.len();
    let ratios: Vec<f64> = (0..y.len())
        .filter(|&i| e.spp[i] < 4096 && y[i] > 1e-3)
        .map(|i| e.stderr[i * slots + 1] as f64 / y[i] as f64)
        .collect();
    assert!(ratios.len() > y.len() / 2, "{} pixels met it", ratios.len());
    let rms = (ratios.iter().map(|r| r * r).sum::<f64>() / ratios.len() as f64).sqrt();
    eprintln!("rms relative error {rms:.4} over {} pixels", ratios.len());
    assert!(rms < 1.5 * target as f64, "rms relative error {rms}");
    let (_, fixed) = render(Spp::Fixed(3), 11);
    assert!(fixed.spp.iter().all(|&n| n == 3));
}

/// The same adaptive render on 1 and 2 threads: the same bits, counts and errors.
#[test]
fn adaptive_is_deterministic_at_any_thread_count() {
    let on = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| render(adaptive(0.05, 4, 32), 3))
    };
    let ((y1, e1), (y2, e2)) = (on(1), on(2));
    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&y1), bits(&y2));
    assert_eq!(e1.spp, e2.spp);
    assert_eq!(bits(&e1.stderr), bits(&e2.stderr));
}

/// `prism render --rel-error`: renders adaptively (the summary and the EXR header say so);
/// with `--spp` it is refused, and bad `Adaptive` fields are errors naming the field, exit 2,
/// no output.
#[test]
fn the_command_line_takes_rel_error() {
    let dir = std::env::temp_dir().join(format!("prism-adaptive-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = |name: &str, spp: &str| {
        let p = dir.join(name);
        let text = format!(
            "(film: (width: 8, height: 6), sampler: (spp: {spp}), \
             materials: {{ \"grey\": Diffuse(reflectance: Constant(0.5)) }}, \
             shapes: [(shape: Sphere(center: (0, 0, 4)), material: \"grey\")], \
             emitters: [Constant(radiance: Named(\"D65\"))])"
        );
        std::fs::write(&p, text).unwrap();
        p
    };
    let run = |scene: &Path, extra: &[&str]| {
        let out = dir.join("out.exr");
        let _ = std::fs::remove_file(&out);
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_prism"))
            .arg("render")
            .arg(scene)
            .arg("-o")
            .arg(&out)
            .args(extra)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr).into_owned();
        (o.status.code().unwrap_or(-1), err, out.exists())
    };
    let good = scene("good.ron", "4");
    let (code, err, written) = run(&good, &["--rel-error", "0.05", "--aovs", "spp"]);
    assert!(code == 0 && written, "{err}");
    assert!(
        err.contains("at Adaptive(rel_error: 0.05, min: 16, max: 4096"),
        "{err}"
    );
    let (code, err, written) = run(&good, &["--rel-error", "0.05", "--spp", "4"]);
    assert!(code == 2 && !written, "{err}");
    for (spp, field) in [
        (
            "Adaptive(rel_error: 0.1, min: 8, max: 4)",
            "sampler.spp.max",
        ),
        (
            "Adaptive(rel_error: -1, min: 8, max: 16)",
            "sampler.spp.rel_error",
        ),
        ("Adaptive(rel_error: 0.1, min: 8)", "max"),
    ] {
        let (code, err, written) = run(&scene("bad.ron", spp), &[]);
        assert!(code == 2 && !written && err.contains(field), "{spp}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A pixel alone in its tile (a 1×1 film here) has no neighbour: its count comes from a pilot
/// of its own stream (discarded), and its value is the fixed render of that count, bit for bit.
#[test]
fn a_lone_pixel_takes_a_pilot_of_its_own() {
    let one = |spp: Spp| {
        let job = prism::load::load(Path::new("scenes/cornell.ron"), |cfg| {
            cfg.film.width = 1;
            cfg.film.height = 1;
            cfg.sampler.spp = spp;
            cfg.sampler.seed = 3;
        })
        .unwrap();
        let (film, stats, errors) =
            render_film(&job.scene, &job.settings, &job.channels, true, &|_| {});
        (film.channel("Y").unwrap()[0], stats.samples, errors.spp[0])
    };
    let (y, samples, n) = one(adaptive(0.05, 8, 256));
    assert!((8..=256).contains(&n), "{n}");
    // The pilot's 8 samples are taken on top of the estimate's n.
    assert_eq!(samples, n as u64 + 8);
    let (fixed, _, _) = one(Spp::Fixed(n));
    assert_eq!(y.to_bits(), fixed.to_bits());
}
