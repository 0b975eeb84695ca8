//! A rough interface between two dielectrics (Mitsuba 3's `roughdielectric`): the microfacet
//! model of Walter et al. 2007, "Microfacet Models for Refraction through Rough Surfaces",
//! sampled through the visible normals (Heitz & d'Eon 2014).
//!
//! ```ron
//! RoughDielectric(distribution: Ggx, alpha: 0.05, int_ior: Glass("SF11"))
//! ```
//!
//! Conventions as the smooth `dielectric` (η = n_int / n_ext, two-sided, radiance transport).
//! With m the half vector (reflection: wi + wo; refraction: the generalised wi + η_it wo, turned
//! to the normal's side), D the distribution, G = G1(wi) G1(wo) and F the Fresnel reflectance at
//! wi·m, the radiance-mode BSDF times |cos θ_o| is
//!
//! - reflection: R · F D G / (4 |cos θ_i|),
//! - refraction: T · (1 − F) D G |wi·m| |wo·m| / (|cos θ_i| (wi·m + η_it wo·m)²)
//!   (Walter's BTDF times the radiance scaling 1/η_it², which cancels its η_it² numerator).
//!
//! Sampling draws a visible normal from the hero's wi, then reflects with probability F_hero.
//! Lane k's density of the same wo uses its own η_k: the same m for reflection (only F_k
//! differs), its own generalised half vector for refraction. Those densities are `pdf_lanes`.

use super::describe::{dielectric, rough};
use super::fresnel;
use super::microfacet::Distribution;
use super::microfacet::Microfacet;
use super::{BsdfLobe, BsdfParams, BsdfSample, Lobe, Param};
use crate::interaction::SurfaceInteraction;
use crate::spectrum::{RelativeIor, Spectrum, Wavelengths};
use crate::texture::{FloatTexture, SpectralTexture};
use glam::{Vec2, Vec3};

#[derive(Clone, Copy, Debug)]
pub struct RoughDielectric<const N: usize> {
    /// η = n_int / n_ext at each lane.
    pub eta: Spectrum<N>,
    pub reflectance: Spectrum<N>,
    pub transmittance: Spectrum<N>,
    pub dist: Microfacet,
    /// η differs between lanes (decided at load from the IORs).
    pub dispersive: bool,
}

impl<const N: usize> RoughDielectric<N> {
    /// For one lane's η: f·|cos θ_o| without the specular factors, the density with which
    /// `sample` (driven by that η) produces wo, and whether wo is a reflection.
    #[inline]
    fn lane(&self, wi: Vec3, wo: Vec3, eta: f32) -> (f32, f32, bool) {
        let (ci, co) = (wi.z, wo.z);
        let reflect = ci * co > 0.0;
        if ci == 0.0 || co == 0.0 {
            return (0.0, 0.0, reflect);
        }
        let eta_it = if ci > 0.0 { eta } else { 1.0 / eta };
        let h = if reflect { wi + wo } else { wi + wo * eta_it };
        let len = h.length();
        if !(len > 0.0 && len.is_finite()) {
            return (0.0, 0.0, reflect);
        }
        let m = if h.z < 0.0 { -h / len } else { h / len };
        let (wim, wom) = (wi.dot(m), wo.dot(m));
        // Each direction must see the facet from its own side of the surface.
        if wim * ci <= 0.0 || wom * co <= 0.0 {
            return (0.0, 0.0, reflect);
        }
        let d = self.dist.d(m);
        if d == 0.0 {
            return (0.0, 0.0, reflect);
        }
        let f = fresnel::dielectric(wim, eta).0;
        let g = self.dist.g(wi, wo, m);
        let pdf_m = self.dist.pdf_visible(wi, m);
        if reflect {
            let value = f * d * g / (4.0 * ci.abs());
            (value, pdf_m * f / (4.0 * wom.abs()), true)
        } else {
            // (wi·m + η_it wo·m)² is |h|² before normalisation.
            let denom2 = len * len;
            let value = (1.0 - f) * d * g * (wim * wom).abs() / (ci.abs() * denom2);
            let pdf = pdf_m * (1.0 - f) * eta_it * eta_it * wom.abs() / denom2;
            (value, pdf, false)
        }
    }

    /// Per-lane values and densities (computed once and copied when η is the same everywhere).
    #[inline]
    fn lanes(&self, wi: Vec3, wo: Vec3) -> (Spectrum<N>, Spectrum<N>, bool) {
        let (v0, p0, reflect) = self.lane(wi, wo, self.eta[0]);
        if !self.dispersive {
            return (Spectrum::splat(v0), Spectrum::splat(p0), reflect);
        }
        let mut v = Spectrum::splat(v0);
        let mut p = Spectrum::splat(p0);
        for k in 1..N {
            (v[k], p[k], _) = self.lane(wi, wo, self.eta[k]);
        }
        (v, p, reflect)
    }
}

impl<const N: usize> BsdfLobe<N> for RoughDielectric<N> {
    #[inline]
    fn eval(&self, wi: Vec3, wo: Vec3) -> Spectrum<N> {
        let (v, _, reflect) = self.lanes(wi, wo);
        v * if reflect {
            self.reflectance
        } else {
            self.transmittance
        }
    }

    #[inline]
    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        self.lane(wi, wo, self.eta[0]).1
    }

    #[inline]
    fn pdf_lanes(&self, wi: Vec3, wo: Vec3) -> Spectrum<N> {
        self.lanes(wi, wo).1
    }

    #[inline]
    fn sample(&self, wi: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample<N>> {
        if wi.z == 0.0 {
            return None;
        }
        let m = self.dist.sample_visible(wi, u);
        let wim = wi.dot(m);
        let (f_h, cos_t, eta_it, eta_ti) = fresnel::dielectric(wim, self.eta[0]);
        let reflect = uc < f_h;
        let wo = if reflect {
            2.0 * wim * m - wi
        } else {
            // Snell about m: wo·m = cos θ_t, tangential part −η_ti times wi's.
            (eta_ti * wim + cos_t) * m - eta_ti * wi
        }
        .normalize();
        // A facet can send the path below (reflection) or back above (refraction) the
        // macro-surface: such samples carry no energy (Smith's G1(wo) = 0).
        if (wo.z * wi.z > 0.0) != reflect || wo.z == 0.0 {
            return None;
        }
        let (v, p, _) = self.lanes(wi, wo);
        let pdf = p[0];
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        let rt = if reflect {
            self.reflectance
        } else {
            self.transmittance
        };
        Some(BsdfSample {
            wo,
            pdf,
            pdf_lanes: p,
            weight: v * rt / pdf,
            delta: false,
            eta: if reflect { 1.0 } else { eta_it },
        })
    }

    #[inline]
    fn glossy(&self, max_alpha: f32) -> bool {
        self.dist.alpha_u.max(self.dist.alpha_v) <= max_alpha
    }

    #[inline]
    fn dispersive(&self) -> bool {
        self.dispersive
    }
}

/// A rough dielectric interface's parameters over the surface.
#[derive(Clone, Debug, PartialEq)]
pub struct RoughDielectricParams {
    pub ior: RelativeIor,
    pub distribution: Distribution,
    pub alpha_u: FloatTexture,
    pub alpha_v: FloatTexture,
    pub specular_reflectance: SpectralTexture,
    pub specular_transmittance: SpectralTexture,
}

impl BsdfParams for RoughDielectricParams {
    #[inline]
    fn lobe<'a, const N: usize>(
        &'a self,
        si: &SurfaceInteraction,
        wl: &Wavelengths<N>,
    ) -> Lobe<'a, N> {
        Lobe::RoughDielectric(RoughDielectric {
            eta: self.ior.eta(wl),
            reflectance: self.specular_reflectance.eval(si.uv, wl),
            transmittance: self.specular_transmittance.eval(si, wl),
            // Texture values outside [0, 1] are clamped, as for conductors.
            dist: Microfacet::new(
                self.distribution,
                self.alpha_u.eval(si.uv).clamp(0.0, 1.0),
                self.alpha_v.eval(si.uv).clamp(0.0, 1.0),
            ),
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
        rough(self.distribution, &self.alpha_u, &self.alpha_v, put);
        "roughdielectric"
    }
}
