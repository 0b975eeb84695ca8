//! Named metals: measured complex indices of refraction η + iκ (`spectra/metals/`), by chemical
//! symbol, for the `material` parameter of conductors (Mitsuba 3's presets).

use super::curve::Curve;
use super::data::FILES;
use super::table;

/// Mitsuba's names for data sets that prism stores under the plain symbol (the files are the
/// same, so a Mitsuba scene that names them ports unchanged).
const ALIASES: &[(&str, &str)] = &[
    ("Be_palik", "Be"),
    ("Hg_palik", "Hg"),
    ("Ir_palik", "Ir"),
    ("Mo_palik", "Mo"),
    ("Nb_palik", "Nb"),
    ("Ni_palik", "Ni"),
    ("Rh_palik", "Rh"),
    ("Ta_palik", "Ta"),
    ("V_palik", "V"),
];

/// Every metal `named_metal` knows, by symbol, sorted (aliases not included).
pub fn metal_names() -> Vec<&'static str> {
    let mut names: Vec<&str> = FILES
        .iter()
        .filter_map(|(k, _)| k.strip_prefix("metals/"))
        .collect();
    names.sort_unstable();
    names
}

/// The (η, κ) curves of a metal, by chemical symbol in any case ("Au", "au"), or by one of
/// Mitsuba's `<X>_palik` names. None for an unknown name; callers list `metal_names()`.
pub fn named_metal(name: &str) -> Option<(Curve, Curve)> {
    let name = ALIASES
        .iter()
        .find(|(a, _)| a.eq_ignore_ascii_case(name))
        .map_or(name, |(_, k)| *k);
    let symbol = metal_names()
        .into_iter()
        .find(|m| m.eq_ignore_ascii_case(name))?;
    let text = super::data::embedded(&format!("metals/{symbol}"))?;
    let t = table::parse(text).expect("embedded metal tables parse");
    let column = |c: &str| {
        let v = t.column(c).expect("metal tables have eta and k columns");
        Curve::from_samples(&t.wavelengths, v)
    };
    Some((column("eta"), column("k")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_cases_and_aliases() {
        let names = metal_names();
        for m in ["Ag", "Al", "Au", "Cr", "Cu", "Fe", "Ni", "Pt", "Ti", "W"] {
            assert!(names.contains(&m), "{m} missing from {names:?}");
        }
        let (eta, k) = named_metal("Au").unwrap();
        assert_eq!(named_metal("au"), Some((eta.clone(), k.clone())));
        assert_eq!(named_metal("AU"), Some((eta, k)));
        assert_eq!(named_metal("Ni_palik"), named_metal("ni"));
        assert!(named_metal("Xx").is_none());
        assert!(
            named_metal("none").is_none(),
            "`none` is the config's mirror, not data"
        );
    }

    /// Every metal's data cover the CIE range, with finite η ≥ 0 and κ > 0 throughout.
    #[test]
    fn every_metal_covers_the_visible_range() {
        for name in metal_names() {
            let (eta, k) = named_metal(name).unwrap();
            for c in [&eta, &k] {
                let (a, b) = c.support().unwrap();
                assert!(a <= 360.0 && b >= 830.0, "{name}: data cover {a}–{b} nm");
            }
            let (lo, _) = eta.min_max(360.0, 830.0);
            let (klo, _) = k.min_max(360.0, 830.0);
            assert!(lo >= 0.0 && klo > 0.0, "{name}: eta ≥ {lo}, k ≥ {klo}");
        }
    }

    fn normal_reflectance(name: &str, nm: f32) -> f32 {
        let (eta, k) = named_metal(name).unwrap();
        crate::bsdf::fresnel::conductor(1.0, eta.eval_one(nm), k.eval_one(nm))
    }

    /// Gold's normal-incidence reflectance: high in the red, low in the blue (its colour). The
    /// literature gives ≈ 0.95 at 650 nm and ≈ 0.38 at 450 nm; our data (LuxPop, via Mitsuba)
    /// give 0.940 and 0.386. Measured sets differ by 1–2% here, hence ±0.02; a wrong column,
    /// unit (µm for nm) or interpolation moves these by more than 0.1.
    #[test]
    fn gold_and_silver_reflectance() {
        let red = normal_reflectance("Au", 650.0);
        let blue = normal_reflectance("Au", 450.0);
        assert!((red - 0.95).abs() < 0.02, "Au at 650 nm: {red}");
        assert!((blue - 0.38).abs() < 0.02, "Au at 450 nm: {blue}");
        // Silver is white and bright: above 0.9 over 450–700 nm (our data's minimum: 0.918 at
        // 450 nm), checked every nm.
        for nm in 450..=700 {
            let r = normal_reflectance("Ag", nm as f32);
            assert!(r > 0.9, "Ag at {nm} nm: {r}");
        }
    }
}
