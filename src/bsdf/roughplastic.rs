//! Rough plastic (Mitsuba's `roughplastic`): a rough dielectric coating (isotropic Beckmann or
//! GGX microfacets) over a diffuse base. The specular part is the coating's microfacet
//! reflection; the diffuse part is weighted by the coating's transmittance on the way in and out
//! (the light a rough dielectric interface refracts and does not mask), tabulated over cos θ at
//! load as Mitsuba does (64 entries, linear in cos θ), with internal reflections folded in
//! through the internal reflectance. Pinned to Mitsuba 3.9.1's values in tests/bsdf.rs.

use super::describe::plastic;
use super::microfacet::Microfacet;
use super::plastic::{fold_internal, specular_probability};
use super::{fresnel, BsdfLobe, BsdfParams, BsdfSample, Lobe, Param};
use crate::interaction::SurfaceInteraction;
use crate::math::sampling::{cosine_hemisphere_pdf, square_to_cosine_hemisphere};
use crate::spectrum::{Spectrum, Wavelengths};
use crate::texture::{SpectralTexture, TexPoint};
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

/// Entries of the transmittance table (Mitsuba's resolution).
pub const TABLE_SIZE: usize = 64;

/// The coating's transmittance 1 − albedo(cos θ) at cos θ = i / 63 (cos θ = 1e-6 for i = 0).
pub type TransmittanceTable = [f32; TABLE_SIZE];

#[derive(Clone, Copy, Debug)]
pub struct RoughPlastic<'a, const N: usize> {
    /// ρ' (internal scattering already folded in).
    pub diffuse: Spectrum<N>,
    pub specular: Spectrum<N>,
    pub eta: f32,
    pub microfacet: Microfacet,
    pub specular_weight: f32,
    pub transmittance: &'a TransmittanceTable,
}

/// The 32-point Gauss–Legendre rule mapped to [0, 1]: nodes and weights (which sum to 1).
static GL32: std::sync::LazyLock<([f32; 32], [f64; 32])> = std::sync::LazyLock::new(|| {
    let (x, w) = crate::math::quadrature::gauss_legendre(32);
    (
        std::array::from_fn(|i| (0.5 * x[i] + 0.5) as f32),
        std::array::from_fn(|i| 0.5 * w[i]),
    )
});

/// Mean of `g(wi, m)` over the visible normals m of direction cos θ = `mu`: a 32 × 32
/// Gauss–Legendre rule over the visible-normal sampler's unit square, as Mitsuba's
/// roughplastic integrates it for η > 1.
fn visible_normal_mean(mf: &Microfacet, mu: f32, g: impl Fn(Vec3, Vec3) -> f32) -> f32 {
    let wi = Vec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu);
    let (x, w) = &*GL32;
    let mut sum = 0.0f64;
    for a in 0..32 {
        for b in 0..32 {
            let u = Vec2::new(x[a], x[b]);
            sum += g(wi, mf.sample_visible(wi, u)) as f64 * (w[a] * w[b]);
        }
    }
    sum as f32
}

/// Directional transmittance of the rough coating (relative index `eta`) for incidence
/// cos θ = `mu`: the light that refracts through a microfacet and is not masked on its way out,
/// E over visible normals m of (1 − F(wi·m)) G1(wt, m), wt the direction refracted about m.
/// Light the coating neither reflects nor transmits (masked after scattering) is lost, as in
/// Mitsuba's roughplastic, which tabulates the same rough-dielectric transmittance.
///
/// The integrand is smooth over the sampler's square (no total internal reflection from
/// outside), so a 32 × 32 Gauss–Legendre rule, Mitsuba's for η > 1, takes it to 2.4e-5 of a
/// 512 × 512 grid, where the 64 × 64 midpoint grid of before erred by up to 8.3e-4 at 4 times
/// the cost (`transmittance_quadrature_matches_a_fine_grid`).
pub fn transmittance_at(mf: &Microfacet, eta: f32, mu: f32) -> f32 {
    visible_normal_mean(mf, mu, |wi, m| transmitted(mf, eta, wi, m))
}

/// The transmittance's integrand at microfacet normal `m`: (1 − F(wi·m)) G1(wt, m).
fn transmitted(mf: &Microfacet, eta: f32, wi: Vec3, m: Vec3) -> f32 {
    let cos_im = wi.dot(m);
    let (f, cos_t, _, eta_ti) = fresnel::dielectric(cos_im, eta);
    if f >= 1.0 {
        return 0.0;
    }
    // Refraction about m: cos_t is signed opposite to wi·m.
    let wt = -eta_ti * wi + (eta_ti * cos_im + cos_t) * m;
    (1.0 - f) * mf.g1(wt, m)
}

/// The transmittance table of a coating with relative index `eta` (built once per process:
/// see [`built_once`]).
pub fn transmittance_table(mf: &Microfacet, eta: f32) -> Box<TransmittanceTable> {
    Box::new(built_once::coating(mf, eta).transmittance)
}

/// The table's cos θ of entry `i`.
fn table_mu(i: usize) -> f32 {
    (i as f32 / (TABLE_SIZE - 1) as f32).max(1e-6)
}

/// The transmittance table and the internal reflectance, their 2 × 64 entries spread over the
/// threads: a dataset frame that draws its roughness builds new tables, 4 of them took 10% of a
/// tabletop frame's instructions on one core. Each entry is its own fixed sum and the internal
/// reflectance adds its entries in order, so the bits are those of one thread
/// (`parallel_tables_equal_sequential_ones`).
fn fresh_coating(mf: &Microfacet, eta: f32) -> (TransmittanceTable, f32) {
    use rayon::prelude::*;
    let entries: Vec<f32> = (0..2 * TABLE_SIZE)
        .into_par_iter()
        .map(|j| match j.checked_sub(TABLE_SIZE) {
            None => transmittance_at(mf, eta, table_mu(j)),
            Some(i) => reflectance_at(mf, 1.0 / eta, table_mu(i)) * table_mu(i),
        })
        .collect();
    let mut table = [0.0; TABLE_SIZE];
    table.copy_from_slice(&entries[..TABLE_SIZE]);
    let sum: f64 = entries[TABLE_SIZE..].iter().map(|&v| v as f64).sum();
    (table, (2.0 * sum / TABLE_SIZE as f64) as f32)
}

#[cfg(test)]
fn fresh_transmittance_table(mf: &Microfacet, eta: f32) -> Box<TransmittanceTable> {
    let mut t = Box::new([0.0; TABLE_SIZE]);
    for (i, v) in t.iter_mut().enumerate() {
        *v = transmittance_at(mf, eta, table_mu(i));
    }
    t
}

/// The coating's tables, built once per process for each (distribution, α, η).
///
/// Both cost 64 × 32² visible-normal samples each (a quarter of the 64³ they took on midpoint
/// grids), and depend on nothing else. A dataset run or a Python session rebuilds its scenes
/// frame after frame while a variation of colours or lights leaves the coating as it was, so
/// what was built is kept.
/// The tables are a deterministic function of the key: a kept table has the bits a fresh one
/// would, and renders do not change.
mod built_once {
    use super::{fresh_coating, TransmittanceTable};
    use crate::bsdf::microfacet::Microfacet;
    use std::collections::HashMap;
    use std::sync::{Arc, LazyLock, Mutex};

    /// (distribution, α_u, α_v, η) as bits: equal keys give equal tables.
    type Key = (u8, u32, u32, u32);

    pub struct Coating {
        pub transmittance: TransmittanceTable,
        pub internal: f32,
    }

    /// More coatings than any scene or dataset uses; past it the map starts over, so a long
    /// session drawing α and η at random stays bounded (4096 · ~270 bytes).
    const CAPACITY: usize = 4096;

    static COATINGS: LazyLock<Mutex<HashMap<Key, Arc<Coating>>>> =
        LazyLock::new(|| Mutex::new(HashMap::new()));

    pub fn coating(mf: &Microfacet, eta: f32) -> Arc<Coating> {
        let key = (
            mf.kind as u8,
            mf.alpha_u.to_bits(),
            mf.alpha_v.to_bits(),
            eta.to_bits(),
        );
        // A poisoned lock means another thread panicked around an insert of a whole value:
        // the map itself is intact.
        let found = COATINGS
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .get(&key)
            .cloned();
        found.unwrap_or_else(|| {
            // Built outside the lock: two threads may both build a new key, to equal values.
            let (transmittance, internal) = fresh_coating(mf, eta);
            let built = Arc::new(Coating {
                transmittance,
                internal,
            });
            let mut map = COATINGS.lock().unwrap_or_else(|e| e.into_inner());
            if map.len() >= CAPACITY {
                map.clear();
            }
            map.insert(key, built.clone());
            built
        })
    }

    #[cfg(test)]
    mod tests {
        use super::super::{fresh_coating, fresh_internal_reflectance, fresh_transmittance_table};
        use super::coating;
        use crate::bsdf::microfacet::{Distribution, Microfacet};

        /// A kept table is the fresh computation, bit for bit, for each key, and keys that
        /// differ in one part only get their own tables.
        #[test]
        fn kept_tables_equal_fresh_ones() {
            for (kind, alpha, eta) in [
                (Distribution::Beckmann, 0.1, 1.5),
                (Distribution::Ggx, 0.1, 1.5),
                (Distribution::Ggx, 0.3, 1.5),
                (Distribution::Ggx, 0.3, 1.33),
            ] {
                let mf = Microfacet::new(kind, alpha, alpha);
                let table = fresh_transmittance_table(&mf, eta).map(f32::to_bits);
                let internal = fresh_internal_reflectance(&mf, eta).to_bits();
                for _ in 0..2 {
                    let kept = coating(&mf, eta);
                    let what = format!("{kind:?} α {alpha} η {eta}");
                    assert_eq!(kept.transmittance.map(f32::to_bits), table, "{what}");
                    assert_eq!(kept.internal.to_bits(), internal, "{what}");
                }
            }
        }

        /// The tables built over the threads are the one-thread loops' bits, in a pool of 3
        /// (entries split unevenly) and of 1.
        #[test]
        fn parallel_tables_equal_sequential_ones() {
            let mf = Microfacet::new(Distribution::Ggx, 0.23, 0.23);
            let eta = 1.47;
            let table = fresh_transmittance_table(&mf, eta).map(f32::to_bits);
            let internal = fresh_internal_reflectance(&mf, eta).to_bits();
            for threads in [3, 1] {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                let (t, i) = pool.install(|| fresh_coating(&mf, eta));
                assert_eq!(t.map(f32::to_bits), table, "{threads} threads");
                assert_eq!(i.to_bits(), internal, "{threads} threads");
            }
        }
    }
}

/// Directional reflectance of the coating's microfacets for incidence cos θ = `mu` (from the
/// side where the relative index is `eta`): E over visible normals of F(wi·m) G1(wr, m), wr
/// the mirrored direction.
///
/// Seen from inside (η < 1) the integrand jumps where total internal reflection sets in, so no
/// rule is exact per entry (32 × 32 Gauss–Legendre and the 64 × 64 midpoint grid of before are
/// both up to 7e-3 off a 512 × 512 grid at Beckmann α 1), but the internal reflectance, the
/// mean over the table's 64 entries that is all the model uses, comes to 2.2e-4 of a 256 × 256
/// grid's with the Gauss–Legendre rule against the midpoint grid's 2.1e-3, at a quarter of
/// the cost (`internal_reflectance_matches_a_fine_grid`).
pub fn reflectance_at(mf: &Microfacet, eta: f32, mu: f32) -> f32 {
    visible_normal_mean(mf, mu, |wi, m| reflected(mf, eta, wi, m))
}

/// The reflectance's integrand at microfacet normal `m`: F(wi·m) G1(wr, m) where the mirrored
/// direction wr is above the surface, else 0.
fn reflected(mf: &Microfacet, eta: f32, wi: Vec3, m: Vec3) -> f32 {
    let wr = 2.0 * wi.dot(m) * m - wi;
    if wr.z > 0.0 {
        fresnel::dielectric(wi.dot(m), eta).0 * mf.g1(wr, m)
    } else {
        0.0
    }
}

/// The coating's internal reflectance: the cosine-weighted average over incidence of the
/// microfacet reflectance seen from inside (index 1/η), as Mitsuba 3's roughplastic defines
/// it, including its discretisation: 2 · mean of R(μ)·μ over the table's 64 evenly spaced μ
/// (endpoints included). That sum is a slightly low estimate of 2∫R(μ)μ dμ (0.479 against
/// 0.486 for GGX α 0.2, η 1.49), but it is the model's parameter: computing it exactly would
/// make prism's roughplastic 1.3% brighter than Mitsuba's instead of equal to it.
pub fn internal_reflectance(mf: &Microfacet, eta: f32) -> f32 {
    built_once::coating(mf, eta).internal
}

#[cfg(test)]
fn fresh_internal_reflectance(mf: &Microfacet, eta: f32) -> f32 {
    let sum: f64 = (0..TABLE_SIZE)
        .map(|i| {
            let mu = table_mu(i);
            (reflectance_at(mf, 1.0 / eta, mu) * mu) as f64
        })
        .sum();
    (2.0 * sum / TABLE_SIZE as f64) as f32
}

impl<const N: usize> RoughPlastic<'_, N> {
    #[inline]
    fn transmittance(&self, cos: f32) -> f32 {
        let x = cos.clamp(0.0, 1.0) * (TABLE_SIZE - 1) as f32;
        let i = (x as usize).min(TABLE_SIZE - 2);
        let t = x - i as f32;
        self.transmittance[i] * (1.0 - t) + self.transmittance[i + 1] * t
    }
}

impl<const N: usize> BsdfLobe<N> for RoughPlastic<'_, N> {
    #[inline]
    fn eval(&self, wi: Vec3, wo: Vec3) -> Spectrum<N> {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return Spectrum::zero();
        }
        let h = (wi + wo).normalize();
        let spec = fresnel::dielectric(wi.dot(h), self.eta).0
            * self.microfacet.d(h)
            * self.microfacet.g(wi, wo, h)
            / (4.0 * wi.z);
        let diff = FRAC_1_PI * wo.z * self.transmittance(wi.z) * self.transmittance(wo.z)
            / (self.eta * self.eta);
        self.specular * spec + self.diffuse * diff
    }

    #[inline]
    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        let p_spec = specular_probability(1.0 - self.transmittance(wi.z), self.specular_weight);
        let h = (wi + wo).normalize();
        // Visible-normal sampling, reflected: pdf(wo) = D(h) G1(wi, h) / (4 cos θi).
        let spec = self.microfacet.d(h) * self.microfacet.g1(wi, h) / (4.0 * wi.z);
        p_spec * spec + (1.0 - p_spec) * cosine_hemisphere_pdf(wo.z)
    }

    #[inline]
    fn sample(&self, wi: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample<N>> {
        if wi.z <= 0.0 {
            return None;
        }
        let p_spec = specular_probability(1.0 - self.transmittance(wi.z), self.specular_weight);
        let wo = if uc < p_spec {
            let m = self.microfacet.sample_visible(wi, u);
            2.0 * wi.dot(m) * m - wi
        } else {
            square_to_cosine_hemisphere(u)
        };
        let pdf = self.pdf(wi, wo);
        if pdf <= 0.0 {
            return None;
        }
        Some(BsdfSample::reflection(wo, pdf, self.eval(wi, wo) / pdf))
    }

    #[inline]
    fn glossy(&self, _max_alpha: f32) -> bool {
        false
    }
}

/// A rough plastic's parameters over the surface, with its coating's tables computed at load.
#[derive(Clone, Debug, PartialEq)]
pub struct RoughPlasticParams {
    pub diffuse: SpectralTexture,
    pub specular: SpectralTexture,
    pub eta: f32,
    pub microfacet: Microfacet,
    pub transmittance: Box<TransmittanceTable>,
    pub internal: f32,
    pub nonlinear: bool,
    pub specular_weight: f32,
}

impl BsdfParams for RoughPlasticParams {
    #[inline]
    fn lobe<'a, const N: usize>(
        &'a self,
        si: &SurfaceInteraction,
        wl: &Wavelengths<N>,
    ) -> Lobe<'a, N> {
        Lobe::RoughPlastic(RoughPlastic {
            diffuse: fold_internal(self.diffuse.eval(si.uv, wl), self.internal, self.nonlinear),
            specular: self.specular.eval(si.uv, wl),
            eta: self.eta,
            microfacet: self.microfacet,
            specular_weight: self.specular_weight,
            transmittance: &self.transmittance,
        })
    }

    fn focuses_light(&self) -> bool {
        false
    }

    fn diffuse_reflectance(&self, uv: TexPoint, wl: &Wavelengths<1>) -> f32 {
        self.diffuse.eval(uv, wl)[0]
    }

    fn traverse<'a>(&'a self, put: &mut impl FnMut(&'static str, Param<'a>)) -> &'static str {
        plastic(&self.diffuse, &self.specular, self.eta, self.nonlinear, put);
        put("distribution", Param::Distribution(self.microfacet.kind));
        put("alpha", Param::Number(self.microfacet.alpha_u));
        "roughplastic"
    }
}

#[cfg(test)]
#[path = "roughplastic_tests.rs"]
mod quadrature_tests;
