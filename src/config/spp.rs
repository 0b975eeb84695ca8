//! `sampler.spp` (and a dataset's `outputs.spp`): a fixed sample count, or adaptive sampling
//! to a target relative standard error per pixel.
//!
//! ```ron
//! spp: 256
//! spp: Adaptive(rel_error: 0.01, min: 16, max: 4096)          // target: Y, floor: 0.001
//! spp: Adaptive(rel_error: 0.02, min: 32, max: 1024, target: Bands)
//! ```

pub use crate::integrator::adaptive::{AdaptiveSpp, ErrorTarget};
use crate::sampler::{SamplerKind, SOBOL_MAX_SPP};
use serde::de::value::MapAccessDeserializer;
use serde::de::{self, MapAccess, Visitor};
use serde::{Deserialize, Serialize};
use std::fmt;

/// Samples per pixel.
///
/// Read with `deserialize_any` (as `SensorField`): serde's untagged enums would lose RON's
/// error positions inside `Adaptive(...)`. RON hands a named struct over as a map, without its
/// name, so `(rel_error: 0.01, ...)` reads as `Adaptive(...)` too (it is also what the
/// untagged serialisation below writes).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Spp {
    Fixed(u32),
    Adaptive(AdaptiveSpp),
}

impl Spp {
    /// The samples per pixel of `settings`, as the scene wrote them.
    pub fn of(settings: &crate::integrator::RenderSettings) -> Spp {
        match settings.adaptive {
            Some(a) => Spp::Adaptive(a),
            None => Spp::Fixed(settings.spp),
        }
    }

    /// What is wrong with it for `kind`, as (field under `spp`, message); None if fine.
    pub fn problem(&self, kind: SamplerKind) -> Option<(&'static str, String)> {
        let sobol = kind == SamplerKind::Sobol;
        let sobol_max = format!(
            "the Sobol sampler (the default) supports at most {SOBOL_MAX_SPP} spp; for more, \
             set `sampler: (kind: Independent)` or pass `--sampler independent`"
        );
        match *self {
            Spp::Fixed(0) => Some(("", "spp must be at least 1".into())),
            Spp::Fixed(n) if sobol && n > SOBOL_MAX_SPP => Some(("", sobol_max)),
            Spp::Fixed(_) => None,
            Spp::Adaptive(a) => {
                if !(a.rel_error.is_finite() && a.rel_error > 0.0) {
                    Some((
                        ".rel_error",
                        "rel_error must be a finite number > 0, such as 0.01".into(),
                    ))
                } else if a.min < 2 {
                    Some((
                        ".min",
                        "min must be at least 2 (the pilot batch measures a variance)".into(),
                    ))
                } else if a.max < a.min {
                    Some((
                        ".max",
                        format!("max ({}) must be at least min ({})", a.max, a.min),
                    ))
                } else if sobol && a.max > SOBOL_MAX_SPP {
                    Some((".max", sobol_max))
                } else if !(a.floor.is_finite() && a.floor > 0.0) {
                    Some((
                        ".floor",
                        "floor must be a finite number > 0, such as 0.001".into(),
                    ))
                } else {
                    None
                }
            }
        }
    }

    /// The most samples a pixel's estimate takes.
    pub fn max(&self) -> u32 {
        match *self {
            Spp::Fixed(n) => n,
            Spp::Adaptive(a) => a.max,
        }
    }

    pub fn adaptive(&self) -> Option<AdaptiveSpp> {
        match *self {
            Spp::Fixed(_) => None,
            Spp::Adaptive(a) => Some(a),
        }
    }
}

impl fmt::Display for Spp {
    /// As a scene writes it (the EXR header's `prism:spp`).
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        match self {
            Spp::Fixed(n) => write!(f, "{n}"),
            Spp::Adaptive(a) => write!(
                f,
                "Adaptive(rel_error: {}, min: {}, max: {}, target: {:?}, floor: {})",
                a.rel_error, a.min, a.max, a.target, a.floor
            ),
        }
    }
}

impl<'de> Deserialize<'de> for Spp {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(SppVisitor)
    }
}

struct SppVisitor;

impl<'de> Visitor<'de> for SppVisitor {
    type Value = Spp;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(
            f,
            "a sample count such as 64, or Adaptive(rel_error: 0.01, min: 16, max: 4096)"
        )
    }

    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Spp, E> {
        u32::try_from(v)
            .map(Spp::Fixed)
            .map_err(|_| E::custom(format!("spp {v} is too large (at most {})", u32::MAX)))
    }

    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Spp, E> {
        match u64::try_from(v) {
            Ok(v) => self.visit_u64(v),
            Err(_) => Err(E::custom(format!("spp must be at least 1, not {v}"))),
        }
    }

    /// `spp: 1.5`: the words the parser gives any integer field a fraction (config/parse.rs).
    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Spp, E> {
        Err(E::custom(format!(
            "expected an integer, got {v}; spp counts samples: write a whole number, e.g. 64, \
             or Adaptive(rel_error: 0.01, min: 16, max: 4096)"
        )))
    }

    fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<Spp, A::Error> {
        AdaptiveSpp::deserialize(MapAccessDeserializer::new(map)).map(Spp::Adaptive)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(s: &str) -> Result<Spp, ron::error::SpannedError> {
        ron::from_str(s)
    }

    #[test]
    fn reads_both_forms() {
        assert_eq!(parse("64").unwrap(), Spp::Fixed(64));
        let a = parse("Adaptive(rel_error: 0.01, min: 16, max: 4096)").unwrap();
        assert_eq!(
            a,
            Spp::Adaptive(AdaptiveSpp {
                rel_error: 0.01,
                min: 16,
                max: 4096,
                target: ErrorTarget::Y,
                floor: 1e-3
            })
        );
        let b = parse("Adaptive(rel_error: 0.05, min: 4, max: 8, target: Bands, floor: 0.5)");
        assert_eq!(b.unwrap().adaptive().unwrap().target, ErrorTarget::Bands);
    }

    /// A typo in a field is an error at its place, never a silent default.
    #[test]
    fn refuses_unknown_fields_and_bad_values() {
        let e = parse("Adaptive(rel_eror: 0.01, min: 16, max: 64)").unwrap_err();
        assert!(e.to_string().contains("rel_eror"), "{e}");
        assert!(parse("-3").is_err());
        assert!(parse("\"64\"").is_err());
        let a = |s| parse(s).unwrap().problem(SamplerKind::Sobol).map(|p| p.0);
        assert_eq!(
            a("Adaptive(rel_error: 0, min: 16, max: 64)"),
            Some(".rel_error")
        );
        assert_eq!(a("Adaptive(rel_error: 0.1, min: 1, max: 64)"), Some(".min"));
        assert_eq!(a("Adaptive(rel_error: 0.1, min: 16, max: 8)"), Some(".max"));
        assert_eq!(
            a("Adaptive(rel_error: 0.1, min: 16, max: 99999)"),
            Some(".max")
        );
        assert_eq!(a("0"), Some(""));
        assert_eq!(a("Adaptive(rel_error: 0.1, min: 2, max: 2)"), None);
    }

    /// A scene's `sampler.spp` and a dataset config's `outputs.spp` read both forms.
    #[test]
    fn scene_and_dataset_configs_take_both_forms() {
        use crate::dataset::config::DatasetConfig;
        let p = std::path::Path::new("x.ron");
        let adaptive = "Adaptive(rel_error: 0.01, min: 16, max: 4096)";
        let scene = |spp: &str| crate::config::parse_str(&format!("(sampler: (spp: {spp}))"), p);
        assert_eq!(scene("32").unwrap().sampler.spp, Spp::Fixed(32));
        assert_eq!(scene(adaptive).unwrap().sampler.spp.max(), 4096);
        let e = scene("Adaptive(rel_error: 0.01, min: 16)").unwrap_err();
        assert!(e.to_string().contains("max"), "{e}");
        let data = |spp: &str| {
            let text = format!("(scene: \"s.ron\", frames: 1, outputs: (spp: {spp}))");
            DatasetConfig::parse(&text, p).unwrap().outputs.spp.unwrap()
        };
        assert_eq!(data("32"), Spp::Fixed(32));
        assert_eq!(data(adaptive).adaptive().unwrap().min, 16);
    }

    /// The RON a dataset export writes reads back as the same value.
    #[test]
    fn round_trips() {
        for s in [
            Spp::Fixed(7),
            parse("Adaptive(rel_error: 0.01, min: 16, max: 4096)").unwrap(),
        ] {
            assert_eq!(parse(&ron::to_string(&s).unwrap()).unwrap(), s);
        }
    }
}
