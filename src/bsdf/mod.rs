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

/// The BSDFs, one entry each: `Variant(its lobe at a hit, its parameters in the scene)`, then its
/// fields in the scene file (RON) and the roles of those fields. `Lobe` (lobe.rs) and `Material`
/// (material.rs) are generated from this list, and so is config's `MaterialConfig` (its schema:
/// the doc comment, fields and serde attributes are written here as config expands them), so a
/// new BSDF is its own file (the two types, implementing `BsdfLobe` and `BsdfParams`), its `mod`
/// and `pub use` lines and its entry here, plus its arm in the loader (load/materials.rs).
///
/// Field types name the scene file's kinds, which config resolves: `Spectrum`, `Float` (a number
/// or a texture) and `Ior` (a number, a name or a spectrum); `f32`, `bool`, `String` and
/// `Distribution` are plain values. The serde defaults name config/material.rs's default values.
/// Roles, each optional (what a dataset variation edits): `base:` the base reflectance (a
/// `Spectrum`), `roughness: alpha(cleared…)` the isotropic α (an `f32` or an `Option<Float>`;
/// the anisotropic fields in parentheses are cleared when it is set), `int_ior:` the interior
/// index (an `Ior`).
macro_rules! for_each_bsdf {
    ($then:ident) => {
        $then! {
            /// Lambertian, one-sided (Mitsuba's `diffuse`). `reflectance` default `Constant(0.5)`.
            Diffuse(Diffuse<N>, DiffuseParams) {
                #[serde(default = "half_grey")]
                reflectance: Spectrum,
            } [base: reflectance,],
            // Conductors.
            /// A smooth metal (Mitsuba's `conductor`): `material` names a metal (`"Au"`, `"Cu"`, …;
            /// default `"none"`, a perfect mirror), or `eta` and `k` give its index of refraction
            /// (defaults 0 and 1, the same mirror), not both; `specular_reflectance` default 1.
            Conductor(Conductor<N>, ConductorParams) {
                #[serde(default)]
                material: Option<String>,
                #[serde(default)]
                eta: Option<Spectrum>,
                #[serde(default)]
                k: Option<Spectrum>,
                #[serde(default = "full_reflectance")]
                specular_reflectance: Spectrum,
            } [base: specular_reflectance,],
            /// A rough metal (Mitsuba's `roughconductor`): `distribution` `Beckmann` (default) or `Ggx`;
            /// `alpha` (default 0.1) or both `alpha_u` and `alpha_v`, each in (0, 1], a number or a
            /// texture; `material`, `eta`, `k`, `specular_reflectance` as for `Conductor`.
            RoughConductor(RoughConductor<N>, RoughConductorParams) {
                #[serde(default)]
                distribution: Distribution,
                #[serde(default)]
                alpha: Option<Float>,
                #[serde(default)]
                alpha_u: Option<Float>,
                #[serde(default)]
                alpha_v: Option<Float>,
                #[serde(default)]
                material: Option<String>,
                #[serde(default)]
                eta: Option<Spectrum>,
                #[serde(default)]
                k: Option<Spectrum>,
                #[serde(default = "full_reflectance")]
                specular_reflectance: Spectrum,
            } [base: specular_reflectance, roughness: alpha(alpha_u, alpha_v),],
            // Dielectrics.
            /// A smooth interface between two dielectrics (Mitsuba's `dielectric`): glass, water.
            /// `int_ior` default `"bk7"` (1.5046), `ext_ior` default `"air"` (1.000277), the exterior
            /// being the side the normal points to; `specular_reflectance` and `specular_transmittance`
            /// (default `Constant(1)`) scale the two lobes and should stay 1 for physical realism.
            ///
            /// ```ron
            /// Dielectric(int_ior: Glass("SF11"), ext_ior: Named("air"))
            /// ```
            Dielectric(Dielectric<N>, DielectricParams) {
                #[serde(default = "bk7")]
                int_ior: Ior,
                #[serde(default = "air")]
                ext_ior: Ior,
                #[serde(default = "unit")]
                specular_reflectance: Spectrum,
                #[serde(default = "unit")]
                specular_transmittance: Spectrum,
            } [int_ior: int_ior,],
            /// A rough dielectric interface (Mitsuba's `roughdielectric`, Walter et al. 2007):
            /// `distribution` `Beckmann` (default) or `Ggx`; `alpha` (default 0.1) or both `alpha_u` and
            /// `alpha_v` (anisotropic); IORs and specular factors as `Dielectric`.
            ///
            /// ```ron
            /// RoughDielectric(distribution: Ggx, alpha: 0.05, int_ior: Glass("BK7"))
            /// ```
            RoughDielectric(RoughDielectric<N>, RoughDielectricParams) {
                #[serde(default)]
                distribution: Distribution,
                #[serde(default)]
                alpha: Option<Float>,
                #[serde(default)]
                alpha_u: Option<Float>,
                #[serde(default)]
                alpha_v: Option<Float>,
                #[serde(default = "bk7")]
                int_ior: Ior,
                #[serde(default = "air")]
                ext_ior: Ior,
                #[serde(default = "unit")]
                specular_reflectance: Spectrum,
                #[serde(default = "unit")]
                specular_transmittance: Spectrum,
            } [roughness: alpha(alpha_u, alpha_v), int_ior: int_ior,],
            /// An infinitely thin dielectric slab, e.g. a window pane modelled as one sheet
            /// (Mitsuba's `thindielectric`): specular reflection, undeflected transmission. Parameters
            /// as `Dielectric`.
            ///
            /// ```ron
            /// ThinDielectric(int_ior: Named("bk7"))
            /// ```
            ThinDielectric(ThinDielectric<N>, ThinDielectricParams) {
                #[serde(default = "bk7")]
                int_ior: Ior,
                #[serde(default = "air")]
                ext_ior: Ior,
                #[serde(default = "unit")]
                specular_reflectance: Spectrum,
                #[serde(default = "unit")]
                specular_transmittance: Spectrum,
            } [int_ior: int_ior,],
            // Plastics.
            /// A smooth dielectric coating over a diffuse base (Mitsuba's `plastic`).
            /// Defaults: diffuse_reflectance 0.5, specular_reflectance 1, int_ior `"polypropylene"`
            /// (1.49), ext_ior `"air"` (1.000277), nonlinear false. The indices are written as a
            /// dielectric's (a number or a name) but must not vary with wavelength, as in Mitsuba.
            Plastic(Plastic<N>, PlasticParams) {
                #[serde(default = "half_grey")]
                diffuse_reflectance: Spectrum,
                #[serde(default = "one_spectrum")]
                specular_reflectance: Spectrum,
                #[serde(default = "polypropylene")]
                int_ior: Ior,
                #[serde(default = "air")]
                ext_ior: Ior,
                #[serde(default)]
                nonlinear: bool,
            } [base: diffuse_reflectance, int_ior: int_ior,],
            /// A rough coating over a diffuse base (Mitsuba's `roughplastic`): isotropic `Beckmann`
            /// (default) or `Ggx` with roughness `alpha` (default 0.1); other defaults as `Plastic`.
            RoughPlastic(RoughPlastic<'a, N>, RoughPlasticParams) {
                #[serde(default)]
                distribution: Distribution,
                #[serde(default = "point_one")]
                alpha: f32,
                #[serde(default = "half_grey")]
                diffuse_reflectance: Spectrum,
                #[serde(default = "one_spectrum")]
                specular_reflectance: Spectrum,
                #[serde(default = "polypropylene")]
                int_ior: Ior,
                #[serde(default = "air")]
                ext_ior: Ior,
                #[serde(default)]
                nonlinear: bool,
            } [base: diffuse_reflectance, roughness: alpha(), int_ior: int_ior,],
            /// The glTF 2.0 metallic-roughness BRDF (the specification's Appendix B, with
            /// KHR_materials_ior, _specular and thin-walled _transmission); what glTF materials become.
            /// Defaults are glTF's: base_color 1, metallic 1, roughness 1 (α = roughness², GGX),
            /// ior 1.5, specular 1, specular_color 1, transmission 0.
            ///
            /// ```ron
            /// Principled(base_color: Rgb(0.8, 0.1, 0.1), metallic: 0, roughness: 0.4)
            /// ```
            Principled(Principled<N>, Box<PrincipledParams>) {
                #[serde(default = "one_spectrum")]
                base_color: Spectrum,
                #[serde(default = "one_float")]
                metallic: Float,
                #[serde(default = "one_float")]
                roughness: Float,
                #[serde(default = "gltf_ior")]
                ior: f32,
                #[serde(default = "one")]
                specular: f32,
                #[serde(default = "one_spectrum")]
                specular_color: Spectrum,
                #[serde(default = "zero_float")]
                transmission: Float,
            } [],
        }
    };
}
pub(crate) use for_each_bsdf;

mod describe;
mod hit;
mod lobe;
mod material;
mod mixture;

pub mod conductor;
pub mod dielectric;
pub mod diffuse;
pub mod fresnel;
pub mod microfacet;
pub mod plastic;
pub mod principled;
pub mod roughconductor;
pub mod roughdielectric;
pub mod roughplastic;
pub mod thindielectric;

pub use conductor::{Conductor, ConductorParams};
pub use describe::Param;
pub use dielectric::{Dielectric, DielectricParams};
pub use diffuse::{Diffuse, DiffuseParams};
pub use hit::{Bsdf, BsdfLike, BsdfSample};
pub use lobe::{BsdfLobe, Lobe};
pub use material::{BsdfParams, Material};
pub use mixture::Mixture;
pub use plastic::{Plastic, PlasticParams};
pub use principled::{Principled, PrincipledParams, SpecularColorTexture};
pub use roughconductor::{RoughConductor, RoughConductorParams};
pub use roughdielectric::{RoughDielectric, RoughDielectricParams};
pub use roughplastic::{RoughPlastic, RoughPlasticParams};
pub use thindielectric::{ThinDielectric, ThinDielectricParams};

/// Most leaf lobes one material may combine (blends and masks of blends…).
pub const MAX_LOBES: usize = 4;
