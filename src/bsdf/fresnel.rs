//! Fresnel reflectance of dielectric and conductor interfaces (unpolarised light).

/// Fresnel reflectance of a dielectric interface with relative index `eta` = η_inside / η_outside
/// for a ray with `cos_i` = cos θ of the incident direction w.r.t. the outward normal (negative:
/// arriving from inside). Returns (F, cos θ_t, η_it, η_ti): cos θ_t is signed opposite to cos_i,
/// η_it the relative index along the ray's travel and η_ti its inverse. F = 1 under total internal
/// reflection (cos θ_t = 0 then).
#[inline]
pub fn dielectric(cos_i: f32, eta: f32) -> (f32, f32, f32, f32) {
    let outside = cos_i >= 0.0;
    let (eta_it, eta_ti) = if outside {
        (eta, 1.0 / eta)
    } else {
        (1.0 / eta, eta)
    };
    let cos_i_abs = cos_i.abs();
    // Snell: sin²θ_t = η_ti² (1 − cos²θ_i).
    let cos_t_sq = 1.0 - eta_ti * eta_ti * (1.0 - cos_i_abs * cos_i_abs).max(0.0);
    if cos_t_sq <= 0.0 {
        return (1.0, 0.0, eta_it, eta_ti);
    }
    let cos_t = cos_t_sq.sqrt();
    if eta == 1.0 {
        return (0.0, -cos_i, 1.0, 1.0);
    }
    let rs = (cos_i_abs - eta_it * cos_t) / (cos_i_abs + eta_it * cos_t);
    let rp = (eta_it * cos_i_abs - cos_t) / (eta_it * cos_i_abs + cos_t);
    let f = 0.5 * (rs * rs + rp * rp);
    (f, if outside { -cos_t } else { cos_t }, eta_it, eta_ti)
}

/// Fresnel reflectance of a conductor with complex index η + iκ (relative to the outside medium)
/// at cos θ_i ≥ 0, from the exact expressions for s- and p-polarised light.
#[inline]
pub fn conductor(cos_i: f32, eta: f32, k: f32) -> f32 {
    let c = cos_i.clamp(0.0, 1.0) as f64;
    let (eta, k) = (eta as f64, k as f64);
    let c2 = c * c;
    let s2 = 1.0 - c2;
    let (e2, k2) = (eta * eta, k * k);
    let t0 = e2 - k2 - s2;
    let a2b2 = (t0 * t0 + 4.0 * e2 * k2).sqrt();
    let a = (0.5 * (a2b2 + t0)).max(0.0).sqrt();
    let t1 = a2b2 + c2;
    let t2 = 2.0 * a * c;
    let rs = (t1 - t2) / (t1 + t2);
    let t3 = c2 * a2b2 + s2 * s2;
    let t4 = t2 * s2;
    let rp = rs * (t3 - t4) / (t3 + t4);
    (0.5 * (rs + rp)) as f32
}

/// Hemispherical average of the dielectric Fresnel reflectance, 2∫F(cos θ) cos θ d cos θ, for
/// light arriving from the side where the relative index is `eta` (used by plastic's internal
/// scattering). Numerical integration; called once per material at load.
pub fn dielectric_average(eta: f32) -> f32 {
    let n = 4096;
    let mut sum = 0.0f64;
    for i in 0..n {
        let c = (i as f64 + 0.5) / n as f64;
        sum += dielectric(c as f32, eta).0 as f64 * c;
    }
    (2.0 * sum / n as f64) as f32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::portable;

    #[test]
    fn dielectric_known_values() {
        // Normal incidence: ((η − 1)/(η + 1))² = 0.04 for η = 1.5.
        assert!((dielectric(1.0, 1.5).0 - 0.04).abs() < 1e-6);
        // From inside, beyond the critical angle asin(1/1.5) = 41.8°: total internal reflection.
        let (f, cos_t, _, _) = dielectric(-(portable::cos(50f32.to_radians())), 1.5);
        assert_eq!((f, cos_t), (1.0, 0.0));
        // Brewster's angle atan(1.5): p-polarised reflectance vanishes, so F = rs²/2.
        let tb = portable::atan(1.5f32);
        let (f, cos_t, _, _) = dielectric(portable::cos(tb), 1.5);
        assert!(cos_t < 0.0);
        let (ci, ct) = (portable::cos(tb), -cos_t);
        let rs = (ci - 1.5 * ct) / (ci + 1.5 * ct);
        assert!((f - 0.5 * rs * rs).abs() < 1e-6);
        // Index matching: no reflection.
        assert_eq!(dielectric(0.3, 1.0).0, 0.0);
    }

    #[test]
    fn conductor_limits() {
        // k = 0 reduces to the dielectric formula; normal incidence ((η−1)² + k²)/((η+1)² + k²).
        for c in [1.0f32, 0.7, 0.2] {
            assert!((conductor(c, 1.5, 0.0) - dielectric(c, 1.5).0).abs() < 1e-5);
        }
        let (e, k) = (0.2f32, 3.0f32);
        let expect = ((e - 1.0).powi(2) + k * k) / ((e + 1.0).powi(2) + k * k);
        assert!((conductor(1.0, e, k) - expect).abs() < 1e-5);
        assert!(
            (conductor(0.0, e, k) - 1.0).abs() < 1e-5,
            "grazing incidence reflects everything"
        );
    }

    #[test]
    fn average_fresnel() {
        // Known value for η = 1.5 from outside: 0.0918 (d'Eon & Irving 2011 fit ≈ 0.092).
        let f = dielectric_average(1.5);
        assert!((f - 0.0918).abs() < 2e-3, "{f}");
    }
}
