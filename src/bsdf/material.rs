//! The scene's materials: a tree of BSDFs whose parameters are spectra or textures, and the
//! building of a hit's `Bsdf` from it.

use super::microfacet::{Distribution, Microfacet};
use super::{
    roughplastic, Bsdf, ConductorParams, Dielectric, Diffuse, Lobe, Mixture, Plastic,
    PrincipledParams, RoughConductor, RoughDielectric, RoughPlastic, ThinDielectric,
};
use crate::interaction::SurfaceInteraction;
use crate::spectrum::{RelativeIor, Spectrum, Wavelengths};
use crate::texture::{FloatTexture, SpectralTexture};
use glam::Vec3;

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
                transmittance: specular_transmittance.eval(si, wl),
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
                transmittance: specular_transmittance.eval(si, wl),
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
                let a = unit_weight(opacity.eval(si));
                inner.add_lobes(si, cos_i, wl, weight * a, flip, out);
                Lobe::Null.push(weight * (1.0 - a), false, out);
                return;
            }
            Material::Conductor(p) => Lobe::Conductor(p.at(si.uv, wl)),
            Material::Principled(p) => Lobe::Principled(p.at(si, wl)),
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
