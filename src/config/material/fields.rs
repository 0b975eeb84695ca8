//! What each material's fields are, for the readers that edit or visit them without matching
//! on the kinds: a dataset's reflectance, roughness and IOR variations, the rewrite of every
//! file path in an exported frame, and the Python module's parameter listing. Generated from the
//! BSDF list (bsdf/mod.rs), whose roles say which field is which; the inner nodes are written
//! out here (a `Twosided` answers for its front).

use super::MaterialConfig;
use crate::bsdf::for_each_bsdf;
use crate::bsdf::microfacet::Distribution;
use crate::config::{FloatConfig, IorConfig, SpectrumConfig};

/// A field of a material that holds a spectrum, a scalar parameter or an index.
pub enum Field<'a> {
    Spectrum(&'a mut SpectrumConfig),
    Float(&'a mut FloatConfig),
    Ior(&'a mut IorConfig),
}

/// A material's roughness α as its config says it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Roughness<'a> {
    /// A plain number (`RoughPlastic`'s `alpha`).
    Value(f32),
    /// A number or a texture.
    Float(&'a FloatConfig),
    /// No isotropic α: the anisotropic pair, either possibly absent.
    Anisotropic(Option<&'a FloatConfig>, Option<&'a FloatConfig>),
}

/// A field's kind, by its type: which `Field` it is, if any.
trait Visit {
    fn visit(&mut self, _f: &mut impl FnMut(Field)) {}
}

impl Visit for SpectrumConfig {
    fn visit(&mut self, f: &mut impl FnMut(Field)) {
        f(Field::Spectrum(self))
    }
}

impl Visit for FloatConfig {
    fn visit(&mut self, f: &mut impl FnMut(Field)) {
        f(Field::Float(self))
    }
}

impl Visit for IorConfig {
    fn visit(&mut self, f: &mut impl FnMut(Field)) {
        f(Field::Ior(self))
    }
}

impl<T: Visit> Visit for Option<T> {
    fn visit(&mut self, f: &mut impl FnMut(Field)) {
        if let Some(x) = self {
            x.visit(f)
        }
    }
}

// Plain values: no spectrum, texture or index to visit.
impl Visit for f32 {}
impl Visit for bool {}
impl Visit for String {}
impl Visit for Distribution {}

/// A roughness field: an `f32` or an optional number-or-texture.
trait Alpha {
    fn set(&mut self, a: f32);
    /// Its value; `aniso` are the anisotropic fields, read when it is absent.
    fn get<'a>(&'a self, aniso: &[&'a Option<FloatConfig>]) -> Roughness<'a>;
}

impl Alpha for f32 {
    fn set(&mut self, a: f32) {
        *self = a;
    }
    fn get<'a>(&'a self, _aniso: &[&'a Option<FloatConfig>]) -> Roughness<'a> {
        Roughness::Value(*self)
    }
}

impl Alpha for Option<FloatConfig> {
    fn set(&mut self, a: f32) {
        *self = Some(FloatConfig::Value(a));
    }
    fn get<'a>(&'a self, aniso: &[&'a Option<FloatConfig>]) -> Roughness<'a> {
        match (self, aniso) {
            (Some(a), _) => Roughness::Float(a),
            (None, [u, v]) => Roughness::Anisotropic(u.as_ref(), v.as_ref()),
            (None, _) => Roughness::Anisotropic(None, None),
        }
    }
}

/// `$V` as a string if the role after it is present (drives a repetition by that role).
macro_rules! name_if {
    ($V:ident $($role:tt)*) => {
        stringify!($V)
    };
}

/// Generates the field accessors from the BSDF list and its roles.
macro_rules! material_fields {
    ($($(#[$doc:meta])* $V:ident($L:ty, $P:ty) {
        $($(#[$fm:meta])* $field:ident: $fty:ty),* $(,)?
    } [
        $(base: $base:ident,)?
        $(roughness: $alpha:ident($($aniso:ident),*),)?
        $(int_ior: $ior:ident,)?
    ]),* $(,)?) => {
        impl MaterialConfig {
            /// The kinds `base_reflectance_mut`, `set_roughness` and `set_int_ior` find a field
            /// in, for error hints.
            pub const WITH_BASE_REFLECTANCE: &'static str =
                concat!($($(name_if!($V $base), ", ",)?)* "each also inside Twosided");
            pub const WITH_ROUGHNESS: &'static str =
                concat!($($(name_if!($V $alpha), ", ",)?)* "each also inside Twosided");
            pub const WITH_INT_IOR: &'static str =
                concat!($($(name_if!($V $ior), ", ",)?)* "each also inside Twosided");

            /// The base reflectance: a diffuse's `reflectance`, a plastic's
            /// `diffuse_reflectance`, a conductor's `specular_reflectance`; inside `Twosided`, its
            /// front's. None: it has none.
            pub fn base_reflectance_mut(&mut self) -> Option<&mut SpectrumConfig> {
                match self {
                    $($(MaterialConfig::$V { $base, .. } => Some($base),)?)*
                    MaterialConfig::Twosided { bsdf, .. } => bsdf.base_reflectance_mut(),
                    _ => None,
                }
            }

            /// Sets the (isotropic) roughness α, clearing an anisotropic pair; false if the
            /// material has none.
            pub fn set_roughness(&mut self, a: f32) -> bool {
                match self {
                    $($(MaterialConfig::$V { $alpha, $($aniso,)* .. } => {
                        Alpha::set($alpha, a);
                        $(*$aniso = None;)*
                        true
                    })?)*
                    MaterialConfig::Twosided { bsdf, .. } => bsdf.set_roughness(a),
                    _ => false,
                }
            }

            /// The roughness α as the config says it; None if the material has none.
            pub fn roughness(&self) -> Option<Roughness<'_>> {
                match self {
                    $($(MaterialConfig::$V { $alpha, $($aniso,)* .. } => {
                        Some(Alpha::get($alpha, &[$($aniso),*]))
                    })?)*
                    MaterialConfig::Twosided { bsdf, .. } => bsdf.roughness(),
                    _ => None,
                }
            }

            /// Sets the interior index of refraction; false if the material has none.
            pub fn set_int_ior(&mut self, n: f32) -> bool {
                match self {
                    $($(MaterialConfig::$V { $ior, .. } => {
                        *$ior = IorConfig::Value(n);
                        true
                    })?)*
                    MaterialConfig::Twosided { bsdf, .. } => bsdf.set_int_ior(n),
                    _ => false,
                }
            }

            /// The interior index of refraction; None if the material has none.
            pub fn int_ior(&self) -> Option<&IorConfig> {
                match self {
                    $($(MaterialConfig::$V { $ior, .. } => Some($ior),)?)*
                    MaterialConfig::Twosided { bsdf, .. } => bsdf.int_ior(),
                    _ => None,
                }
            }

            /// Calls `f` on every spectrum, scalar and index field, nested materials' included.
            pub fn for_each_field(&mut self, f: &mut impl FnMut(Field)) {
                match self {
                    $(MaterialConfig::$V { $($field),* } => {
                        $(Visit::visit($field, f);)*
                    })*
                    MaterialConfig::Twosided { bsdf, back } => {
                        bsdf.for_each_field(f);
                        back.iter_mut().for_each(|b| b.for_each_field(f));
                    }
                    MaterialConfig::Blend {
                        weight,
                        bsdf0,
                        bsdf1,
                    } => {
                        f(Field::Float(weight));
                        bsdf0.for_each_field(f);
                        bsdf1.for_each_field(f);
                    }
                    MaterialConfig::Mask { opacity, bsdf } => {
                        f(Field::Float(opacity));
                        bsdf.for_each_field(f);
                    }
                }
            }
        }
    };
}

for_each_bsdf!(material_fields);
