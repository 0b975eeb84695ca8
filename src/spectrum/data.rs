//! The spectral data files of `spectra/`, embedded at build time, and named spectra.

use super::curve::Curve;
use super::table;

include!(concat!(env!("OUT_DIR"), "/spectra_files.rs"));

/// The text of an embedded data file, by its path under `spectra/` without `.txt`
/// (e.g. `illuminants/D65`).
pub fn embedded(key: &str) -> Option<&'static str> {
    FILES.iter().find(|(k, _)| *k == key).map(|(_, text)| *text)
}

/// Names accepted for the older CIE illuminant spellings.
const ALIASES: &[(&str, &str)] = &[
    ("F1", "FL1"),
    ("F2", "FL2"),
    ("F3", "FL3"),
    ("F4", "FL4"),
    ("F5", "FL5"),
    ("F6", "FL6"),
    ("F7", "FL7"),
    ("F8", "FL8"),
    ("F9", "FL9"),
    ("F10", "FL10"),
    ("F11", "FL11"),
    ("F12", "FL12"),
];

/// Every name `named_illuminant` accepts, in a stable order.
pub fn illuminant_names() -> Vec<&'static str> {
    let mut names: Vec<&str> = FILES
        .iter()
        .filter_map(|(k, _)| k.strip_prefix("illuminants/"))
        .collect();
    names.extend(ALIASES.iter().map(|(a, _)| *a));
    names.sort_by(|a, b| natural_cmp(a, b));
    names
}

fn natural_cmp(a: &str, b: &str) -> std::cmp::Ordering {
    // Compare runs of digits as numbers and everything else as text: F2 < F10, FL3.2 < FL3.10.
    fn chunks(s: &str) -> Vec<(String, u64)> {
        let mut out = Vec::new();
        let mut rest = s;
        while !rest.is_empty() {
            let t = rest
                .find(|c: char| c.is_ascii_digit())
                .unwrap_or(rest.len());
            let (text, tail) = rest.split_at(t);
            let d = tail
                .find(|c: char| !c.is_ascii_digit())
                .unwrap_or(tail.len());
            let (digits, tail) = tail.split_at(d);
            out.push((text.to_string(), digits.parse().unwrap_or(0)));
            rest = tail;
        }
        out
    }
    chunks(a).cmp(&chunks(b))
}

/// A named CIE illuminant, normalised to unit luminance (∫ S ȳ dλ / ∫ ȳ dλ = 1, as Mitsuba's
/// `d65`), so `Named("D65")` as an emitter's radiance is a white of luminance 1 W m⁻² sr⁻¹ nm⁻¹.
/// Returns None for an unknown name; callers list `illuminant_names()` in the error.
pub fn named_illuminant(name: &str) -> Option<Curve> {
    let key = ALIASES
        .iter()
        .find(|(a, _)| *a == name)
        .map_or(name, |(_, k)| *k);
    let text = embedded(&format!("illuminants/{key}"))?;
    let t = table::parse(text).expect("embedded illuminant tables parse");
    let curve = Curve::from_samples(&t.wavelengths, &t.values[0]);
    let y = curve.luminance();
    Some(curve.scaled(1.0 / y))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn required_illuminants_exist_and_are_normalised() {
        let names = illuminant_names();
        for n in [
            "A", "D50", "D55", "D65", "D75", "E", "F1", "F12", "FL11", "LED-B1",
        ] {
            assert!(names.contains(&n), "{n} missing from {names:?}");
            let c = named_illuminant(n).unwrap();
            assert!((c.luminance() - 1.0).abs() < 1e-4, "{n}");
        }
        assert!(named_illuminant("D66").is_none());
        let d65 = named_illuminant("D65").unwrap();
        // Mitsuba 3's d65 at 560 nm: 1.010127 (its normalisation uses its 5 nm CIE table;
        // ours the 1 nm table: they agree to ~0.1%).
        assert!(
            (d65.eval_one(560.0) - 1.010_127).abs() < 2e-3,
            "{}",
            d65.eval_one(560.0)
        );
    }
}
