//! One leaf BSDF at a hit (`BsdfLobe`, which each BSDF's file implements) and the `Lobe` enum
//! that dispatches to it, generated from the list in `bsdf/mod.rs` (`for_each_bsdf!`): a new
//! BSDF adds no arm here.

use super::*;
use crate::spectrum::Spectrum;
use glam::{Vec2, Vec3};

/// What a leaf BSDF at a hit answers, at the path's wavelengths; directions in the local shading
/// frame. The defaults are those of a smooth lobe whose sampling does not depend on wavelength.
pub trait BsdfLobe<const N: usize> {
    /// f(wi, wo) · |cos θ_o| per lane (0 for Dirac lobes).
    fn eval(&self, wi: Vec3, wo: Vec3) -> Spectrum<N>;
    /// Hero density of sampling `wo` (0 for Dirac lobes).
    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32;
    /// Per-lane densities of sampling `wo`.
    #[inline]
    fn pdf_lanes(&self, wi: Vec3, wo: Vec3) -> Spectrum<N> {
        Spectrum::splat(self.pdf(wi, wo))
    }
    fn sample(&self, wi: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample<N>>;
    /// True if the lobe has a non-Dirac part (emitter sampling can reach it).
    #[inline]
    fn has_smooth(&self) -> bool {
        true
    }
    /// True if the lobe is a Dirac lobe or a microfacet lobe no rougher than `max_alpha`.
    fn glossy(&self, max_alpha: f32) -> bool;
    /// True if the lobe's sampling depends on wavelength.
    #[inline]
    fn dispersive(&self) -> bool {
        false
    }
}

/// Generates `Lobe` from the BSDF list: one variant per BSDF (its lobe type) and `Null`.
macro_rules! lobe_enum {
    ($($(#[$doc:meta])* $V:ident($L:ty, $P:ty) {$($schema:tt)*} [$($roles:tt)*]),* $(,)?) => {
        /// One leaf BSDF at a hit, at the path's wavelengths.
        #[derive(Clone, Copy, Debug)]
        pub enum Lobe<'a, const N: usize> {
            $($V($L),)*
            /// Passes light straight through, unchanged (the transparent part of a `mask`).
            Null,
        }

        impl<const N: usize> Lobe<'_, N> {
            /// f(wi, wo) · |cos θ_o| per lane (0 for Dirac lobes).
            #[inline]
            pub(super) fn eval(&self, wi: Vec3, wo: Vec3) -> Spectrum<N> {
                match self {
                    $(Lobe::$V(b) => BsdfLobe::eval(b, wi, wo),)*
                    Lobe::Null => Spectrum::zero(),
                }
            }

            /// Hero density of sampling `wo` (0 for Dirac lobes).
            #[inline]
            pub(super) fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
                match self {
                    $(Lobe::$V(b) => BsdfLobe::pdf(b, wi, wo),)*
                    Lobe::Null => 0.0,
                }
            }

            /// Per-lane densities of sampling `wo`.
            #[inline]
            pub(super) fn pdf_lanes(&self, wi: Vec3, wo: Vec3) -> Spectrum<N> {
                match self {
                    $(Lobe::$V(b) => BsdfLobe::pdf_lanes(b, wi, wo),)*
                    Lobe::Null => Spectrum::zero(),
                }
            }

            #[inline]
            pub(super) fn sample(&self, wi: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample<N>> {
                match self {
                    $(Lobe::$V(b) => BsdfLobe::sample(b, wi, uc, u),)*
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
            pub(super) fn has_smooth(&self) -> bool {
                match self {
                    $(Lobe::$V(b) => BsdfLobe::has_smooth(b),)*
                    Lobe::Null => false,
                }
            }

            /// True if the lobe is a Dirac lobe or a microfacet lobe no rougher than
            /// `max_alpha`.
            #[inline]
            pub(super) fn glossy(&self, max_alpha: f32) -> bool {
                match self {
                    $(Lobe::$V(b) => BsdfLobe::glossy(b, max_alpha),)*
                    Lobe::Null => true,
                }
            }

            /// True if the lobe's sampling depends on wavelength.
            #[inline]
            pub(super) fn dispersive(&self) -> bool {
                match self {
                    $(Lobe::$V(b) => BsdfLobe::dispersive(b),)*
                    Lobe::Null => false,
                }
            }
        }
    };
}

for_each_bsdf!(lobe_enum);

impl<'a, const N: usize> Lobe<'a, N> {
    pub(super) fn push(self, weight: f32, flip: bool, out: &mut Mixture<'a, N>) {
        if weight > 0.0 && !out.lobes.is_full() {
            out.lobes.push((self, weight, flip));
        }
    }
}
