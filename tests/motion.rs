//! Time: animated scenes at an instant, motion blur and the rolling shutter, against closed
//! forms (issue 30).
//!
//! The blur scenes put a black (albedo 0) shape in front of a white constant environment seen
//! directly: every camera sample is exactly 1 (background) or 0 (shape), so a pixel's value is
//! the fraction of its area × shutter time the shape leaves uncovered, and its Monte Carlo
//! spread is at most a Bernoulli one, √(p(1 − p)/spp).

use prism::film::Film;
use std::path::Path;

fn render(text: &str) -> Film {
    let job = prism::load::load_str(text, Path::new("inline.ron")).unwrap();
    prism::integrator::render(&job.scene, &job.settings, &job.channels, &|_| {}).0
}

/// The film's luminance-free test channel: the mean band (every band is the same 0/1 value).
fn values(film: &Film) -> Vec<f32> {
    film.channel("S0.550,000000nm")
        .or_else(|| film.channel("Y"))
        .expect("a band or Y")
        .to_vec()
}

/// A white world seen by an orthographic camera 8 units wide looking along −z, with
/// `shapes` (black) and `camera` fields spliced in.
fn scene(w: u32, h: u32, spp: u32, camera: &str, shapes: &str) -> String {
    format!(
        r#"(
    camera: (model: Orthographic(width: 8), {camera}),
    film: (width: {w}, height: {h}, filter: Box()),
    sampler: (spp: {spp}, seed: 5),
    spectral: (sampling: Uniform, range: (500, 600), wavelengths: 1),
    outputs: (rgb: false, xyz: false, bands: 1, band_range: (500, 600)),
    materials: {{ "black": Diffuse(reflectance: Constant(0.0)) }},
    shapes: [{shapes}],
    emitters: [Constant(radiance: Constant(1.0))],
)"#
    )
}

const LOOK: &str = "to_world: [LookAt(origin: (0, 0, 5), target: (0, 0, 0), up: (0, 1, 0))]";

/// An animated sphere rendered at an instant (shutter open = close) is bit for bit the static
/// scene with the interpolated transform written out, for every interpolation.
#[test]
fn an_instant_of_an_animation_is_the_static_scene() {
    let keys = "keys: [(time: 0, to_world: [Translate((-1, 0, 0))]), (time: 2, to_world: [Translate((3, 0, 0))]), (time: 4, to_world: [Translate((3, 2, 0))])]";
    // At t = 0.5: Linear x = −1 + 4·0.25 = 0; Step holds the first key; at t = 2 Cubic
    // (Catmull-Rom) passes through its key exactly.
    for (interp, t, at) in [
        ("Linear", 0.5, "(0, 0, 0)"),
        ("Step", 0.5, "(-1, 0, 0)"),
        ("Cubic", 2.0, "(3, 0, 0)"),
    ] {
        let anim = format!(
            "(shape: Sphere(radius: 1), material: \"black\", animation: (interpolation: {interp}, {keys}))"
        );
        let fixed =
            format!("(shape: Sphere(radius: 1), material: \"black\", to_world: [Translate({at})])");
        let shutter = format!("{LOOK}, shutter: (open: {t}, close: {t})");
        let a = values(&render(&scene(24, 12, 4, &shutter, &anim)));
        let b = values(&render(&scene(24, 12, 4, LOOK, &fixed)));
        assert!(
            a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits()),
            "{interp} at {t}: the animated render differs from the static one"
        );
    }
}

/// Film position (pixels) → world (x, y) for `scene`'s camera: 8 units over `w` pixels.
fn world(fx: f64, fy: f64, w: u32, h: u32) -> (f64, f64) {
    let unit = 8.0 / w as f64;
    ((fx - 0.5 * w as f64) * unit, (0.5 * h as f64 - fy) * unit)
}

/// A unit sphere moving from x = −2 to x = 2 while the shutter is open (0 to 1 s). A point
/// (x, y) with |y| < 1 is covered while the centre c(t) = −2 + 4t lies within
/// w = √(1 − y²) of x: for a time |[x − w, x + w] ∩ [−2, 2]| / 4. Each pixel's expected value
/// is 1 minus that, averaged over its area (16 × 16 points). Per pixel the error must stay
/// within 5 Bernoulli standard deviations at 256 spp (0.16), and the mean error over the image
/// within 5 of its own (0.16 / √n); a render at one instant fails both by far.
#[test]
fn a_moving_sphere_covers_its_closed_form_time_average() {
    let (w, h, spp) = (48u32, 16u32, 256u32);
    let shape = r#"(shape: Sphere(radius: 1), material: "black", animation: (keys: [
        (time: 0, to_world: [Translate((-2, 0, 0))]), (time: 1, to_world: [Translate((2, 0, 0))])]))"#;
    let cam = format!("{LOOK}, shutter: (open: 0, close: 1)");
    let v = values(&render(&scene(w, h, spp, &cam, shape)));
    let covered = |x: f64, y: f64| {
        if y.abs() >= 1.0 {
            return 0.0;
        }
        let r = (1.0 - y * y).sqrt();
        ((x + r).min(2.0) - (x - r).max(-2.0)).max(0.0) / 4.0
    };
    let n = 16;
    let mut worst = 0.0f64;
    let mut sum = 0.0;
    for py in 0..h {
        for px in 0..w {
            let mut c = 0.0;
            for i in 0..n {
                for j in 0..n {
                    let fx = px as f64 + (i as f64 + 0.5) / n as f64;
                    let fy = py as f64 + (j as f64 + 0.5) / n as f64;
                    let (x, y) = world(fx, fy, w, h);
                    c += covered(x, y);
                }
            }
            let expect = 1.0 - c / (n * n) as f64;
            let err = v[(py * w + px) as usize] as f64 - expect;
            worst = worst.max(err.abs());
            sum += err;
        }
    }
    let bound = 5.0 * 0.5 / (spp as f64).sqrt();
    let mean = sum / (w * h) as f64;
    eprintln!("moving sphere: worst pixel error {worst:.4} (bound {bound:.4}), mean {mean:.2e}");
    assert!(worst < bound, "worst pixel error {worst} ≥ {bound}");
    assert!(
        mean.abs() < bound / ((w * h) as f64).sqrt(),
        "mean error {mean}"
    );
}

/// A rolling shutter: an instant per row (open = close = 0), row y read at y · 2 ms. A black
/// bar 1 unit wide moving at 60 units/s is at x = −3 + 60 · 0.002 · y in row y: its centre
/// shifts 0.12 units (0.72 px at 6 px/unit) per row. The fitted slope of each row's bar centre
/// (the coverage-weighted mean of the pixel centres: exact up to a few hundredths of a pixel,
/// its partial edge pixels) must match it to 1%; a global shutter gives slope 0.
#[test]
fn a_rolling_shutter_skews_a_moving_bar_by_its_closed_form() {
    let (w, h) = (48u32, 40u32);
    let bar = r#"(shape: Rectangle, material: "black", animation: (keys: [
        (time: 0, to_world: [Scale((0.5, 10, 1)), Translate((-3, 0, 0))]),
        (time: 1, to_world: [Scale((0.5, 10, 1)), Translate((57, 0, 0))])]))"#;
    let cam = format!("{LOOK}, shutter: (open: 0, close: 0, readout: 0.002)");
    let v = values(&render(&scene(w, h, 16, &cam, bar)));
    let centres: Vec<(f64, f64)> = (0..h)
        .map(|y| {
            let (mut s, mut sx) = (0.0, 0.0);
            for x in 0..w {
                let c = 1.0 - v[(y * w + x) as usize] as f64;
                s += c;
                sx += c * (x as f64 + 0.5);
            }
            (y as f64, sx / s)
        })
        .collect();
    let n = centres.len() as f64;
    let (my, mx) = (
        centres.iter().map(|c| c.0).sum::<f64>() / n,
        centres.iter().map(|c| c.1).sum::<f64>() / n,
    );
    let slope = centres.iter().map(|c| (c.0 - my) * (c.1 - mx)).sum::<f64>()
        / centres.iter().map(|c| (c.0 - my).powi(2)).sum::<f64>();
    let want = 60.0 * 0.002 * w as f64 / 8.0;
    eprintln!("rolling shutter: skew {slope:.5} px/row, closed form {want}");
    assert!(
        (slope - want).abs() < 0.01 * want,
        "skew {slope} px/row, closed form {want}"
    );
    // Row 0 is read at t = 0: the bar's centre at x = −3 (pixel 6).
    let (x0, _) = world(centres[0].1, 0.0, w, h);
    assert!((x0 + 3.0).abs() < 0.05, "row 0 centre at x = {x0}");
}

/// Motion blur equals, within noise, the average of renders at 32 instants evenly spread
/// over the shutter (the midpoint rule), for a sliding, spinning cube seen by a panning and
/// turning perspective camera: the open-shutter render carries each camera ray from the
/// opening pose, the instants build the camera at their pose. Compared per column (sums over
/// rows): the difference must lie within 5 standard deviations of the two renders' Bernoulli
/// noise plus 0.5% of the column for the midpoint rule's own error.
#[test]
fn motion_blur_is_the_average_of_instants() {
    let (w, h) = (40u32, 24u32);
    let cube = r#"(shape: Cube, material: "black", animation: (interpolation: Cubic, keys: [
        (time: 0, to_world: [Scale((0.6, 0.6, 0.6)), Translate((-1.5, 0, 0))]),
        (time: 0.5, to_world: [Scale((0.6, 0.6, 0.6)), Rotate(axis: (0, 0, 1), angle: 40), Translate((0, 0.4, 0))]),
        (time: 1, to_world: [Scale((0.6, 0.6, 0.6)), Rotate(axis: (0, 0, 1), angle: 90), Translate((1.5, 0, 0))])]))"#;
    let cam = |shutter: &str| {
        format!(
            r#"fov: 60, animation: (keys: [
            (time: 0, to_world: [LookAt(origin: (-0.5, 0, 5), target: (0, 0, 0), up: (0, 1, 0))]),
            (time: 1, to_world: [LookAt(origin: (0.5, 0.3, 5), target: (0.2, 0, 0), up: (0, 1, 0))])]),
            shutter: {shutter}"#
        )
    };
    let persp = |s: String| s.replace("model: Orthographic(width: 8), ", "");
    let spp = 256;
    let blur = values(&render(&persp(scene(
        w,
        h,
        spp,
        &cam("(open: 0, close: 1)"),
        cube,
    ))));
    let k = 32;
    let mut avg = vec![0.0f64; blur.len()];
    for i in 0..k {
        let t = (i as f64 + 0.5) / k as f64;
        let s = persp(scene(
            w,
            h,
            spp / 8,
            &cam(&format!("(open: {t}, close: {t})")),
            cube,
        ));
        for (a, v) in avg.iter_mut().zip(values(&render(&s))) {
            *a += v as f64 / k as f64;
        }
    }
    let mut moving = 0;
    let mut worst = 0.0f64;
    for x in 0..w as usize {
        let (mut b, mut a, mut var) = (0.0, 0.0, 0.0);
        for y in 0..h as usize {
            let (pb, pa) = (blur[y * w as usize + x] as f64, avg[y * w as usize + x]);
            b += pb;
            a += pa;
            var += pb * (1.0 - pb) / spp as f64 + pa * (1.0 - pa) / (spp / 8 * k) as f64;
        }
        if var > 0.0 {
            moving += 1;
        }
        let tol = 5.0 * var.sqrt() + 5e-3 * h as f64;
        worst = worst.max((b - a).abs() / tol);
        assert!(
            (b - a).abs() < tol,
            "column {x}: blur {b}, instants {a}, tolerance {tol}"
        );
    }
    eprintln!("blur vs instants: worst column difference {worst:.3} of its tolerance");
    assert!(moving > w / 2, "only {moving} columns see the cube move");
}

/// `alpha` retraces the colour pass's own camera rays, times included: behind a moving black
/// sphere on white, each sample is 0 exactly when it hits, so alpha + value = 1 in every
/// pixel (to 1e-6, the f32 rounding of two means of 0/1 samples). Rays at another time than
/// the colour pass's would miss this by whole samples (1/64).
#[test]
fn alpha_follows_the_blurred_samples() {
    let shape = r#"(shape: Sphere(radius: 1), material: "black", animation: (keys: [
        (time: 0, to_world: [Translate((-2, 0, 0))]), (time: 1, to_world: [Translate((2, 0, 0))])]))"#;
    let cam = format!("{LOOK}, shutter: (open: 0, close: 1)");
    let text = scene(32, 12, 64, &cam, shape).replace("shapes:", "aovs: [\"alpha\"], shapes:");
    let job = prism::load::load_str(&text, Path::new("inline.ron")).unwrap();
    let r = prism::pipeline::render(&job, 1.0, &|_| {});
    let v = values(&r.film);
    let a = r.film.channel("alpha.A").unwrap();
    let partial = a.iter().filter(|&&x| x > 0.0 && x < 1.0).count();
    assert!(partial > 20, "only {partial} blurred pixels");
    for (i, (x, y)) in v.iter().zip(a).enumerate() {
        assert!(
            (x + y - 1.0).abs() < 1e-6,
            "pixel {i}: value {x}, alpha {y}"
        );
    }
}

/// A chained motion (`Motion::under`: a moving parent, a static offset, a moving child) is
/// the product parent(t) · offset · child(t) at every time (to 1e-5), and its `bounds` over
/// [0.1, 0.9] hold the moving box at 1000 times of it, though neither track alone moves the
/// box that way (the parent turns 2.5 rad while the child slides along the turning axis).
#[test]
fn a_chained_motion_is_the_product_and_its_bounds_hold() {
    use glam::{Mat4, Quat, Vec3};
    use prism::motion::{Interp, Motion, Track};
    fn lin<T>(times: Vec<f32>, values: Vec<T>) -> Track<T> {
        Track {
            times,
            values,
            tangents: Vec::new(),
            interp: Interp::Linear,
        }
    }
    let parent = Motion::trs(
        lin(vec![0.0, 1.0], vec![Vec3::ZERO, Vec3::new(3.0, 1.0, 0.0)]),
        lin(
            vec![0.0, 1.0],
            vec![Quat::IDENTITY, prism::math::rotation::quat(Vec3::Y, 2.5)],
        ),
        Track::constant(Vec3::ONE),
    );
    let child = Motion::trs(
        lin(vec![0.2, 0.7], vec![Vec3::ZERO, Vec3::new(4.0, 0.0, 0.0)]),
        Track::constant(prism::math::rotation::quat(Vec3::Z, 0.3)),
        lin(vec![0.0, 1.0], vec![Vec3::ONE, Vec3::new(0.5, 2.0, 1.0)]),
    );
    let offset = Mat4::from_scale_rotation_translation(
        Vec3::new(1.0, 2.0, 0.5),
        prism::math::rotation::quat(Vec3::X, 0.4),
        Vec3::new(0.0, 0.0, 1.0),
    );
    let chain = child.clone().under(parent.clone(), offset);
    assert_eq!(chain.key_span(), Some((0.0, 1.0)));
    let obj = (Vec3::splat(-1.0), Vec3::splat(1.0));
    let (lo, hi) = chain.bounds(obj, 0.1, 0.9);
    for i in 0..=1000 {
        let t = 0.1 + 0.8 * i as f32 / 1000.0;
        let want = parent.matrix(t) * offset * child.matrix(t);
        let m = chain.matrix(t);
        assert!(m.abs_diff_eq(want, 1e-5), "t {t}: {m} vs {want}");
        for c in 0..8 {
            let v = Vec3::new(
                if c & 1 != 0 { 1.0 } else { -1.0 },
                if c & 2 != 0 { 1.0 } else { -1.0 },
                if c & 4 != 0 { 1.0 } else { -1.0 },
            );
            let p = m.transform_point3(v);
            assert!(p.cmpge(lo).all() && p.cmple(hi).all(), "t {t}: {p} outside");
        }
    }
}
