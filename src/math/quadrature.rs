//! Gauss–Legendre quadrature: the n nodes and weights on [−1, 1] that integrate polynomials of
//! degree 2n − 1 exactly. Computed here (Newton's method on the Legendre recurrence, as in
//! Numerical Recipes' `gauleg`) because only this one rule is needed, at load, for n ≤ a few
//! hundred; the bits depend on `math::portable` only, so every machine gets the same nodes.

use crate::math::portable;

/// Nodes (ascending) and weights of the n-point rule on [−1, 1].
pub fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut nodes = vec![0.0; n];
    let mut weights = vec![0.0; n];
    for i in 0..n.div_ceil(2) {
        // The i-th root from the top, from Tricomi's first-order estimate.
        let mut x = portable::cos(std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5));
        for _ in 0..100 {
            let (p, d) = legendre(n, x);
            let dx = p / d;
            x -= dx;
            if dx.abs() <= 1e-15 {
                break;
            }
        }
        let (_, dp) = legendre(n, x);
        let w = 2.0 / ((1.0 - x * x) * dp * dp);
        nodes[i] = -x;
        nodes[n - 1 - i] = x;
        weights[i] = w;
        weights[n - 1 - i] = w;
    }
    (nodes, weights)
}

/// P_n(x) and P_n'(x), by the three-term recurrence.
fn legendre(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    if n == 0 {
        return (1.0, 0.0);
    }
    for k in 2..=n {
        let k = k as f64;
        let p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
    }
    (p1, n as f64 * (x * p1 - p0) / (x * x - 1.0))
}

#[cfg(test)]
mod tests {
    use super::gauss_legendre;

    /// Exact for x^k up to k = 2n − 1 (∫ x^k over [−1, 1] is 2/(k+1) for even k, 0 for odd),
    /// to 1e-13 (rounding over n terms); for small n not exact at k = 2n, which tells the rule
    /// is not a finer one in disguise.
    #[test]
    fn integrates_polynomials_of_degree_below_2n_exactly() {
        for n in [1, 2, 5, 32, 64] {
            let (x, w) = gauss_legendre(n);
            assert!(x.windows(2).all(|p| p[0] < p[1]), "n {n}: nodes ascend");
            for k in 0..=2 * n {
                let got: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(k as i32)).sum();
                let want = if k % 2 == 0 {
                    2.0 / (k as f64 + 1.0)
                } else {
                    0.0
                };
                if k < 2 * n {
                    assert!(
                        (got - want).abs() < 1e-13,
                        "n {n}, x^{k}: {got} against {want}"
                    );
                } else if n <= 5 {
                    assert!(
                        (got - want).abs() > 1e-6,
                        "n {n}: x^{k} should not be exact"
                    );
                }
            }
        }
    }
}
