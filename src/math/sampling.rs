//! Warps from the unit square to the domains the renderer samples, each with its pdf.
//! Every warp here has a chi-square test in `tests/sampling_chi2.rs`.

use crate::math::turns::{sin_cos_eighth, sin_cos_turns};
use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, PI};

/// Concentric map of the square onto the unit disk (Shirley & Chiu 1997): area-preserving and
/// low-distortion, so stratification in the square survives on the disk.
#[inline]
pub fn square_to_disk_concentric(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    if o.x == 0.0 && o.y == 0.0 {
        return Vec2::ZERO;
    }
    // The angle is π/4 · t with |t| ≤ 1, or π/2 minus that, whose sine and cosine are the
    // other way round.
    let steep = o.x.abs() <= o.y.abs();
    let (r, t) = if steep {
        (o.y, o.x / o.y)
    } else {
        (o.x, o.y / o.x)
    };
    let (s, c) = sin_cos_eighth(t);
    if steep {
        Vec2::new(r * s, r * c)
    } else {
        Vec2::new(r * c, r * s)
    }
}

/// Cosine-weighted direction on the +z hemisphere (Malley's method).
#[inline]
pub fn square_to_cosine_hemisphere(u: Vec2) -> Vec3 {
    let d = square_to_disk_concentric(u);
    let z = (1.0 - d.length_squared()).max(0.0).sqrt();
    Vec3::new(d.x, d.y, z)
}

#[inline]
pub fn cosine_hemisphere_pdf(cos_theta: f32) -> f32 {
    cos_theta.max(0.0) * FRAC_1_PI
}

/// Uniform direction on the unit sphere.
#[inline]
pub fn square_to_uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let (s, c) = sin_cos_turns(u.y);
    Vec3::new(r * c, r * s, z)
}

pub const UNIFORM_SPHERE_PDF: f32 = 0.25 * FRAC_1_PI;

/// Uniform direction in the cone of directions within acos(cos_max) of +z.
#[inline]
pub fn square_to_uniform_cone(u: Vec2, cos_max: f32) -> Vec3 {
    // sin²θ from 1 − cos θ directly: accurate for narrow cones.
    let omc = u.x * (1.0 - cos_max);
    let cos_t = 1.0 - omc;
    let sin_t = (omc * (2.0 - omc)).max(0.0).sqrt();
    let (s, c) = sin_cos_turns(u.y);
    Vec3::new(sin_t * c, sin_t * s, cos_t)
}

#[inline]
pub fn uniform_cone_pdf(cos_max: f32) -> f32 {
    1.0 / (2.0 * PI * (1.0 - cos_max))
}

/// Uniform barycentrics (b1, b2) on a triangle; b0 = 1 − b1 − b2.
#[inline]
pub fn square_to_triangle(u: Vec2) -> Vec2 {
    let s = u.x.sqrt();
    Vec2::new(u.y * s, 1.0 - s)
}

/// Power heuristic (β = 2) weight of a strategy with pdf `a` against one with pdf `b`.
#[inline]
pub fn power_heuristic(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    if a2.is_infinite() {
        return 1.0;
    }
    let w = a2 / (a2 + b2);
    if w.is_finite() {
        w
    } else {
        0.0
    }
}
