//! An infinitely thin dielectric slab (Mitsuba 3's `thindielectric`), e.g. a window pane
//! modelled as one sheet: light reflects specularly or passes straight through, undeflected.
//!
//! ```ron
//! ThinDielectric(int_ior: Named("bk7"), ext_ior: Named("air"))
//! ```
//!
//! The slab's internal reflections are summed in closed form: with R the Fresnel reflectance
//! at one face and T = 1 − R, the slab reflects R' = R + T²R (1 + R² + R⁴ + …) = R + T²R/(1 − R²)
//! = 2R/(1 + R) and transmits 1 − R'. The path chooses reflection with probability R'_hero.
//!
//! Directions do not depend on wavelength, but with a dispersive η each lane would choose them
//! with its own probability: `pdf_lanes[k]` = R'_k or 1 − R'_k, and the weight is the lane's
//! value over the hero's probability.

use super::describe::dielectric;
use super::fresnel;
use super::{BsdfLobe, BsdfParams, BsdfSample, Lobe, Param};
use crate::interaction::SurfaceInteraction;
use crate::spectrum::{RelativeIor, Spectrum, Wavelengths};
use crate::texture::SpectralTexture;
use glam::{Vec2, Vec3};

#[derive(Clone, Copy, Debug)]
pub struct ThinDielectric<const N: usize> {
    /// η = n_int / n_ext at each lane.
    pub eta: Spectrum<N>,
    pub reflectance: Spectrum<N>,
    pub transmittance: Spectrum<N>,
    /// η differs between lanes (decided at load from the IORs).
    pub dispersive: bool,
}

/// The slab's total reflectance 2R/(1 + R) at |cos θ|.
#[inline]
pub fn slab_reflectance(cos_abs: f32, eta: f32) -> f32 {
    let r = fresnel::dielectric(cos_abs, eta).0;
    2.0 * r / (1.0 + r)
}

impl<const N: usize> BsdfLobe<N> for ThinDielectric<N> {
    #[inline]
    fn sample(&self, wi: Vec3, uc: f32, _u: Vec2) -> Option<BsdfSample<N>> {
        if wi.z == 0.0 {
            return None;
        }
        // Both faces see the same angle, so the side the path comes from does not matter.
        let c = wi.z.abs();
        let r_h = slab_reflectance(c, self.eta[0]);
        let r = if self.dispersive {
            Spectrum::from_fn(|k| slab_reflectance(c, self.eta[k]))
        } else {
            Spectrum::splat(r_h)
        };
        let (wo, p_h, p, value) = if uc < r_h {
            (Vec3::new(-wi.x, -wi.y, wi.z), r_h, r, r * self.reflectance)
        } else {
            let t = Spectrum::one() - r;
            (-wi, 1.0 - r_h, t, t * self.transmittance)
        };
        Some(BsdfSample {
            wo,
            pdf: p_h,
            pdf_lanes: p,
            weight: value / p_h,
            delta: true,
            eta: 1.0,
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

    /// R' = R + T²R/(1 − R²) (the series written out) equals 2R/(1 + R); at normal incidence on
    /// η = 1.5, R = 0.04 and R' = 0.08/1.04. Tolerance 1e-6 (f32).
    #[test]
    fn slab_sums_internal_reflections() {
        for c in [1.0f32, 0.7, 0.3, 0.05] {
            let r = fresnel::dielectric(c, 1.5).0;
            let t = 1.0 - r;
            let series = r + t * t * r / (1.0 - r * r);
            assert!((slab_reflectance(c, 1.5) - series).abs() < 1e-6);
        }
        assert!((slab_reflectance(1.0, 1.5) - 0.08 / 1.04).abs() < 1e-6);
    }

    /// A dispersive slab keeps every lane, with the lanes' own choice probabilities.
    #[test]
    fn dispersive_lanes_share_directions() {
        let eta = [1.8, 1.75, 1.7, 1.65];
        let s = ThinDielectric::<4> {
            eta: Spectrum(eta),
            reflectance: Spectrum::one(),
            transmittance: Spectrum::one(),
            dispersive: true,
        };
        let wi = Vec3::new(0.0, 0.6, -0.8);
        let t = s.sample(wi, 0.99, Vec2::ZERO).unwrap();
        assert_eq!(t.wo, -wi);
        for (k, &e) in eta.iter().enumerate() {
            let tk = 1.0 - slab_reflectance(0.8, e);
            assert!((t.pdf_lanes[k] - tk).abs() < 1e-6);
            assert!((t.weight[k] - tk / t.pdf).abs() < 1e-6);
        }
    }
}

/// A thin dielectric slab's parameters over the surface.
#[derive(Clone, Debug, PartialEq)]
pub struct ThinDielectricParams {
    pub ior: RelativeIor,
    pub specular_reflectance: SpectralTexture,
    pub specular_transmittance: SpectralTexture,
}

impl BsdfParams for ThinDielectricParams {
    #[inline]
    fn lobe<'a, const N: usize>(
        &'a self,
        si: &SurfaceInteraction,
        wl: &Wavelengths<N>,
    ) -> Lobe<'a, N> {
        Lobe::ThinDielectric(ThinDielectric {
            eta: self.ior.eta(wl),
            reflectance: self.specular_reflectance.eval(si.uv, wl),
            transmittance: self.specular_transmittance.eval(si.uv, wl),
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
        "thindielectric"
    }
}
