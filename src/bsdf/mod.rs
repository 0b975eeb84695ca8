//! Materials and BSDFs.
//!
//! A `Material` is what the scene holds: a tree of BSDFs (Mitsuba's names: `diffuse`,
//! `conductor`, `dielectric`, …, combined by `twosided`, `blend` and `mask`) whose parameters
//! are spectra or textures. At a hit it becomes a `Bsdf<N>`: a mixture of at most `MAX_LOBES`
//! leaf lobes with their parameters evaluated at the path's N wavelengths and the hit's uv,
//! built on the stack (no allocation, static dispatch). A plain `diffuse` material, the
//! commonest by far, becomes a lone diffuse lobe instead, which the integrator handles without
//! any of the mixture's machinery: a diffuse-only scene pays nothing for the other materials
//! (docs/performance.md).
//!
//! Directions are in the local shading frame (z = normal) and point away from the surface:
//! `wi` towards the previous vertex (the camera side), `wo` towards the next (the light side).
//! Leaf BSDFs are one-sided where Mitsuba's are (light from below a diffuse surface is black);
//! `twosided` mirrors directions (z → −z) for the back side.
//!
//! Wavelength-dependent sampling (dispersion): a sample reports the density with which each
//! lane's BSDF would have produced the same direction (`pdf_lanes`); the integrator weights the
//! lanes by spectral MIS with them (Wilkie et al. 2014).

mod conductor;
pub mod dielectric;
mod diffuse;
pub mod fresnel;
pub mod microfacet;
mod plastic;
pub mod principled;
mod roughconductor;
pub mod roughdielectric;
pub mod roughplastic;
pub mod thindielectric;

use crate::interaction::SurfaceInteraction;
use crate::spectrum::{RelativeIor, Spectrum, Wavelengths};
use crate::texture::{FloatTexture, SpectralTexture};
use arrayvec::ArrayVec;
pub use conductor::{Conductor, ConductorParams};
pub use dielectric::Dielectric;
pub use diffuse::Diffuse;
use glam::{Vec2, Vec3};
use microfacet::{Distribution, Microfacet};
pub use plastic::Plastic;
pub use principled::{Principled, PrincipledParams, SpecularColorTexture};
pub use roughconductor::RoughConductor;
pub use roughdielectric::RoughDielectric;
pub use roughplastic::RoughPlastic;
pub use thindielectric::ThinDielectric;

/// Most leaf lobes one material may combine (blends and masks of blends…).
pub const MAX_LOBES: usize = 4;

/// A material of the scene.
#[derive(Clone, Debug, PartialEq)]
pub enum Material {
    /// Lambertian reflection (Mitsuba's `diffuse`).
    Diffuse { reflectance: SpectralTexture },
    /// `front` on the front side, `back` (mirrored) on the back (Mitsuba's `twosided`).
    Twosided {
        front: Box<Material>,
        back: Box<Material>,
    },
    /// (1 − weight)·a + weight·b (Mitsuba's `blendbsdf`).
    Blend {
        a: Box<Material>,
        b: Box<Material>,
        weight: FloatTexture,
    },
    /// Opacity·inner, the rest passes straight through (Mitsuba's `mask`).
    Mask {
        inner: Box<Material>,
        opacity: FloatTexture,
    },
    // Conductors.
    /// Mirror reflection with a conductor's Fresnel reflectance (Mitsuba's `conductor`).
    Conductor(ConductorParams),
    /// Microfacet reflection from a conductor (Mitsuba's `roughconductor`); the roughnesses
    /// along the tangent and bitangent may vary over the surface.
    RoughConductor {
        params: ConductorParams,
        distribution: Distribution,
        alpha_u: FloatTexture,
        alpha_v: FloatTexture,
    },
    // Dielectrics.
    /// A smooth dielectric interface (Mitsuba's `dielectric`).
    Dielectric {
        ior: RelativeIor,
        specular_reflectance: SpectralTexture,
        specular_transmittance: SpectralTexture,
    },
    /// A rough dielectric interface (Mitsuba's `roughdielectric`).
    RoughDielectric {
        ior: RelativeIor,
        distribution: Distribution,
        alpha_u: FloatTexture,
        alpha_v: FloatTexture,
        specular_reflectance: SpectralTexture,
        specular_transmittance: SpectralTexture,
    },
    /// An infinitely thin dielectric slab (Mitsuba's `thindielectric`).
    ThinDielectric {
        ior: RelativeIor,
        specular_reflectance: SpectralTexture,
        specular_transmittance: SpectralTexture,
    },
    // Plastics.
    /// A smooth dielectric coating over a diffuse base (Mitsuba's `plastic`).
    Plastic {
        diffuse: SpectralTexture,
        specular: SpectralTexture,
        eta: f32,
        /// Hemispherical average of the internal Fresnel reflectance.
        internal: f32,
        nonlinear: bool,
        specular_weight: f32,
    },
    /// A rough coating over a diffuse base (Mitsuba's `roughplastic`).
    RoughPlastic {
        diffuse: SpectralTexture,
        specular: SpectralTexture,
        eta: f32,
        microfacet: Microfacet,
        transmittance: Box<roughplastic::TransmittanceTable>,
        internal: f32,
        nonlinear: bool,
        specular_weight: f32,
    },
    /// The glTF 2.0 metallic-roughness BRDF (`principled`).
    Principled(Box<PrincipledParams>),
}

/// ρ' = ρ / (1 − F_dr), or ρ / (1 − ρ F_dr) with `nonlinear`: the diffuse base with the light
/// that bounces between it and the coating's underside folded in.
#[inline]
fn fold_internal<const N: usize>(rho: Spectrum<N>, internal: f32, nonlinear: bool) -> Spectrum<N> {
    if nonlinear {
        Spectrum::from_fn(|i| rho[i] / (1.0 - rho[i] * internal))
    } else {
        rho / (1.0 - internal)
    }
}

/// One leaf BSDF at a hit, at the path's wavelengths.
#[derive(Clone, Copy, Debug)]
pub enum Lobe<'a, const N: usize> {
    Diffuse(Diffuse<N>),
    // Conductors.
    /// Mirror reflection, Fresnel-weighted per wavelength.
    Conductor(Conductor<N>),
    /// Microfacet reflection, Fresnel-weighted per wavelength.
    RoughConductor(RoughConductor<N>),
    // Dielectrics.
    Dielectric(Dielectric<N>),
    RoughDielectric(RoughDielectric<N>),
    ThinDielectric(ThinDielectric<N>),
    // Plastics.
    Plastic(Plastic<N>),
    RoughPlastic(RoughPlastic<'a, N>),
    Principled(Principled<N>),
    /// Passes light straight through, unchanged (the transparent part of a `mask`).
    Null,
}

/// A sampled outgoing direction.
#[derive(Clone, Copy, Debug)]
pub struct BsdfSample<const N: usize> {
    pub wo: Vec3,
    /// Density of `wo` under the hero wavelength's BSDF (solid angle; for a Dirac lobe, the
    /// discrete probability of choosing it).
    pub pdf: f32,
    /// The same density for each lane's BSDF (equal to `pdf` in every lane unless sampling
    /// depends on wavelength; 0 where that lane could not have produced `wo`).
    pub pdf_lanes: Spectrum<N>,
    /// f · |cos θ_o| / pdf, per lane.
    pub weight: Spectrum<N>,
    /// True for a Dirac lobe: no emitter sampling, no MIS.
    pub delta: bool,
    /// Relative index of refraction crossed, for the hero (1 for reflection).
    pub eta: f32,
}

impl<const N: usize> BsdfSample<N> {
    /// A sample of a smooth reflection lobe whose sampling does not depend on wavelength:
    /// every lane's density is the hero's.
    #[inline]
    pub fn reflection(wo: Vec3, pdf: f32, weight: Spectrum<N>) -> Self {
        Self {
            wo,
            pdf,
            pdf_lanes: Spectrum::splat(pdf),
            weight,
            delta: false,
            eta: 1.0,
        }
    }
}

/// A BSDF at one hit.
#[derive(Clone, Debug)]
pub enum Bsdf<'a, const N: usize> {
    /// A plain `diffuse` material: one front-side lobe of weight 1 (every hit of a diffuse-only
    /// scene). Kept apart so that the integrator can run its per-hit code on it directly,
    /// without the mixture's loops over lobes, dispatch on their kind and calls out of line.
    Diffuse(Diffuse<N>),
    /// Any other material.
    Mixture(Mixture<'a, N>),
}

/// Leaf lobes whose weights sum to 1, each on its side (`twosided` mirrors the back side).
#[derive(Clone, Debug, Default)]
pub struct Mixture<'a, const N: usize> {
    // An ArrayVec rather than a filled array: most hits have one lobe, and initialising all
    // MAX_LOBES slots of the largest lobe variant at every hit showed in profiles.
    lobes: ArrayVec<(Lobe<'a, N>, f32, bool), MAX_LOBES>,
}

/// An empty mixture (for `fill_bsdf` to fill).
impl<const N: usize> Default for Bsdf<'_, N> {
    fn default() -> Self {
        Bsdf::Mixture(Mixture::default())
    }
}

impl Material {
    /// The most leaf lobes this material can produce at a hit (checked against `MAX_LOBES`).
    pub fn max_lobes(&self) -> usize {
        match self {
            Material::Twosided { front, back } => front.max_lobes().max(back.max_lobes()),
            Material::Blend { a, b, .. } => a.max_lobes() + b.max_lobes(),
            Material::Mask { inner, .. } => inner.max_lobes() + 1,
            _ => 1,
        }
    }

    /// True if some lobe of the material samples directions by wavelength (a dielectric with a
    /// dispersive index): the integrator then keeps per-lane densities.
    pub fn dispersive(&self) -> bool {
        match self {
            Material::Twosided { front, back } => front.dispersive() || back.dispersive(),
            Material::Blend { a, b, .. } => a.dispersive() || b.dispersive(),
            Material::Mask { inner, .. } => inner.dispersive(),
            Material::Dielectric { ior, .. }
            | Material::RoughDielectric { ior, .. }
            | Material::ThinDielectric { ior, .. } => ior.dispersive(),
            Material::Diffuse { .. }
            | Material::Conductor(_)
            | Material::RoughConductor { .. }
            | Material::Plastic { .. }
            | Material::RoughPlastic { .. }
            | Material::Principled(_) => false,
        }
    }

    /// True if some lobe of the material can focus light into caustics: a Dirac lobe (a
    /// mirror, a smooth interface or coating, a mask's pass-through) or a microfacet conductor
    /// or dielectric (glossy if smooth enough). The objects caustic light tracing aims at.
    pub fn focuses_light(&self) -> bool {
        match self {
            Material::Twosided { front, back } => front.focuses_light() || back.focuses_light(),
            Material::Blend { a, b, .. } => a.focuses_light() || b.focuses_light(),
            Material::Mask { .. }
            | Material::Conductor(_)
            | Material::RoughConductor { .. }
            | Material::Dielectric { .. }
            | Material::RoughDielectric { .. }
            | Material::ThinDielectric { .. }
            | Material::Plastic { .. }
            | Material::Principled(_) => true,
            Material::Diffuse { .. } | Material::RoughPlastic { .. } => false,
        }
    }

    /// The BSDF at `si` for a path arriving from local direction `wi`.
    #[inline]
    pub fn bsdf<'a, const N: usize>(
        &'a self,
        si: &SurfaceInteraction,
        wi: Vec3,
        wl: &Wavelengths<N>,
    ) -> Bsdf<'a, N> {
        let mut b = Bsdf::default();
        self.fill_bsdf(si, wi, wl, &mut b);
        b
    }

    /// `bsdf`, written into `out`: the path loop reuses one `Bsdf`, so a mixture's lobes are
    /// written once in place instead of being returned and copied at every hit.
    #[inline(always)]
    pub fn fill_bsdf<'a, const N: usize>(
        &'a self,
        si: &SurfaceInteraction,
        wi: Vec3,
        wl: &Wavelengths<N>,
        out: &mut Bsdf<'a, N>,
    ) {
        // The commonest material, built here, inline (add_lobes is recursive, so never inlined).
        if let Material::Diffuse { reflectance } = self {
            *out = Bsdf::Diffuse(Diffuse {
                reflectance: reflectance.eval(si.uv, wl),
            });
            return;
        }
        if !matches!(out, Bsdf::Mixture(_)) {
            *out = Bsdf::default();
        }
        let Bsdf::Mixture(m) = out else {
            unreachable!("`out` was made a mixture just above")
        };
        m.lobes.clear();
        self.add_lobes(si, wi.z, wl, 1.0, false, m);
    }

    /// Adds the material's lobes to `out`, their weights scaled by `weight`. Of the direction
    /// the path arrives from only its side matters here (`twosided`), so only `cos_i` = wi.z
    /// is passed: wi.x and wi.y are then computed only where a mixture reads them, never for a
    /// diffuse-only scene.
    fn add_lobes<'a, const N: usize>(
        &'a self,
        si: &SurfaceInteraction,
        cos_i: f32,
        wl: &Wavelengths<N>,
        weight: f32,
        flip: bool,
        out: &mut Mixture<'a, N>,
    ) {
        let lobe = match self {
            Material::Diffuse { reflectance } => Lobe::Diffuse(Diffuse {
                reflectance: reflectance.eval(si.uv, wl),
            }),
            // Conductors.
            // Dielectrics.
            Material::Dielectric {
                ior,
                specular_reflectance,
                specular_transmittance,
            } => Lobe::Dielectric(Dielectric {
                eta: ior.eta(wl),
                reflectance: specular_reflectance.eval(si.uv, wl),
                transmittance: specular_transmittance.eval(si.uv, wl),
                dispersive: ior.dispersive(),
            }),
            Material::RoughDielectric {
                ior,
                distribution,
                alpha_u,
                alpha_v,
                specular_reflectance,
                specular_transmittance,
            } => Lobe::RoughDielectric(RoughDielectric {
                eta: ior.eta(wl),
                reflectance: specular_reflectance.eval(si.uv, wl),
                transmittance: specular_transmittance.eval(si.uv, wl),
                // Texture values outside [0, 1] are clamped, as for conductors.
                dist: Microfacet::new(
                    *distribution,
                    alpha_u.eval(si.uv).clamp(0.0, 1.0),
                    alpha_v.eval(si.uv).clamp(0.0, 1.0),
                ),
                dispersive: ior.dispersive(),
            }),
            Material::ThinDielectric {
                ior,
                specular_reflectance,
                specular_transmittance,
            } => Lobe::ThinDielectric(ThinDielectric {
                eta: ior.eta(wl),
                reflectance: specular_reflectance.eval(si.uv, wl),
                transmittance: specular_transmittance.eval(si.uv, wl),
                dispersive: ior.dispersive(),
            }),
            // Plastics.
            Material::Plastic {
                diffuse,
                specular,
                eta,
                internal,
                nonlinear,
                specular_weight,
            } => Lobe::Plastic(Plastic {
                diffuse: fold_internal(diffuse.eval(si.uv, wl), *internal, *nonlinear),
                specular: specular.eval(si.uv, wl),
                eta: *eta,
                specular_weight: *specular_weight,
            }),
            Material::RoughPlastic {
                diffuse,
                specular,
                eta,
                microfacet,
                transmittance,
                internal,
                nonlinear,
                specular_weight,
            } => Lobe::RoughPlastic(RoughPlastic {
                diffuse: fold_internal(diffuse.eval(si.uv, wl), *internal, *nonlinear),
                specular: specular.eval(si.uv, wl),
                eta: *eta,
                microfacet: *microfacet,
                specular_weight: *specular_weight,
                transmittance,
            }),
            Material::Twosided { front, back } => {
                // The side is decided by where the path arrives from, as Mitsuba does.
                let back_side = (cos_i < 0.0) != flip;
                let m = if back_side { back } else { front };
                m.add_lobes(si, cos_i, wl, weight, flip ^ back_side, out);
                return;
            }
            Material::Blend { a, b, weight: w } => {
                let t = unit_weight(w.eval(si.uv));
                a.add_lobes(si, cos_i, wl, weight * (1.0 - t), flip, out);
                b.add_lobes(si, cos_i, wl, weight * t, flip, out);
                return;
            }
            Material::Mask { inner, opacity } => {
                let a = unit_weight(opacity.eval(si.uv));
                inner.add_lobes(si, cos_i, wl, weight * a, flip, out);
                Lobe::Null.push(weight * (1.0 - a), false, out);
                return;
            }
            Material::Conductor(p) => Lobe::Conductor(p.at(si.uv, wl)),
            Material::Principled(p) => Lobe::Principled(p.at(si.uv, wl)),
            Material::RoughConductor {
                params,
                distribution,
                alpha_u,
                alpha_v,
            } => Lobe::RoughConductor(RoughConductor {
                surface: params.at(si.uv, wl),
                // Texture values outside [0, 1] are clamped, as for blend weights and opacities.
                distr: Microfacet::new(
                    *distribution,
                    alpha_u.eval(si.uv).clamp(0.0, 1.0),
                    alpha_v.eval(si.uv).clamp(0.0, 1.0),
                ),
            }),
        };
        lobe.push(weight, flip, out);
    }
}

/// A texture value as a lobe weight in [0, 1]: clamped, and NaN (a NaN texel) taken as 0, so a
/// mixture never gets a NaN weight (nor, its lobes all dropped, no lobe at all).
#[inline]
fn unit_weight(v: f32) -> f32 {
    if v > 0.0 {
        v.min(1.0)
    } else {
        0.0
    }
}

impl<'a, const N: usize> Lobe<'a, N> {
    fn push(self, weight: f32, flip: bool, out: &mut Mixture<'a, N>) {
        if weight > 0.0 && !out.lobes.is_full() {
            out.lobes.push((self, weight, flip));
        }
    }

    /// f(wi, wo) · |cos θ_o| per lane (0 for Dirac lobes).
    #[inline]
    fn eval(&self, wi: Vec3, wo: Vec3) -> Spectrum<N> {
        match self {
            Lobe::Diffuse(b) => b.eval(wi, wo),
            // Conductors.
            Lobe::Conductor(_) => Spectrum::zero(),
            Lobe::RoughConductor(b) => b.eval(wi, wo),
            // Dielectrics.
            Lobe::RoughDielectric(b) => b.eval(wi, wo),
            Lobe::Dielectric(_) | Lobe::ThinDielectric(_) => Spectrum::zero(),
            // Plastics.
            Lobe::Plastic(b) => b.eval(wi, wo),
            Lobe::RoughPlastic(b) => b.eval(wi, wo),
            Lobe::Principled(b) => b.eval(wi, wo),
            Lobe::Null => Spectrum::zero(),
        }
    }

    /// Hero density of sampling `wo` (0 for Dirac lobes).
    #[inline]
    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        match self {
            Lobe::Diffuse(b) => b.pdf(wi, wo),
            // Conductors.
            Lobe::Conductor(_) => 0.0,
            Lobe::RoughConductor(b) => b.pdf(wi, wo),
            // Dielectrics.
            Lobe::RoughDielectric(b) => b.pdf(wi, wo),
            Lobe::Dielectric(_) | Lobe::ThinDielectric(_) => 0.0,
            // Plastics.
            Lobe::Plastic(b) => b.pdf(wi, wo),
            Lobe::RoughPlastic(b) => b.pdf(wi, wo),
            Lobe::Principled(b) => b.pdf(wi, wo),
            Lobe::Null => 0.0,
        }
    }

    /// Per-lane densities of sampling `wo`.
    #[inline]
    fn pdf_lanes(&self, wi: Vec3, wo: Vec3) -> Spectrum<N> {
        match self {
            Lobe::Diffuse(_) | Lobe::Null => Spectrum::splat(self.pdf(wi, wo)),
            // Conductors.
            Lobe::Conductor(_) | Lobe::RoughConductor(_) => Spectrum::splat(self.pdf(wi, wo)),
            // Dielectrics.
            Lobe::RoughDielectric(b) => b.pdf_lanes(wi, wo),
            Lobe::Dielectric(_) | Lobe::ThinDielectric(_) => Spectrum::zero(),
            // Plastics.
            Lobe::Plastic(_) | Lobe::RoughPlastic(_) | Lobe::Principled(_) => {
                Spectrum::splat(self.pdf(wi, wo))
            }
        }
    }

    #[inline]
    fn sample(&self, wi: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample<N>> {
        match self {
            Lobe::Diffuse(b) => b.sample(wi, uc, u),
            // Conductors.
            Lobe::Conductor(b) => b.sample(wi, uc, u),
            Lobe::RoughConductor(b) => b.sample(wi, uc, u),
            // Dielectrics.
            Lobe::Dielectric(b) => b.sample(wi, uc, u),
            Lobe::RoughDielectric(b) => b.sample(wi, uc, u),
            Lobe::ThinDielectric(b) => b.sample(wi, uc, u),
            // Plastics.
            Lobe::Plastic(b) => b.sample(wi, uc, u),
            Lobe::RoughPlastic(b) => b.sample(wi, uc, u),
            Lobe::Principled(b) => b.sample(wi, uc, u),
            Lobe::Null => Some(BsdfSample {
                wo: -wi,
                pdf: 1.0,
                pdf_lanes: Spectrum::one(),
                weight: Spectrum::one(),
                delta: true,
                eta: 1.0,
            }),
        }
    }

    /// True if the lobe has a non-Dirac part (emitter sampling can reach it).
    #[inline]
    fn has_smooth(&self) -> bool {
        match self {
            Lobe::Diffuse(_) => true,
            // Conductors.
            Lobe::Conductor(_) => false,
            Lobe::RoughConductor(_) => true,
            // Dielectrics.
            Lobe::RoughDielectric(_) => true,
            Lobe::Dielectric(_) | Lobe::ThinDielectric(_) => false,
            // Plastics.
            Lobe::Plastic(_) | Lobe::RoughPlastic(_) | Lobe::Principled(_) => true,
            Lobe::Null => false,
        }
    }

    /// True if the lobe is a Dirac lobe or a microfacet lobe no rougher than `max_alpha`.
    #[inline]
    fn glossy(&self, max_alpha: f32) -> bool {
        match self {
            Lobe::Conductor(_) | Lobe::Dielectric(_) | Lobe::ThinDielectric(_) | Lobe::Null => true,
            Lobe::RoughConductor(b) => b.distr.alpha_u.max(b.distr.alpha_v) <= max_alpha,
            Lobe::RoughDielectric(b) => b.dist.alpha_u.max(b.dist.alpha_v) <= max_alpha,
            // Only a pure metal is glossy throughout (a dielectric has a diffuse base).
            Lobe::Principled(b) => b.metallic >= 1.0 && b.distr.alpha_u <= max_alpha,
            Lobe::Diffuse(_) | Lobe::Plastic(_) | Lobe::RoughPlastic(_) => false,
        }
    }

    /// True if the lobe's sampling depends on wavelength.
    #[inline]
    fn dispersive(&self) -> bool {
        match self {
            Lobe::Diffuse(_) | Lobe::Null => false,
            // Conductors.
            Lobe::Conductor(_) | Lobe::RoughConductor(_) => false,
            // Dielectrics.
            Lobe::Dielectric(b) => b.dispersive,
            Lobe::RoughDielectric(b) => b.dispersive,
            Lobe::ThinDielectric(b) => b.dispersive,
            // Plastics.
            Lobe::Plastic(_) | Lobe::RoughPlastic(_) | Lobe::Principled(_) => false,
        }
    }
}

/// Mirrors a local direction through the tangent plane (the back side of a `twosided`).
#[inline]
fn mirror(v: Vec3, flip: bool) -> Vec3 {
    if flip {
        Vec3::new(v.x, v.y, -v.z)
    } else {
        v
    }
}

/// What the integrator asks of a BSDF at a hit; directions in the local shading frame.
///
/// `Bsdf` answers by dispatching to its variant. The integrator instead matches on the variant
/// once per hit and runs its per-hit code on the variant itself (generic code, one copy per
/// variant), so a plain diffuse material costs no dispatch at all (`integrator::path`).
pub trait BsdfLike<const N: usize> {
    /// f(wi, wo) · |cos θ_o| of the smooth lobes (Dirac lobes contribute nothing here).
    fn eval(&self, wi: Vec3, wo: Vec3) -> Spectrum<N>;
    /// Hero density with which `sample` produces `wo` from its smooth lobes.
    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32;
    /// Per-lane densities with which `sample` produces `wo` from its smooth lobes.
    fn pdf_lanes(&self, wi: Vec3, wo: Vec3) -> Spectrum<N>;
    /// `uc` picks a lobe (by weight), `u` the direction within it.
    fn sample(&self, wi: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample<N>>;
    /// True if some lobe is not a Dirac lobe: emitter sampling can then contribute.
    fn has_smooth(&self) -> bool;
    /// True if sampling depends on wavelength (the integrator then tracks per-lane densities).
    fn dispersive(&self) -> bool;
    /// True if every lobe is a Dirac lobe or a microfacet lobe no rougher than `max_alpha`
    /// (what caustic light tracing follows).
    fn glossy(&self, max_alpha: f32) -> bool;
}

impl<const N: usize> BsdfLike<N> for Diffuse<N> {
    #[inline]
    fn eval(&self, wi: Vec3, wo: Vec3) -> Spectrum<N> {
        Diffuse::eval(self, wi, wo)
    }

    #[inline]
    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        Diffuse::pdf(self, wi, wo)
    }

    #[inline]
    fn pdf_lanes(&self, wi: Vec3, wo: Vec3) -> Spectrum<N> {
        Spectrum::splat(Diffuse::pdf(self, wi, wo))
    }

    #[inline]
    fn sample(&self, wi: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample<N>> {
        Diffuse::sample(self, wi, uc, u)
    }

    #[inline]
    fn has_smooth(&self) -> bool {
        true
    }

    #[inline]
    fn dispersive(&self) -> bool {
        false
    }

    #[inline]
    fn glossy(&self, _max_alpha: f32) -> bool {
        false
    }
}

impl<const N: usize> BsdfLike<N> for Bsdf<'_, N> {
    #[inline]
    fn eval(&self, wi: Vec3, wo: Vec3) -> Spectrum<N> {
        match self {
            Bsdf::Diffuse(d) => d.eval(wi, wo),
            Bsdf::Mixture(m) => m.eval(wi, wo),
        }
    }

    #[inline]
    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        match self {
            Bsdf::Diffuse(d) => d.pdf(wi, wo),
            Bsdf::Mixture(m) => m.pdf(wi, wo),
        }
    }

    #[inline]
    fn pdf_lanes(&self, wi: Vec3, wo: Vec3) -> Spectrum<N> {
        match self {
            Bsdf::Diffuse(d) => d.pdf_lanes(wi, wo),
            Bsdf::Mixture(m) => m.pdf_lanes(wi, wo),
        }
    }

    #[inline]
    fn sample(&self, wi: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample<N>> {
        match self {
            Bsdf::Diffuse(d) => d.sample(wi, uc, u),
            Bsdf::Mixture(m) => m.sample(wi, uc, u),
        }
    }

    #[inline]
    fn has_smooth(&self) -> bool {
        match self {
            Bsdf::Diffuse(d) => d.has_smooth(),
            Bsdf::Mixture(m) => m.has_smooth(),
        }
    }

    #[inline]
    fn dispersive(&self) -> bool {
        match self {
            Bsdf::Diffuse(d) => d.dispersive(),
            Bsdf::Mixture(m) => m.dispersive(),
        }
    }

    #[inline]
    fn glossy(&self, max_alpha: f32) -> bool {
        match self {
            Bsdf::Diffuse(d) => d.glossy(max_alpha),
            Bsdf::Mixture(m) => m.glossy(max_alpha),
        }
    }
}

// Out of line, so that the integrator's copy of its per-hit code for mixtures stays small.
impl<const N: usize> BsdfLike<N> for Mixture<'_, N> {
    #[inline(never)]
    fn eval(&self, wi: Vec3, wo: Vec3) -> Spectrum<N> {
        let mut f = Spectrum::zero();
        for (lobe, w, flip) in &self.lobes[..] {
            f += lobe.eval(mirror(wi, *flip), mirror(wo, *flip)) * *w;
        }
        f
    }

    #[inline(never)]
    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        self.lobes[..]
            .iter()
            .map(|(l, w, flip)| w * l.pdf(mirror(wi, *flip), mirror(wo, *flip)))
            .sum()
    }

    #[inline(never)]
    fn pdf_lanes(&self, wi: Vec3, wo: Vec3) -> Spectrum<N> {
        let mut p = Spectrum::zero();
        for (lobe, w, flip) in &self.lobes[..] {
            p += lobe.pdf_lanes(mirror(wi, *flip), mirror(wo, *flip)) * *w;
        }
        p
    }

    #[inline(never)]
    fn sample(&self, wi: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample<N>> {
        // No lobe (every weight 0 or NaN): nothing to sample, rather than an index past the end.
        if self.lobes.is_empty() {
            return None;
        }
        if self.lobes.len() == 1 {
            let (lobe, w, flip) = &self.lobes[0];
            let mut s = lobe.sample(mirror(wi, *flip), uc, u)?;
            s.wo = mirror(s.wo, *flip);
            // A lone lobe of weight < 1 (a mask's inner part when fully opaque is weight 1).
            s.weight *= *w;
            return Some(s);
        }
        // Choose lobe i with probability w_i (the weights sum to 1), reusing uc.
        let mut acc = 0.0;
        let mut chosen = self.lobes.len() - 1;
        let mut uc_lobe = uc;
        for (i, (_, w, _)) in self.lobes[..].iter().enumerate() {
            if uc < acc + w || i == self.lobes.len() - 1 {
                chosen = i;
                uc_lobe = ((uc - acc) / w).clamp(0.0, 1.0 - f32::EPSILON);
                break;
            }
            acc += w;
        }
        let (lobe, w, flip) = &self.lobes[chosen];
        let mut s = lobe.sample(mirror(wi, *flip), uc_lobe, u)?;
        s.wo = mirror(s.wo, *flip);
        if s.delta {
            // A Dirac lobe: the mixture's probability of this exact direction is w·p.
            s.pdf *= w;
            s.pdf_lanes *= *w;
            return Some(s);
        }
        // A smooth direction: every smooth lobe could have produced it.
        let pdf = self.pdf(wi, s.wo);
        if pdf <= 0.0 {
            return None;
        }
        let f = self.eval(wi, s.wo);
        Some(BsdfSample {
            pdf,
            pdf_lanes: self.pdf_lanes(wi, s.wo),
            weight: f / pdf,
            ..s
        })
    }

    #[inline]
    fn has_smooth(&self) -> bool {
        self.lobes[..].iter().any(|(l, _, _)| l.has_smooth())
    }

    #[inline]
    fn dispersive(&self) -> bool {
        self.lobes[..].iter().any(|(l, _, _)| l.dispersive())
    }

    #[inline]
    fn glossy(&self, max_alpha: f32) -> bool {
        !self.lobes.is_empty() && self.lobes[..].iter().all(|(l, _, _)| l.glossy(max_alpha))
    }
}
