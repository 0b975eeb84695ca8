//! The scene's materials: a tree of BSDFs whose parameters are spectra or textures, and the
//! building of a hit's `Bsdf` from it. The leaves are the BSDFs of the list in `bsdf/mod.rs`
//! (`for_each_bsdf!`), each answering through `BsdfParams` in its own file; the tree's inner
//! nodes (`twosided`, `blend`, `mask`) are written out here.

use super::*;
use crate::interaction::SurfaceInteraction;
use crate::spectrum::Wavelengths;
use crate::texture::{FloatTexture, TexPoint};
use glam::Vec3;

/// What a leaf material (one BSDF's parameters over the surface) answers. Each BSDF's file
/// implements it; `Material` dispatches to it.
pub trait BsdfParams {
    /// The lobe at hit `si`, at the path's wavelengths.
    fn lobe<'a, const N: usize>(
        &'a self,
        si: &SurfaceInteraction,
        wl: &Wavelengths<N>,
    ) -> Lobe<'a, N>;
    /// True if the lobe samples directions by wavelength (a dispersive index).
    #[inline]
    fn dispersive(&self) -> bool {
        false
    }
    /// True if the lobe can focus light into caustics: a Dirac lobe or a microfacet conductor
    /// or dielectric (glossy if smooth enough).
    fn focuses_light(&self) -> bool;
    /// ρ of the diffuse part at `uv` for the one wavelength of `wl`
    /// (`Material::diffuse_reflectance`); 0 for a BSDF without one.
    #[inline]
    fn diffuse_reflectance(&self, _uv: TexPoint, _wl: &Wavelengths<1>) -> f32 {
        0.0
    }
    /// Passes the parameters to `put` by Mitsuba 3's names; returns Mitsuba 3's plugin name.
    fn traverse<'a>(&'a self, put: &mut impl FnMut(&'static str, Param<'a>)) -> &'static str;
}

/// Generates `Material` from the BSDF list: one variant per BSDF (its parameters), the inner
/// nodes of the tree, and the dispatch of `BsdfParams` to the leaves (`leaf_*`; an inner node
/// is matched before them by every caller).
macro_rules! material_enum {
    ($($(#[$doc:meta])* $V:ident($L:ty, $P:ty) {$($schema:tt)*} [$($roles:tt)*]),* $(,)?) => {
        /// A material of the scene.
        #[derive(Clone, Debug, PartialEq)]
        pub enum Material {
            $($V($P),)*
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
        }

        impl Material {
            // Always: out of line it costs add_lobes a call per leaf (+0.16% instructions on
            // the materials scene).
            #[inline(always)]
            fn leaf_lobe<'a, const N: usize>(
                &'a self,
                si: &SurfaceInteraction,
                wl: &Wavelengths<N>,
            ) -> Lobe<'a, N> {
                match self {
                    $(Material::$V(p) => p.lobe(si, wl),)*
                    _ => unreachable!("an inner node is matched before its leaves"),
                }
            }

            #[inline]
            fn leaf_dispersive(&self) -> bool {
                match self {
                    $(Material::$V(p) => p.dispersive(),)*
                    _ => unreachable!("an inner node is matched before its leaves"),
                }
            }

            #[inline]
            fn leaf_focuses_light(&self) -> bool {
                match self {
                    $(Material::$V(p) => p.focuses_light(),)*
                    _ => unreachable!("an inner node is matched before its leaves"),
                }
            }

            #[inline]
            pub(super) fn leaf_diffuse_reflectance(&self, uv: TexPoint, wl: &Wavelengths<1>) -> f32 {
                match self {
                    $(Material::$V(p) => p.diffuse_reflectance(uv, wl),)*
                    _ => unreachable!("an inner node is matched before its leaves"),
                }
            }

            #[inline]
            pub(super) fn leaf_traverse<'a>(
                &'a self,
                put: &mut impl FnMut(&'static str, Param<'a>),
            ) -> &'static str {
                match self {
                    $(Material::$V(p) => p.traverse(put),)*
                    _ => unreachable!("an inner node is matched before its leaves"),
                }
            }
        }
    };
}

for_each_bsdf!(material_enum);

/// A boxed leaf (a large parameter set kept off the enum) answers as its contents.
impl<P: BsdfParams> BsdfParams for Box<P> {
    #[inline]
    fn lobe<'a, const N: usize>(
        &'a self,
        si: &SurfaceInteraction,
        wl: &Wavelengths<N>,
    ) -> Lobe<'a, N> {
        (**self).lobe(si, wl)
    }
    #[inline]
    fn dispersive(&self) -> bool {
        (**self).dispersive()
    }
    #[inline]
    fn focuses_light(&self) -> bool {
        (**self).focuses_light()
    }
    #[inline]
    fn diffuse_reflectance(&self, uv: TexPoint, wl: &Wavelengths<1>) -> f32 {
        (**self).diffuse_reflectance(uv, wl)
    }
    fn traverse<'a>(&'a self, put: &mut impl FnMut(&'static str, Param<'a>)) -> &'static str {
        (**self).traverse(put)
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
            leaf => leaf.leaf_dispersive(),
        }
    }

    /// True if some lobe of the material can focus light into caustics: a Dirac lobe (a
    /// mirror, a smooth interface or coating, a mask's pass-through) or a microfacet conductor
    /// or dielectric (glossy if smooth enough). The objects caustic light tracing aims at.
    pub fn focuses_light(&self) -> bool {
        match self {
            Material::Twosided { front, back } => front.focuses_light() || back.focuses_light(),
            Material::Blend { a, b, .. } => a.focuses_light() || b.focuses_light(),
            Material::Mask { .. } => true,
            leaf => leaf.leaf_focuses_light(),
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
        if let Material::Diffuse(d) = self {
            *out = Bsdf::Diffuse(d.at(si, wl));
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
            leaf => leaf.leaf_lobe(si, wl),
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
