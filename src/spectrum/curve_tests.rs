//! Tests of `Curve` (curve.rs): tabulated interpolation, dense lanes against the scalar path, Planck's
//! law against reference values and Wien's displacement, and unit luminance.

use super::*;

#[test]
fn tabulated_forms_interpolate() {
    let even = Curve::from_samples(&[400.0, 500.0, 600.0], &[0.0, 1.0, 0.5]);
    assert!(matches!(even, Curve::Dense(_)));
    assert!((even.eval_one(450.0) - 0.5).abs() < 1e-6);
    assert!((even.eval_one(600.0) - 0.5).abs() < 1e-6);
    assert_eq!(even.eval_one(399.0), 0.0);
    // Knots off any common grid of their smallest interval (10.5 nm).
    let uneven = Curve::from_samples(&[400.0, 410.5, 600.0], &[0.0, 1.0, 0.0]);
    assert!(matches!(uneven, Curve::Irregular { .. }));
    assert!((uneven.eval_one(505.25) - 0.5).abs() < 1e-5);
    assert_eq!(uneven.support(), Some((400.0, 600.0)));
}

/// Knots on a common grid (a table padded with far knots, as the reflectance library pads its
/// 10 nm tables, and one with a half-step interval) make a `Dense` curve through the same
/// points: equal to the `Irregular` curve at the knots, within 10⁻⁵ between them, 0 outside.
/// (A dense lookup places λ on the grid in f32, (λ − start) · (1/step) with the reciprocal
/// rounded: up to ~10⁻⁵ of a cell off at 80 cells out, times these tables' slope of ≤ 1 per
/// cell; measured reflectances carry 3–4 digits.) Knots off the grid, or a grid finer than
/// `MAX_GRID` points, stay `Irregular`.
#[test]
fn knots_on_a_common_grid_make_a_dense_curve() {
    let padded: Vec<f64> = [300.0]
        .into_iter()
        .chain((0..36).map(|i| 380.0 + 10.0 * i as f64))
        .chain([1130.0])
        .collect();
    let halves = vec![400.0, 400.5, 401.0, 420.0, 700.0];
    for nm in [padded, halves] {
        let values: Vec<f64> = (0..nm.len())
            .map(|i| 0.05 + (i * 7 % 11) as f64 / 12.0)
            .collect();
        let c = Curve::from_samples(&nm, &values);
        assert!(matches!(c, Curve::Dense(_)), "{nm:?} is on a grid");
        let irregular = Curve::Irregular {
            nm: Knots::new(nm.iter().map(|&v| v as f32).collect()),
            values: values.iter().map(|&v| v as f32).collect(),
        };
        for (&l, &v) in nm.iter().zip(&values) {
            assert_eq!(c.eval_one(l as f32), v as f32, "knot {l}");
        }
        let (lo, hi) = (nm[0] as f32, nm[nm.len() - 1] as f32);
        for k in 0..=4000 {
            let l = lo - 5.0 + (hi - lo + 10.0) * k as f32 / 4000.0;
            let (a, b) = (c.eval_one(l), irregular.eval_one(l));
            assert!((a - b).abs() <= 1e-5, "{l} nm: {a} against {b}");
        }
        assert_eq!(c.support(), irregular.support());
    }
    let fine = Curve::from_samples(&[400.0, 400.01, 700.0], &[0.0, 1.0, 0.0]);
    assert!(
        matches!(fine, Curve::Irregular { .. }),
        "30,000 grid points"
    );
}

#[test]
fn dense_lanes_match_scalar_bit_for_bit() {
    // The D65 table, a two-sample curve and an odd one; wavelengths inside, on the knots and
    // ends, outside on both sides, and NaN; 6 lanes, so the scalar tail runs too.
    let d65 = match crate::spectrum::data::named_illuminant("D65") {
        Some(Curve::Dense(d)) => d,
        _ => unreachable!(),
    };
    let two = match Curve::from_samples(&[400.0, 700.0], &[0.25, 2.0]) {
        Curve::Dense(d) => d,
        _ => unreachable!(),
    };
    let odd = match Curve::from_samples(&[380.5, 390.5, 400.5, 410.5], &[1.0, -3.0, 7.5, 0.0]) {
        Curve::Dense(d) => d,
        _ => unreachable!(),
    };
    let mut rng = crate::math::rng::Pcg32::new(7, 1);
    for d in [&d65, &two, &odd] {
        let (lo, hi) = d.range();
        for n in 0..4000 {
            let lambda: [f32; 6] = std::array::from_fn(|k| match (n + k) % 9 {
                0 => lo,
                1 => hi,
                2 => lo - 1e-3,
                3 => hi + 0.5,
                4 => f32::NAN,
                5 => lo + ((n % 40) as f32) / d.inv_step,
                _ => lo - 20.0 + (hi - lo + 40.0) * rng.next_f32(),
            });
            let lanes = d.eval_lanes(&lambda);
            for k in 0..6 {
                assert_eq!(
                    lanes[k].to_bits(),
                    d.eval(lambda[k]).to_bits(),
                    "λ = {}",
                    lambda[k]
                );
            }
        }
    }
}

#[test]
fn planck_matches_reference_values() {
    // B(λ = 500 nm, T = 5778 K) = 2.6375e13 W m⁻² sr⁻¹ m⁻¹ → 2.6375e4 per nm (Planck's law
    // evaluated independently in f64).
    let b = planck(500.0, 5778.0);
    assert!((b / 2.6375e4 - 1.0).abs() < 1e-3, "{b}");
    // Wien's displacement: the peak of a 5000 K body is at 2.897771955e6 nm·K / 5000 K.
    let peak = (300..1200)
        .map(|l| l as f32)
        .max_by(|a, b| planck(*a, 5000.0).total_cmp(&planck(*b, 5000.0)))
        .unwrap();
    assert!((peak - 579.55).abs() <= 1.0, "{peak}");
}

#[test]
fn constant_one_has_unit_luminance() {
    assert!((Curve::Constant(1.0).luminance() - 1.0).abs() < 1e-5);
}
