//! A smooth interface between two dielectrics (Mitsuba 3's `dielectric`): Dirac reflection and
//! refraction, chosen with the Fresnel reflectance of the hero wavelength.
//!
//! ```ron
//! Dielectric(int_ior: Glass("SF11"), ext_ior: Named("air"))
//! ```
//!
//! Conventions as Mitsuba: η = n_int / n_ext, the exterior on the side the normal points to, so
//! the lobe is two-sided (wi.z < 0 means the path arrives from inside). Radiance transport:
//! refracted radiance is scaled by η_ti² = (n_wi side / n_wo side)² (radiance is compressed into
//! a smaller solid angle on the denser side), and `eta` of a refraction sample is η_it, the
//! relative index crossed, for Russian roulette.
//!
//! Dispersion (η varies per lane): reflection leaves every lane in the same direction, so lane k
//! would have chosen it with probability F_k: `pdf_lanes[k] = F_k`, weight F_k R_k / F_hero.
//! Refraction bends each lane its own way, so a lane whose η differs from the hero's cannot
//! produce the hero's direction: its pdf and weight are 0 (spectral MIS then gives the hero
//! lane the whole estimate).

use super::describe::dielectric;
use super::fresnel;
use super::{BsdfLobe, BsdfParams, BsdfSample, Lobe, Param};
use crate::interaction::SurfaceInteraction;
use crate::spectrum::{RelativeIor, Spectrum, Wavelengths};
use crate::texture::SpectralTexture;
use glam::{Vec2, Vec3};

#[derive(Clone, Copy, Debug)]
pub struct Dielectric<const N: usize> {
    /// η = n_int / n_ext at each lane.
    pub eta: Spectrum<N>,
    pub reflectance: Spectrum<N>,
    pub transmittance: Spectrum<N>,
    /// η differs between lanes (decided at load from the IORs).
    pub dispersive: bool,
}

/// Mirror reflection about the local normal.
#[inline]
pub fn reflect(wi: Vec3) -> Vec3 {
    Vec3::new(-wi.x, -wi.y, wi.z)
}

/// Refraction through the local normal, given `fresnel::dielectric`'s signed cos θ_t and η_ti.
#[inline]
pub fn refract(wi: Vec3, cos_t: f32, eta_ti: f32) -> Vec3 {
    Vec3::new(-eta_ti * wi.x, -eta_ti * wi.y, cos_t)
}

impl<const N: usize> BsdfLobe<N> for Dielectric<N> {
    #[inline]
    fn sample(&self, wi: Vec3, uc: f32, _u: Vec2) -> Option<BsdfSample<N>> {
        if wi.z == 0.0 {
            return None;
        }
        let (f_h, cos_t, eta_it, eta_ti) = fresnel::dielectric(wi.z, self.eta[0]);
        // Fresnel per lane; without dispersion every lane is the hero.
        let f = if self.dispersive {
            Spectrum::from_fn(|k| fresnel::dielectric(wi.z, self.eta[k]).0)
        } else {
            Spectrum::splat(f_h)
        };
        if uc < f_h {
            return Some(BsdfSample {
                wo: reflect(wi),
                pdf: f_h,
                pdf_lanes: f,
                weight: f * self.reflectance / f_h,
                delta: true,
                eta: 1.0,
            });
        }
        let t_h = 1.0 - f_h;
        let mut pdf_lanes = Spectrum::zero();
        let mut weight = Spectrum::zero();
        for k in 0..N {
            // Exact equality: a lane shares the refracted direction only if its η is the hero's.
            if self.eta[k] == self.eta[0] {
                pdf_lanes[k] = 1.0 - f[k];
                weight[k] = (1.0 - f[k]) * self.transmittance[k] * eta_ti * eta_ti / t_h;
            }
        }
        Some(BsdfSample {
            wo: refract(wi, cos_t, eta_ti),
            pdf: t_h,
            pdf_lanes,
            weight,
            delta: true,
            eta: eta_it,
        })
    }

    #[inline]
    fn eval(&self, _wi: Vec3, _wo: Vec3) -> Spectrum<N> {
        Spectrum::zero()
    }

    #[inline]
    fn pdf(&self, _wi: Vec3, _wo: Vec3) -> f32 {
        0.0
    }

    #[inline]
    fn has_smooth(&self) -> bool {
        false
    }

    #[inline]
    fn glossy(&self, _max_alpha: f32) -> bool {
        true
    }

    #[inline]
    fn pdf_lanes(&self, _wi: Vec3, _wo: Vec3) -> Spectrum<N> {
        Spectrum::zero()
    }

    #[inline]
    fn dispersive(&self) -> bool {
        self.dispersive
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn glass(eta: [f32; 4]) -> Dielectric<4> {
        Dielectric {
            eta: Spectrum(eta),
            reflectance: Spectrum::one(),
            transmittance: Spectrum::one(),
            dispersive: eta.iter().any(|&e| e != eta[0]),
        }
    }

    /// A dispersive glass: a reflection keeps every lane with pdf_lanes = F_k and weight
    /// F_k / F_hero; a refraction keeps only the lanes whose η equals the hero's. Tolerance 1e-6
    /// (f32 rounding of the same expressions).
    #[test]
    fn dispersive_lanes() {
        let eta = [1.52, 1.51, 1.52, 1.50];
        let g = glass(eta);
        let wi = Vec3::new(0.6, 0.0, 0.8);
        let fk: Vec<f32> = eta.iter().map(|&e| fresnel::dielectric(0.8, e).0).collect();
        let r = g.sample(wi, 0.0, Vec2::ZERO).unwrap();
        assert!(r.delta && r.eta == 1.0);
        assert_eq!(r.wo, Vec3::new(-0.6, 0.0, 0.8));
        assert!((r.pdf - fk[0]).abs() < 1e-7);
        for k in 0..4 {
            assert!((r.pdf_lanes[k] - fk[k]).abs() < 1e-7);
            assert!((r.weight[k] - fk[k] / fk[0]).abs() < 1e-6);
        }
        let t = g.sample(wi, 0.999, Vec2::ZERO).unwrap();
        assert!((t.pdf - (1.0 - fk[0])).abs() < 1e-6 && t.eta == 1.52);
        // Snell: sin θ_t = sin θ_i / η.
        assert!((t.wo.x + 0.6 / 1.52).abs() < 1e-6 && t.wo.z < 0.0);
        assert!((t.wo.length() - 1.0).abs() < 1e-6);
        assert_eq!(t.pdf_lanes[1], 0.0);
        assert_eq!(t.pdf_lanes[3], 0.0);
        assert_eq!(t.weight[1], 0.0);
        assert!((t.pdf_lanes[2] - (1.0 - fk[2])).abs() < 1e-7);
        // Lanes with the hero's η carry the radiance scaling 1/η².
        for k in [0, 2] {
            assert!((t.weight[k] - 1.0 / (1.52 * 1.52)).abs() < 1e-6, "{k}");
        }
    }

    /// From inside beyond the critical angle every lane reflects totally: F = 1, weight 1.
    #[test]
    fn total_internal_reflection() {
        let g = glass([1.5, 1.6, 1.7, 1.8]);
        let wi = Vec3::new(0.8, 0.0, -0.6);
        let s = g.sample(wi, 0.99, Vec2::ZERO).unwrap();
        assert_eq!(s.wo, Vec3::new(-0.8, 0.0, -0.6));
        assert_eq!(
            (s.pdf, s.pdf_lanes.0, s.weight.0),
            (1.0, [1.0; 4], [1.0; 4])
        );
    }
}

/// A smooth dielectric interface's parameters over the surface.
#[derive(Clone, Debug, PartialEq)]
pub struct DielectricParams {
    pub ior: RelativeIor,
    pub specular_reflectance: SpectralTexture,
    pub specular_transmittance: SpectralTexture,
}

impl BsdfParams for DielectricParams {
    #[inline]
    fn lobe<'a, const N: usize>(
        &'a self,
        si: &SurfaceInteraction,
        wl: &Wavelengths<N>,
    ) -> Lobe<'a, N> {
        Lobe::Dielectric(Dielectric {
            eta: self.ior.eta(wl),
            reflectance: self.specular_reflectance.eval(si.uv, wl),
            transmittance: self.specular_transmittance.eval(si, wl),
            dispersive: self.ior.dispersive(),
        })
    }

    #[inline]
    fn dispersive(&self) -> bool {
        self.ior.dispersive()
    }

    fn focuses_light(&self) -> bool {
        true
    }

    fn traverse<'a>(&'a self, put: &mut impl FnMut(&'static str, Param<'a>)) -> &'static str {
        dielectric(
            &self.ior,
            &self.specular_reflectance,
            &self.specular_transmittance,
            put,
        );
        "dielectric"
    }
}
