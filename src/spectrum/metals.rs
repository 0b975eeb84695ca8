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

/// The other data sets of the metal `name` (`Au` → `Au_mcpeak`, …) whose data cover
/// `lo`–`hi` nm, as "`Au_mcpeak` (300–1700 nm)", for the warning of a metal whose data end
/// inside the render range.
pub fn covering_alternatives(name: &str, lo: f32, hi: f32) -> Vec<String> {
    let symbol = name.split('_').next().unwrap_or(name);
    metal_names()
        .into_iter()
        .filter(|m| !m.eq_ignore_ascii_case(name))
        .filter(|m| {
            m.split('_')
                .next()
                .is_some_and(|s| s.eq_ignore_ascii_case(symbol))
        })
        .filter_map(|m| {
            let (eta, k) = named_metal(m)?;
            let (a, b) = eta.support()?;
            let (ka, kb) = k.support()?;
            (a.max(ka) <= lo && b.min(kb) >= hi).then(|| format!("`{m}` ({a}–{b} nm)"))
        })
        .collect()
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

    /// McPeak et al. 2015 (ACS Photonics 2, 326), via the refractiveindex.info database: at
    /// 1000 nm, a tabulated wavelength, the curves give the published values (to f32 rounding,
    /// 1e-6 relative); at 1005 nm, between two samples, the linear interpolation of the two
    /// neighbours (the tabulation's own resolution: 10 nm for Au, Ag, Cu, 5 nm for Al).
    #[test]
    fn nir_metals_match_their_source() {
        // (name, eta and k at 1000 nm, at the next tabulated wavelength, its wavelength)
        let published = [
            (
                "Au_mcpeak",
                (0.132311724, 6.904527963),
                (0.133907614, 6.978318655),
                1010.0,
            ),
            (
                "Ag_mcpeak",
                (0.088025428, 7.254153877),
                (0.090501937, 7.335202151),
                1010.0,
            ),
            (
                "Cu_mcpeak",
                (0.123314675, 6.744939326),
                (0.123500553, 6.819402641),
                1010.0,
            ),
            (
                "Al_mcpeak",
                (1.126639087, 8.511598888),
                (1.114680776, 8.571960874),
                1005.0,
            ),
        ];
        for (name, at1000, next, next_nm) in published {
            let (eta, k) = named_metal(name).unwrap();
            let close = |a: f32, b: f64| ((a as f64 - b) / b).abs() < 1e-6;
            assert!(close(eta.eval_one(1000.0), at1000.0), "{name} eta");
            assert!(close(k.eval_one(1000.0), at1000.1), "{name} k");
            let mid = 0.5 * (1000.0 + next_nm);
            assert!(
                close(eta.eval_one(mid), 0.5 * (at1000.0 + next.0)),
                "{name} eta at {mid}"
            );
            assert!(
                close(k.eval_one(mid), 0.5 * (at1000.1 + next.1)),
                "{name} k at {mid}"
            );
            let (a, b) = eta.support().unwrap();
            assert!(a <= 300.0 && b >= 1700.0, "{name}: {a}–{b}");
        }
        assert_eq!(named_metal("au_MCPEAK"), named_metal("Au_mcpeak"));
        assert_eq!(
            covering_alternatives("Au", 300.0, 1100.0),
            ["`Au_mcpeak` (300–1700 nm)"]
        );
        assert_eq!(covering_alternatives("Al", 300.0, 1100.0).len(), 1);
        assert!(covering_alternatives("W", 300.0, 1100.0).is_empty());
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
