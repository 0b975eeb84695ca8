//! Microfacet normal distributions (Beckmann and GGX, anisotropic) with Smith shadowing and
//! sampling of the distribution of visible normals (Heitz & d'Eon 2014; Heitz 2018 for GGX).
//!
//! Conventions as Mitsuba 3: local frame with the macro-normal +z; `alpha_u`, `alpha_v` the
//! roughness along the tangent and bitangent; G = G1(wi) · G1(wo) (uncorrelated Smith).

use crate::math::portable;
use crate::math::turns::sin_cos_turns;
use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize};
use std::f32::consts::PI;

/// Which microfacet normal distribution.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Distribution {
    /// Beckmann (Gaussian slopes): Mitsuba's default.
    #[default]
    Beckmann,
    /// GGX / Trowbridge–Reitz: longer tails.
    Ggx,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Microfacet {
    pub kind: Distribution,
    pub alpha_u: f32,
    pub alpha_v: f32,
}

const INV_SQRT_PI: f32 = 0.564_189_6;

/// erf(x), Abramowitz & Stegun 7.1.26 (absolute error < 1.5e-7).
#[inline]
pub fn erf(x: f32) -> f32 {
    let s = x.signum();
    let x = x.abs() as f64;
    let t = 1.0 / (1.0 + 0.327_591_1 * x);
    let poly = t
        * (0.254_829_592
            + t * (-0.284_496_736
                + t * (1.421_413_741 + t * (-1.453_152_027 + t * 1.061_405_429))));
    s * (1.0 - poly * portable::exp(-x * x)) as f32
}

/// erf⁻¹(x) for x in (−1, 1), Giles' single-precision approximation (2010).
// The published coefficients are kept verbatim, digits beyond f32 included.
#[allow(clippy::excessive_precision)]
#[inline]
pub fn erfinv(x: f32) -> f32 {
    let w = -portable::ln(((1.0 - x) * (1.0 + x)).max(1e-30));
    let p = if w < 5.0 {
        let w = w - 2.5;
        let mut p = 2.810_226_36e-08f32;
        for c in [
            3.432_739_39e-07,
            -3.523_387_7e-06,
            -4.391_506_54e-06,
            0.000_218_580_87,
            -0.001_253_725_03,
            -0.004_177_681_64,
            0.246_640_727,
            1.501_409_41,
        ] {
            p = c + p * w;
        }
        p
    } else {
        let w = w.sqrt() - 3.0;
        let mut p = -0.000_200_214_257f32;
        for c in [
            0.000_100_950_558,
            0.001_349_343_22,
            -0.003_673_428_44,
            0.005_739_507_73,
            -0.007_622_461_3,
            0.009_438_870_47,
            1.001_674_06,
            2.832_976_82,
        ] {
            p = c + p * w;
        }
        p
    };
    p * x
}

impl Microfacet {
    pub fn new(kind: Distribution, alpha_u: f32, alpha_v: f32) -> Self {
        // Below ~1e-4 the distributions underflow in f32; such surfaces are specular anyway.
        Self {
            kind,
            alpha_u: alpha_u.max(1e-4),
            alpha_v: alpha_v.max(1e-4),
        }
    }

    /// D(m): microfacet normal density w.r.t. projected solid angle (∫ D(m) m.z dm = 1).
    #[inline]
    pub fn d(&self, m: Vec3) -> f32 {
        if m.z <= 0.0 {
            return 0.0;
        }
        let cos2 = m.z * m.z;
        let e = (m.x * m.x / (self.alpha_u * self.alpha_u)
            + m.y * m.y / (self.alpha_v * self.alpha_v))
            / cos2;
        let norm = PI * self.alpha_u * self.alpha_v * cos2 * cos2;
        let r = match self.kind {
            Distribution::Beckmann => portable::exp(-e) / norm,
            Distribution::Ggx => 1.0 / (norm * (1.0 + e) * (1.0 + e)),
        };
        if r * m.z > 1e-20 {
            r
        } else {
            0.0
        }
    }

    /// Smith's Λ(w).
    #[inline]
    fn lambda(&self, w: Vec3) -> f32 {
        let xy2 = w.x * w.x * self.alpha_u * self.alpha_u + w.y * w.y * self.alpha_v * self.alpha_v;
        if xy2 <= 0.0 {
            return 0.0;
        }
        let z2 = w.z * w.z;
        match self.kind {
            Distribution::Ggx => 0.5 * ((1.0 + xy2 / z2).sqrt() - 1.0),
            Distribution::Beckmann => {
                // a = 1 / (α(w) tan θ)
                let a = (z2 / xy2).sqrt();
                if a > 6.0 {
                    return 0.0;
                }
                0.5 * (erf(a) - 1.0) + portable::exp(-a * a) / (2.0 * a) * INV_SQRT_PI
            }
        }
    }

    /// Smith's masking G1(w, m): 0 if w sees the back of m or lies on the other side of the
    /// macro-surface than m's side.
    #[inline]
    pub fn g1(&self, w: Vec3, m: Vec3) -> f32 {
        if w.dot(m) * w.z <= 0.0 {
            return 0.0;
        }
        1.0 / (1.0 + self.lambda(w))
    }

    /// Shadowing-masking G = G1(wi) G1(wo), as Mitsuba 3.
    #[inline]
    pub fn g(&self, wi: Vec3, wo: Vec3, m: Vec3) -> f32 {
        self.g1(wi, m) * self.g1(wo, m)
    }

    /// Density of `sample_visible(wi, ·)` producing m: G1(wi, m) |wi·m| D(m) / |wi.z|.
    #[inline]
    pub fn pdf_visible(&self, wi: Vec3, m: Vec3) -> f32 {
        if wi.z == 0.0 {
            return 0.0;
        }
        self.g1(wi, m) * wi.dot(m).abs() * self.d(m) / wi.z.abs()
    }

    /// Samples a normal visible from `wi` (any hemisphere; treated as the upper one).
    #[inline]
    pub fn sample_visible(&self, wi: Vec3, u: Vec2) -> Vec3 {
        let wi = if wi.z < 0.0 { -wi } else { wi };
        // Stretch to the isotropic unit-roughness configuration.
        let wi_s = Vec3::new(self.alpha_u * wi.x, self.alpha_v * wi.y, wi.z).normalize();
        let slope = match self.kind {
            Distribution::Ggx => return self.sample_visible_ggx(wi_s, u),
            Distribution::Beckmann => {
                let (sin_phi, cos_phi) = if wi_s.z < 0.99999 {
                    let r = (wi_s.x * wi_s.x + wi_s.y * wi_s.y).sqrt();
                    (wi_s.y / r, wi_s.x / r)
                } else {
                    (0.0, 1.0)
                };
                let s = beckmann_sample_unit_slopes(wi_s.z, u);
                // Rotate by φ_i, unstretch.
                Vec2::new(
                    (cos_phi * s.x - sin_phi * s.y) * self.alpha_u,
                    (sin_phi * s.x + cos_phi * s.y) * self.alpha_v,
                )
            }
        };
        Vec3::new(-slope.x, -slope.y, 1.0).normalize()
    }

    /// Heitz 2018: uniform point on the projected hemisphere of the stretched configuration.
    #[inline]
    fn sample_visible_ggx(&self, v: Vec3, u: Vec2) -> Vec3 {
        let len2 = v.x * v.x + v.y * v.y;
        let t1 = if len2 > 0.0 {
            Vec3::new(-v.y, v.x, 0.0) / len2.sqrt()
        } else {
            Vec3::X
        };
        let t2 = v.cross(t1);
        let r = u.x.sqrt();
        let (sp, cp) = sin_cos_turns(u.y);
        let p1 = r * cp;
        let s = 0.5 * (1.0 + v.z);
        let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * r * sp;
        let nh = p1 * t1 + p2 * t2 + (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt() * v;
        Vec3::new(self.alpha_u * nh.x, self.alpha_v * nh.y, nh.z.max(1e-6)).normalize()
    }
}

/// Slopes of unit-roughness Beckmann normals visible from a direction with cos θ = `cos_t`
/// (Heitz & d'Eon 2014, Appendix: invert the slope-x CDF with a safeguarded Newton iteration;
/// slope y is Gaussian).
fn beckmann_sample_unit_slopes(cos_t: f32, u: Vec2) -> Vec2 {
    if cos_t > 0.9999 {
        let r = (-portable::ln((1.0 - u.x).max(1e-12))).sqrt();
        let (s, c) = sin_cos_turns(u.y);
        return Vec2::new(r * c, r * s);
    }
    let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
    let tan_t = sin_t / cos_t;
    let cot_t = 1.0 / tan_t;
    // The slope-x CDF, as a function of b = erf(x), is proportional to
    // 1 + b + tan θ e^{−erfinv(b)²} / √π on [−1, erf(cot θ)].
    let (mut lo, mut hi) = (-1.0f32, erf(cot_t));
    let sample_x = u.x.max(1e-6);
    let theta = portable::acos(cos_t);
    // An approximate inverse as the start point (the paper's fit).
    let fit = 1.0 + theta * (-0.876 + theta * (0.4265 - 0.0594 * theta));
    let mut b = hi - (1.0 + hi) * portable::powf(1.0 - sample_x, fit);
    let norm = 1.0 / (1.0 + hi + INV_SQRT_PI * tan_t * portable::exp(-cot_t * cot_t));
    for _ in 0..12 {
        if !(b >= lo && b <= hi) {
            b = 0.5 * (lo + hi);
        }
        let x = erfinv(b);
        let value = norm * (1.0 + b + INV_SQRT_PI * tan_t * portable::exp(-x * x)) - sample_x;
        let derivative = norm * (1.0 - x * tan_t);
        if value.abs() < 1e-6 {
            break;
        }
        if value > 0.0 {
            hi = b;
        } else {
            lo = b;
        }
        b -= value / derivative;
    }
    Vec2::new(erfinv(b), erfinv(2.0 * u.y.max(1e-6) - 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn erf_and_inverse() {
        // erf(0.5) = 0.5204998778, erf(2) = 0.9953222650.
        assert!((erf(0.5) - 0.520_499_9).abs() < 2e-7);
        assert!((erf(2.0) - 0.995_322_3).abs() < 2e-7);
        assert!((erf(-1.0) + 0.842_700_8).abs() < 2e-7);
        for i in 1..199 {
            let x = -0.99 + i as f32 * 0.01;
            assert!((erf(erfinv(x)) - x).abs() < 2e-6, "{x}");
        }
    }

    /// ∫ D(m) cos θ_m dω = 1, and for every wi ∫ D_wi(m) dω = 1 (the visible normals' pdf is
    /// normalised). Midpoint rule in (cos θ, φ) with 400×400 cells: error < 0.5%.
    #[test]
    fn distributions_are_normalised() {
        for kind in [Distribution::Beckmann, Distribution::Ggx] {
            for (au, av) in [(0.1, 0.1), (0.5, 0.5), (0.2, 0.6), (1.0, 1.0)] {
                let m = Microfacet::new(kind, au, av);
                let wi = Vec3::new(0.5, 0.3, 0.6).normalize();
                let n = 400;
                let (mut proj, mut vis) = (0.0f64, 0.0f64);
                for i in 0..n {
                    // Concentrate cells near the pole for small roughness: substitute c = 1 − t².
                    let t = (i as f64 + 0.5) / n as f64;
                    let c = 1.0 - t * t;
                    let dc = 2.0 * t / n as f64;
                    for j in 0..n {
                        let phi = (j as f64 + 0.5) / n as f64 * 2.0 * std::f64::consts::PI;
                        let s = (1.0 - c * c).max(0.0).sqrt();
                        let h = Vec3::new(
                            (s * portable::cos(phi)) as f32,
                            (s * portable::sin(phi)) as f32,
                            c as f32,
                        );
                        let dw = dc * 2.0 * std::f64::consts::PI / n as f64;
                        proj += m.d(h) as f64 * c * dw;
                        vis += m.pdf_visible(wi, h) as f64 * dw;
                    }
                }
                assert!(
                    (proj - 1.0).abs() < 5e-3,
                    "{kind:?} {au},{av}: ∫D cos = {proj}"
                );
                assert!(
                    (vis - 1.0).abs() < 5e-3,
                    "{kind:?} {au},{av}: ∫D_wi = {vis}"
                );
            }
        }
    }
}
