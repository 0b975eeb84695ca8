//! OpenCV's lens distortion (Brown–Conrady with OpenCV's coefficient order k1, k2, p1, p2, k3;
//! OpenCV docs, "Camera Calibration and 3D Reconstruction"): in OpenCV's normalised camera
//! coordinates (x right, y down), an undistorted point (x, y), r² = x² + y², lands at
//!
//! ```text
//! x_d = x·(1 + k1 r² + k2 r⁴ + k3 r⁶) + 2 p1 x y + p2 (r² + 2x²)
//! y_d = y·(1 + k1 r² + k2 r⁴ + k3 r⁶) + p1 (r² + 2y²) + 2 p2 x y
//! ```
//!
//! A film position is a distorted point; the camera ray goes through the undistorted one, found
//! by Newton's method on this map (f64, from x = x_d). The loader refuses coefficients whose map
//! folds inside the frame (`check_frame`), where no unique inverse exists.

use super::Intrinsics;
use glam::{DVec2, Vec2};

/// Distortion coefficients, OpenCV's order and meaning.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Distortion {
    pub k1: f64,
    pub k2: f64,
    pub p1: f64,
    pub p2: f64,
    pub k3: f64,
}

/// Newton steps before giving up (converged maps take 3–6; the load check proves convergence
/// on a grid over the frame).
const MAX_ITERATIONS: u32 = 30;

impl Distortion {
    /// OpenCV's forward model: undistorted → distorted normalised point.
    pub fn distort(&self, p: DVec2) -> DVec2 {
        let (x, y) = (p.x, p.y);
        let r2 = x * x + y * y;
        let radial = 1.0 + r2 * (self.k1 + r2 * (self.k2 + r2 * self.k3));
        DVec2::new(
            x * radial + 2.0 * self.p1 * x * y + self.p2 * (r2 + 2.0 * x * x),
            y * radial + self.p1 * (r2 + 2.0 * y * y) + 2.0 * self.p2 * x * y,
        )
    }

    /// The forward map's Jacobian [[∂x_d/∂x, ∂x_d/∂y], [∂y_d/∂x, ∂y_d/∂y]] at `p`.
    fn jacobian(&self, p: DVec2) -> [[f64; 2]; 2] {
        let (x, y) = (p.x, p.y);
        let r2 = x * x + y * y;
        let radial = 1.0 + r2 * (self.k1 + r2 * (self.k2 + r2 * self.k3));
        // d(radial)/d(r²)
        let dr = self.k1 + r2 * (2.0 * self.k2 + 3.0 * self.k3 * r2);
        [
            [
                radial + 2.0 * x * x * dr + 2.0 * self.p1 * y + 6.0 * self.p2 * x,
                2.0 * x * y * dr + 2.0 * self.p1 * x + 2.0 * self.p2 * y,
            ],
            [
                2.0 * x * y * dr + 2.0 * self.p1 * x + 2.0 * self.p2 * y,
                radial + 2.0 * y * y * dr + 6.0 * self.p1 * y + 2.0 * self.p2 * x,
            ],
        ]
    }

    /// The undistorted point whose image is `d`, and the final residual |distort(p) − d|.
    pub fn undistort(&self, d: DVec2) -> (DVec2, f64) {
        let mut p = d;
        let mut err = f64::INFINITY;
        for _ in 0..MAX_ITERATIONS {
            let f = self.distort(p) - d;
            err = f.length();
            if err < 1e-13 {
                break;
            }
            let [[a, b], [c, e]] = self.jacobian(p);
            let det = a * e - b * c;
            if det.abs() < 1e-300 || !det.is_finite() {
                break;
            }
            p -= DVec2::new(e * f.x - b * f.y, a * f.y - c * f.x) / det;
        }
        (p, err)
    }

    /// `undistort` on prism's plane coordinates (x left, y up: OpenCV's with both signs flipped).
    #[inline]
    pub fn undistort_plane(&self, q: Vec2) -> Vec2 {
        let (p, _) = self.undistort(-q.as_dvec2());
        (-p).as_vec2()
    }

    /// `distort` on prism's plane coordinates.
    pub fn distort_plane(&self, q: Vec2) -> Vec2 {
        (-self.distort(-q.as_dvec2())).as_vec2()
    }

    /// Checks that the map is one-to-one over the frame (widened by `margin` pixels, the pixel
    /// filter's reach): the radial map r·(1 + k1r² + k2r⁴ + k3r⁶) increases up to the frame's
    /// farthest corner, and on a grid over the frame Newton's method converges to a point
    /// where the Jacobian's determinant is positive. Err: a sentence saying where it folds.
    pub fn check_frame(&self, k: &Intrinsics, margin: f32) -> Result<(), String> {
        let corners = [
            Vec2::new(-margin, -margin),
            Vec2::new(k.width + margin, -margin),
            Vec2::new(-margin, k.height + margin),
            Vec2::new(k.width + margin, k.height + margin),
        ];
        let rd_max = corners
            .iter()
            .map(|&c| k.plane(c).as_dvec2().length())
            .fold(0.0, f64::max);
        // Walk r outwards until the distorted radius covers the frame's corner.
        let steps = 100_000;
        let r_end = 4.0 * rd_max.max(1e-3) + 10.0;
        let mut reached = false;
        for i in 1..=steps {
            let r = r_end * i as f64 / steps as f64;
            let r2 = r * r;
            let slope = 1.0 + r2 * (3.0 * self.k1 + r2 * (5.0 * self.k2 + r2 * 7.0 * self.k3));
            let rd = r * (1.0 + r2 * (self.k1 + r2 * (self.k2 + r2 * self.k3)));
            if slope <= 0.0 {
                return Err(format!(
                    "the radial distortion folds at undistorted radius {r:.4} (distorted {rd:.4}), \
                     inside the frame, whose farthest corner is at distorted radius {rd_max:.4}"
                ));
            }
            if rd >= rd_max {
                reached = true;
                break;
            }
        }
        if !reached {
            return Err(format!(
                "the radial distortion never reaches the frame's corner (distorted radius {rd_max:.4})"
            ));
        }
        let n = 32;
        for j in 0..=n {
            for i in 0..=n {
                let film = Vec2::new(
                    -margin + (k.width + 2.0 * margin) * i as f32 / n as f32,
                    -margin + (k.height + 2.0 * margin) * j as f32 / n as f32,
                );
                let d = -k.plane(film).as_dvec2();
                let (p, err) = self.undistort(d);
                let [[a, b], [c, e]] = self.jacobian(p);
                let converged = err < 1e-9 * (1.0 + d.length());
                if !converged || a * e - b * c <= 0.0 {
                    return Err(format!(
                        "the distortion has no unique inverse at film position ({:.1}, {:.1}) px \
                         (the map folds there)",
                        film.x, film.y
                    ));
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Newton's inverse undoes the forward model to 1e-12 over a wide field, with every term.
    #[test]
    fn undistort_inverts_distort() {
        let d = Distortion {
            k1: -0.28,
            k2: 0.07,
            p1: 0.001,
            p2: -0.0015,
            k3: 0.01,
        };
        for j in -8..=8 {
            for i in -8..=8 {
                let p = DVec2::new(i as f64 * 0.08, j as f64 * 0.06);
                let (q, err) = d.undistort(d.distort(p));
                assert!(err < 1e-12 && (q - p).length() < 1e-10, "{p} -> {q}");
            }
        }
    }

    /// The Jacobian is the forward map's derivative (central differences).
    #[test]
    fn jacobian_matches_differences() {
        let d = Distortion {
            k1: 0.2,
            k2: -0.1,
            p1: 0.01,
            p2: 0.02,
            k3: 0.05,
        };
        let p = DVec2::new(0.3, -0.4);
        let h = 1e-6;
        let j = d.jacobian(p);
        let dx = (d.distort(p + DVec2::X * h) - d.distort(p - DVec2::X * h)) / (2.0 * h);
        let dy = (d.distort(p + DVec2::Y * h) - d.distort(p - DVec2::Y * h)) / (2.0 * h);
        assert!((j[0][0] - dx.x).abs() < 1e-8 && (j[1][0] - dx.y).abs() < 1e-8);
        assert!((j[0][1] - dy.x).abs() < 1e-8 && (j[1][1] - dy.y).abs() < 1e-8);
    }

    /// Strong barrel distortion folds: r(1 + k1 r²) peaks at r = 1/√(−3k1).
    #[test]
    fn folding_is_refused() {
        let k = Intrinsics::from_k(200.0, 200.0, 159.5, 119.5, 320, 240);
        let mild = Distortion {
            k1: -0.1,
            k2: 0.0,
            p1: 0.0,
            p2: 0.0,
            k3: 0.0,
        };
        // The corner is at distorted radius 1.0 (+ the margin); k1 = −0.1 peaks at
        // r = 1.83, r_d = 1.22: fine. k1 = −0.2 peaks at r = 1.29, r_d = 0.86 < 1: folds.
        assert!(mild.check_frame(&k, 1.0).is_ok());
        let strong = Distortion { k1: -0.2, ..mild };
        let e = strong.check_frame(&k, 1.0).unwrap_err();
        assert!(e.contains("folds"), "{e}");
    }
}
