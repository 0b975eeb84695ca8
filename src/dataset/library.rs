//! Measured reflectance sets a dataset draws materials from (`spectra/reflectances/`, exported
//! from colour-science by `tools/export_spectra.py`; sources in spectra/README.md).

use crate::config::SpectrumConfig;
use crate::spectrum::table::{self, Table};

/// (name in a dataset config, file contents).
const SETS: [(&str, &str); 2] = [
    (
        "colorchecker",
        include_str!("../../spectra/reflectances/colorchecker.txt"),
    ),
    (
        "cie1995_tcs",
        include_str!("../../spectra/reflectances/cie1995_tcs.txt"),
    ),
];

/// The names of the sets, for error messages.
pub fn names() -> Vec<&'static str> {
    SETS.iter().map(|s| s.0).collect()
}

/// The set called `name`, parsed.
pub fn set(name: &str) -> Option<Table> {
    let text = SETS.iter().find(|s| s.0 == name)?.1;
    Some(table::parse(text).expect("the embedded reflectance tables parse"))
}

/// Entry `column` of `t` as a tabulated spectrum over at least `range` nm: the measured data
/// (380–780 nm for the ColorChecker) with its end values held outside, as for the ColorChecker
/// test (tools/prism_tools/colorchecker.py; the CIE curves are < 0.2% of their peak there).
pub fn spectrum(t: &Table, column: usize, range: (f32, f32)) -> SpectrumConfig {
    let (wl, v) = (&t.wavelengths, &t.values[column]);
    let mut pairs = Vec::with_capacity(wl.len() + 2);
    if (range.0 as f64) < wl[0] {
        pairs.push((range.0, v[0] as f32));
    }
    pairs.extend(wl.iter().zip(v).map(|(&w, &x)| (w as f32, x as f32)));
    let last = *wl.last().expect("a table has rows");
    if (range.1 as f64) > last {
        pairs.push((range.1, *v.last().expect("a table has rows") as f32));
    }
    SpectrumConfig::Tabulated(pairs)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sets_load_with_their_patches() {
        let cc = set("colorchecker").unwrap();
        assert_eq!(cc.columns.len(), 24);
        assert_eq!(cc.columns[0], "dark_skin");
        let tcs = set("cie1995_tcs").unwrap();
        assert_eq!(tcs.columns.len(), 14);
        assert!(set("munsell").is_none());
        // Held ends: 360 nm takes the 380 nm value.
        let SpectrumConfig::Tabulated(p) = spectrum(&cc, 0, (360.0, 830.0)) else {
            panic!()
        };
        assert_eq!(p[0].0, 360.0);
        assert_eq!(p[0].1, p[1].1);
        assert_eq!(p.last().unwrap().0, 830.0);
    }
}
