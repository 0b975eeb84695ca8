//! Tests of `envmap`: texel placement (as Mitsuba), interpolation, the sampling density and its
//! agreement with sampling, and the bright cells (a sun) sampled by energy.

use super::*;
use crate::math::portable;

fn image(w: usize, h: usize, f: impl Fn(usize, usize) -> [f32; 3]) -> RgbImage {
    RgbImage {
        width: w,
        height: h,
        pixels: (0..h)
            .flat_map(|j| (0..w).map(move |i| (i, j)))
            .map(|(i, j)| f(i, j))
            .collect(),
        source: None,
    }
}

fn wl(lambda: f32) -> Wavelengths<1> {
    Wavelengths {
        lambda: [lambda],
        pdf: [1.0],
    }
}

#[test]
fn texel_centres_land_where_mitsuba_puts_them() {
    // One bright texel at column 3, row 2 of a 16×9 map: φ = 2π·3.5/16, θ = π·2/8.
    let img = image(
        16,
        9,
        |i, j| {
            if (i, j) == (3, 2) {
                [1.0; 3]
            } else {
                [0.0; 3]
            }
        },
    );
    let m = EnvMap::new(&img, 1.0, Mat3::IDENTITY);
    let (phi, theta) = (2.0 * PI * 3.5 / 16.0, PI * 0.25);
    let d = Vec3::new(
        portable::sin(phi) * portable::sin(theta),
        portable::cos(theta),
        -portable::cos(phi) * portable::sin(theta),
    );
    let d65 = m.d65.eval(550.0);
    let at = m.eval(d, &wl(550.0))[0] / d65;
    assert!((at - 1.0).abs() < 1e-3, "{at}");
    // Half a texel to the side, next to black texels: both the sigmoid and the scale are
    // halved, so the value is ¼ (Mitsuba interpolates them separately and multiplies).
    let phi2 = phi + PI / 16.0;
    let d2 = Vec3::new(
        portable::sin(phi2) * portable::sin(theta),
        portable::cos(theta),
        -portable::cos(phi2) * portable::sin(theta),
    );
    let half = m.eval(d2, &wl(550.0))[0] / d65;
    assert!((half - 0.25).abs() < 1e-3, "{half}");
}

#[test]
fn colours_interpolate_sigmoid_and_scale_separately() {
    // Between a red and a blue texel: (s_r + s_b)/2 · (f_r + f_b)/2 · D65, Mitsuba's formula.
    let img = image(2, 3, |i, _| {
        if i == 0 {
            [0.8, 0.1, 0.1]
        } else {
            [0.05, 0.1, 0.4]
        }
    });
    let m = EnvMap::new(&img, 2.0, Mat3::IDENTITY);
    // u = ½ is halfway between column centres ¼ and ¾: the +z direction on the horizon.
    let lambda = 610.0;
    let got = m.eval(Vec3::Z, &wl(lambda))[0];
    let (sr, sb) = (m.sigmoids[0].eval(lambda), m.sigmoids[1].eval(lambda));
    let expect = 0.5 * (sr + sb) * 0.5 * (1.6 + 0.8) * 2.0 * m.d65.eval(lambda);
    assert!((got / expect - 1.0).abs() < 1e-5, "{got} vs {expect}");
}

/// The density follows luminance (Rec. 709 Y of the RGB, not e.g. its mean or maximum): at a
/// cell's centre the interpolated luminance is the mean of its four corners', and the solid-
/// angle pdf there must be that times one constant. The only departure is the cell's mean
/// of sin θ against sin θ at its centre, < 1e-3 relative for these 32 rows (Δθ ≈ 5.8°).
#[test]
fn pdf_is_proportional_to_luminance() {
    let (w, h) = (64, 32);
    // Colours whose luminance ordering differs from their mean's and maximum's.
    let img = image(w, h, |i, j| match (i * 7 + j * 3) % 4 {
        0 => [0.9, 0.05, 0.05],
        1 => [0.05, 0.6, 0.05],
        2 => [0.05, 0.05, 1.5],
        _ => [0.3, 0.3, 0.3],
    });
    let m = EnvMap::new(&img, 1.0, Mat3::IDENTITY);
    let lum = |i: usize, j: usize| luminance(img.pixels[j * w + i % w]) as f64;
    let mut ratios = Vec::new();
    for j in 4..h - 5 {
        for i in 0..w {
            let corners = 0.25 * (lum(i, j) + lum(i + 1, j) + lum(i, j + 1) + lum(i + 1, j + 1));
            let theta = PI * (j as f32 + 0.5) / (h - 1) as f32;
            let phi = 2.0 * PI * (i as f32 + 1.0) / w as f32;
            let d = Vec3::new(
                portable::sin(phi) * portable::sin(theta),
                portable::cos(theta),
                -portable::cos(phi) * portable::sin(theta),
            );
            ratios.push(m.pdf(d) as f64 / corners);
        }
    }
    let (lo, hi) = ratios
        .iter()
        .fold((f64::MAX, 0.0f64), |(a, b), &r| (a.min(r), b.max(r)));
    assert!(hi / lo - 1.0 < 1e-3, "pdf / luminance spans {lo}..{hi}");
}

#[test]
fn pdf_integrates_to_one_and_matches_sampling() {
    let img = image(12, 7, |i, j| [(i * j) as f32 * 0.1 + 0.01, 0.2, 0.0]);
    let rot = Mat3::from_mat4(crate::math::rotation::axis_angle(
        Vec3::new(1.0, 1.0, 0.0).normalize(),
        0.7,
    ));
    let m = EnvMap::new(&img, 1.0, rot);
    // ∫ pdf dω over the sphere by a fine midpoint rule in (cos θ, φ) of the world frame.
    let n = 600;
    let mut total = 0.0f64;
    for a in 0..n {
        let z = 1.0 - 2.0 * (a as f32 + 0.5) / n as f32;
        let r = (1.0 - z * z).sqrt();
        for b in 0..2 * n {
            let p = 2.0 * PI * (b as f32 + 0.5) / (2 * n) as f32;
            total += m.pdf(Vec3::new(r * portable::cos(p), r * portable::sin(p), z)) as f64;
        }
    }
    total *= 4.0 * std::f64::consts::PI / (2 * n * n) as f64;
    assert!((total - 1.0).abs() < 2e-3, "∫pdf = {total}");
    // A sample within rounding of a cell edge may read back the neighbouring cell's density
    // (a set of measure zero); allow a few of those among 1000 samples.
    let mut differ = 0;
    for k in 0..1000 {
        let u = Vec2::new(
            (k as f32 * 0.618_034 + 0.1).fract(),
            (k as f32 + 0.5) / 1000.0,
        );
        if let Some((d, pdf)) = m.sample(u) {
            let q = m.pdf(d);
            if (q / pdf - 1.0).abs() > 1e-3 {
                differ += 1;
            }
        }
    }
    assert!(differ <= 3, "{differ} samples' pdf differs from pdf()");
}

/// The bright cells of a map with a 3×2-texel sun: exactly the cells the sun's texels
/// touch, and `sample_bright` draws them by energy (chi-square over the cells, expected
/// counts from the cells' probabilities), lands in the cell it chose (`cell`), and its
/// density is right (E[1/pdf] is the set's solid angle).
#[test]
fn bright_cells_hold_the_sun_and_sample_it_by_energy() {
    let (w, h) = (32, 17);
    let sun = |i: usize, j: usize| (10..13).contains(&i) && (4..6).contains(&j);
    let img = image(w, h, |i, j| {
        if sun(i, j) {
            [300.0 + 40.0 * i as f32, 280.0, 250.0 + 30.0 * j as f32]
        } else {
            [0.4, 0.5, 0.9]
        }
    });
    let m = EnvMap::new(
        &img,
        1.0,
        Mat3::from_mat4(crate::math::rotation::axis_angle(Vec3::Y, 0.7)),
    );
    // Corner cells touching one sun texel hold ~20× the mean, sky cells ~0.15×.
    let b = m.bright_cells(5.0).expect("the sun is bright");
    // A cell between columns i, i+1 and rows j, j+1 is bright iff a corner is sun.
    for j in 0..h - 1 {
        for i in 0..w {
            let touches = [(i, j), ((i + 1) % w, j), (i, j + 1), ((i + 1) % w, j + 1)]
                .iter()
                .any(|&(x, y)| sun(x, y));
            assert_eq!(b.contains(j * w + i), touches, "cell ({i}, {j})");
        }
    }
    let total: f64 = b
        .ids
        .iter()
        .map(|&c| m.cell_probability(c as usize) as f64)
        .sum();
    let mut counts = vec![0.0f64; w * (h - 1)];
    let n = 200_000;
    let mut rng = crate::math::rng::Pcg32::new(4, 2);
    for _ in 0..n {
        let u = Vec2::new(rng.next_f32(), rng.next_f32());
        let (d, pdf) = m.sample_bright(&b, u).unwrap();
        let c = m.cell(d);
        assert!(b.contains(c), "sampled outside the set");
        assert!(pdf > 0.0);
        counts[c] += 1.0;
    }
    let (mut chi2, mut dof) = (0.0, 0);
    for &c in &b.ids {
        let e = m.cell_probability(c as usize) as f64 / total * n as f64;
        chi2 += (counts[c as usize] - e).powi(2) / e;
        dof += 1;
    }
    // dof − 1 degrees of freedom; the 1e-4 quantile is below dof + 4√(2 dof) + 10.
    let limit = dof as f64 + 4.0 * (2.0 * dof as f64).sqrt() + 10.0;
    assert!(
        chi2 < limit,
        "χ² = {chi2:.1} over {dof} cells (limit {limit:.1})"
    );
    // The density is right if E[1/pdf] over its samples is the solid angle of the set it
    // covers: here the bright cells' solid angles in closed form, (cos θ₀ − cos θ₁)·2π/w
    // per cell (not the sampler's own formula). Tolerance 4 standard errors.
    let rows = h - 1;
    let omega: f64 = b
        .ids
        .iter()
        .map(|&c| {
            let j = c as usize / w;
            let (t0, t1) = (
                std::f64::consts::PI * j as f64 / rows as f64,
                std::f64::consts::PI * (j + 1) as f64 / rows as f64,
            );
            (portable::cos(t0) - portable::cos(t1)) * 2.0 * std::f64::consts::PI / w as f64
        })
        .sum();
    let (mean, se) = inverse_pdf_mean(n, |u| m.sample_bright(&b, u));
    assert!(
        (mean - omega).abs() < 4.0 * se,
        "E[1/pdf] = {mean} ± {se}, solid angle of the bright cells {omega}"
    );
}

/// Mean and standard error of 1/pdf over `n` samples of `sample` (fixed seed).
fn inverse_pdf_mean(n: usize, sample: impl Fn(Vec2) -> Option<(Vec3, f32)>) -> (f64, f64) {
    let mut rng = crate::math::rng::Pcg32::new(19, 5);
    let (mut s1, mut s2) = (0.0f64, 0.0f64);
    for _ in 0..n {
        let u = Vec2::new(rng.next_f32(), rng.next_f32());
        let x = sample(u).map_or(0.0, |(_, pdf)| 1.0 / pdf as f64);
        s1 += x;
        s2 += x * x;
    }
    let mean = s1 / n as f64;
    (
        mean,
        ((s2 / n as f64 - mean * mean) / (n - 1) as f64).sqrt(),
    )
}

/// `sample`'s density, checked without the pdf formula: every texel is lit, so the samples
/// cover the whole sphere and E[1/pdf] must be 4π (4 standard errors).
#[test]
fn sampling_density_covers_the_sphere() {
    let img = image(12, 7, |i, j| [(i * j) as f32 * 0.1 + 0.01, 0.2, 0.0]);
    let m = EnvMap::new(
        &img,
        1.0,
        Mat3::from_mat4(crate::math::rotation::axis_angle(Vec3::X, 0.4)),
    );
    let (mean, se) = inverse_pdf_mean(400_000, |u| m.sample(u));
    let four_pi = 4.0 * std::f64::consts::PI;
    assert!(
        (mean - four_pi).abs() < 4.0 * se,
        "E[1/pdf] = {mean} ± {se}, expected 4π"
    );
}
