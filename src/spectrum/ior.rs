//! Indices of refraction as functions of wavelength, evaluated per lane.
//!
//! Four forms: a constant (Mitsuba 3's named values, e.g. `water` = 1.333), the Sellmeier
//! equation n² = 1 + Σ Bᵢλ²/(λ² − Cᵢ) (λ in µm; the form glass catalogues publish), Cauchy's
//! n = A + B/λ² (λ in µm) and a tabulated curve. Named dispersive glasses (Schott N-BK7, N-SF11,
//! fused silica, …) are data in `spectra/glasses.txt`.

use super::{data, Curve, Spectrum, Wavelengths};

/// An index of refraction n(λ).
#[derive(Clone, Debug, PartialEq)]
pub enum Ior {
    Constant(f32),
    /// n² = 1 + Σᵢ bᵢ λ² / (λ² − cᵢ), λ in µm, cᵢ in µm².
    Sellmeier {
        b: [f32; 3],
        c: [f32; 3],
    },
    /// n = a + b / λ², λ in µm.
    Cauchy {
        a: f32,
        b: f32,
    },
    /// Tabulated (or any other) spectrum of n.
    Curve(Curve),
}

/// Mitsuba 3's named indices of refraction (`ior.h`; Hecht, *Optics*, at ~589 nm, 0–20 °C).
const NAMED: &[(&str, f32)] = &[
    ("vacuum", 1.0),
    ("helium", 1.000036),
    ("hydrogen", 1.000132),
    ("air", 1.000277),
    ("carbon dioxide", 1.00045),
    ("water", 1.3330),
    ("acetone", 1.36),
    ("ethanol", 1.361),
    ("carbon tetrachloride", 1.461),
    ("glycerol", 1.4729),
    ("benzene", 1.501),
    ("silicone oil", 1.52045),
    ("bromine", 1.661),
    ("water ice", 1.31),
    ("fused quartz", 1.458),
    ("pyrex", 1.470),
    ("acrylic glass", 1.49),
    ("polypropylene", 1.49),
    ("bk7", 1.5046),
    ("sodium chloride", 1.544),
    ("amber", 1.55),
    ("pet", 1.5750),
    ("diamond", 2.419),
];

/// Fraunhofer lines used for n_d and the Abbe number (nm): d (He), F (H), C (H).
pub const LINE_D: f32 = 587.5618;
pub const LINE_F: f32 = 486.1327;
pub const LINE_C: f32 = 656.2725;

impl Ior {
    /// One of Mitsuba 3's named constants, matched ignoring case (as Mitsuba does).
    pub fn named(name: &str) -> Option<Ior> {
        let lower = name.to_lowercase();
        NAMED
            .iter()
            .find(|(n, _)| *n == lower)
            .map(|&(_, v)| Ior::Constant(v))
    }

    /// The names `named` accepts, in Mitsuba's order.
    pub fn names() -> Vec<&'static str> {
        NAMED.iter().map(|(n, _)| *n).collect()
    }

    /// A dispersive glass of `spectra/glasses.txt`, matched ignoring case and punctuation; an
    /// `N-` prefix may be left out (`SF11` finds `N-SF11`, but `F2` is Schott's F2).
    pub fn glass(name: &str) -> Option<Ior> {
        let key = normalise(name);
        let glasses = glasses();
        let find = |k: &str| glasses.iter().find(|g| normalise(g.0) == k);
        find(&key)
            .or_else(|| find(&format!("n{key}")))
            .map(|&(_, b, c)| Ior::Sellmeier { b, c })
    }

    /// The names of the glasses `glass` accepts, as written in the data file.
    pub fn glass_names() -> Vec<&'static str> {
        glasses().into_iter().map(|g| g.0).collect()
    }

    /// n at `lambda` nm.
    #[inline]
    pub fn eval_one(&self, lambda: f32) -> f32 {
        match self {
            Ior::Constant(n) => *n,
            Ior::Sellmeier { b, c } => {
                let l2 = (lambda * 1e-3) * (lambda * 1e-3);
                let mut n2 = 1.0;
                for i in 0..3 {
                    n2 += b[i] * l2 / (l2 - c[i]);
                }
                n2.max(0.0).sqrt()
            }
            Ior::Cauchy { a, b } => {
                let l = lambda * 1e-3;
                a + b / (l * l)
            }
            Ior::Curve(c) => c.eval_one(lambda),
        }
    }

    /// n at every lane.
    #[inline]
    pub fn eval<const N: usize>(&self, wl: &Wavelengths<N>) -> Spectrum<N> {
        match self {
            Ior::Constant(n) => Spectrum::splat(*n),
            Ior::Curve(c) => c.eval(wl),
            _ => Spectrum::from_fn(|i| self.eval_one(wl.lambda[i])),
        }
    }

    /// True if n does not depend on wavelength.
    pub fn is_constant(&self) -> bool {
        match self {
            Ior::Constant(_) => true,
            Ior::Sellmeier { b, .. } => b.iter().all(|&v| v == 0.0),
            Ior::Cauchy { b, .. } => *b == 0.0,
            Ior::Curve(c) => c.is_constant(),
        }
    }

    /// Smallest and largest n over [lo, hi] nm, sampled every 0.25 nm (for validation; NaN
    /// propagates so a pole inside the range is caught).
    pub fn min_max(&self, lo: f32, hi: f32) -> (f32, f32) {
        let n = (((hi - lo) * 4.0).ceil() as usize).max(1);
        let mut out = (f32::INFINITY, f32::NEG_INFINITY);
        for i in 0..=n {
            let v = self.eval_one(lo + (hi - lo) * i as f32 / n as f32);
            if !v.is_finite() {
                return (v, v);
            }
            out = (out.0.min(v), out.1.max(v));
        }
        out
    }

    /// Wavelength-value pairs describing n over [lo, hi] nm, or None for a constant: a curve's
    /// own knots (Curve::tabulate), the analytic forms every 1 nm (Sellmeier and Cauchy indices
    /// change by < 1e-4 per nm in the visible, so linear interpolation between the samples is
    /// exact to ~1e-6).
    pub fn tabulate(&self, lo: f32, hi: f32) -> Option<(Vec<f32>, Vec<f32>)> {
        match self {
            _ if self.is_constant() => None,
            Ior::Curve(c) => c.tabulate(lo, hi),
            _ => {
                let n = (hi - lo).ceil() as usize;
                let nm: Vec<f32> = (0..=n).map(|i| (lo + i as f32).min(hi)).collect();
                let values = nm.iter().map(|&l| self.eval_one(l)).collect();
                Some((nm, values))
            }
        }
    }

    /// Abbe number V_d = (n_d − 1) / (n_F − n_C): low values disperse strongly.
    pub fn abbe_number(&self) -> f32 {
        (self.eval_one(LINE_D) - 1.0) / (self.eval_one(LINE_F) - self.eval_one(LINE_C))
    }
}

/// Lower-case letters and digits only.
fn normalise(s: &str) -> String {
    s.chars()
        .filter(|c| c.is_ascii_alphanumeric())
        .map(|c| c.to_ascii_lowercase())
        .collect()
}

type Glass = (&'static str, [f32; 3], [f32; 3]);

/// The rows of `spectra/glasses.txt` (checked by the unit tests, so a malformed row is a bug).
fn glasses() -> Vec<Glass> {
    let text = data::embedded("glasses").expect("spectra/glasses.txt is embedded");
    text.lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#') && !l.starts_with("name "))
        .map(|l| {
            let mut it = l.split_whitespace();
            let name = it.next().unwrap();
            let v: Vec<f32> = it
                .map(|x| x.parse().expect("glasses.txt: numbers"))
                .collect();
            assert_eq!(v.len(), 6, "glasses.txt: {name} needs B1 B2 B3 C1 C2 C3");
            (name, [v[0], v[1], v[2]], [v[3], v[4], v[5]])
        })
        .collect()
}

/// The relative index η = n_int / n_ext of an interface (the exterior is the side the shading
/// normal points to), as Mitsuba 3's dielectrics define it.
#[derive(Clone, Debug, PartialEq)]
pub struct RelativeIor {
    pub int: Ior,
    pub ext: Ior,
    /// Decided at load: η varies with wavelength unless both sides are constant.
    dispersive: bool,
}

impl RelativeIor {
    pub fn new(int: Ior, ext: Ior) -> Self {
        let dispersive = !(int.is_constant() && ext.is_constant());
        Self {
            int,
            ext,
            dispersive,
        }
    }

    /// η at every lane.
    #[inline]
    pub fn eta<const N: usize>(&self, wl: &Wavelengths<N>) -> Spectrum<N> {
        if self.dispersive {
            self.int.eval(wl) / self.ext.eval(wl)
        } else {
            Spectrum::splat(self.int.eval_one(wl.hero()) / self.ext.eval_one(wl.hero()))
        }
    }

    /// True if η depends on wavelength (refraction then sends each lane its own way).
    #[inline]
    pub fn dispersive(&self) -> bool {
        self.dispersive
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Catalogue n_d and V_d (the data file's comments). Tolerances: n_d to 2e-5 (catalogue
    /// values have 5 decimals; f32 evaluation adds < 1e-6), V_d to 0.05 (two decimals, and the
    /// difference n_F − n_C loses ~3 digits in f32).
    #[test]
    fn glasses_match_catalogue_indices_and_abbe_numbers() {
        let expect = [
            ("N-BK7", 1.51680, 64.17),
            ("N-BAF10", 1.67003, 47.11),
            ("F2", 1.62004, 36.37),
            ("N-F2", 1.62005, 36.43),
            ("N-SF11", 1.78472, 25.68),
            ("N-LASF9", 1.85025, 32.17),
            ("FusedSilica", 1.45846, 67.82),
        ];
        assert_eq!(Ior::glass_names().len(), expect.len());
        for (name, nd, vd) in expect {
            let g = Ior::glass(name).unwrap_or_else(|| panic!("{name} missing"));
            assert!(!g.is_constant());
            let n = g.eval_one(LINE_D);
            assert!((n - nd).abs() < 2e-5, "{name}: n_d {n} vs {nd}");
            let v = g.abbe_number();
            assert!((v - vd).abs() < 0.05, "{name}: V_d {v} vs {vd}");
        }
    }

    #[test]
    fn glass_names_resolve_loosely() {
        assert_eq!(Ior::glass("BK7"), Ior::glass("N-BK7"));
        assert_eq!(Ior::glass("sf11"), Ior::glass("N-SF11"));
        assert_eq!(Ior::glass("fused silica"), Ior::glass("FusedSilica"));
        // F2 and N-F2 are different glasses: the exact name wins.
        assert_ne!(Ior::glass("F2"), Ior::glass("N-F2"));
        assert!(Ior::glass("unobtainium").is_none());
    }

    /// Fused silica at other wavelengths (Malitson 1965 table): n(404.66 nm) = 1.46962,
    /// n(706.52 nm) = 1.45515; dispersion is normal (n falls with λ) over the visible.
    #[test]
    fn sellmeier_across_the_visible() {
        let s = Ior::glass("FusedSilica").unwrap();
        assert!((s.eval_one(404.66) - 1.46962).abs() < 5e-5);
        assert!((s.eval_one(706.52) - 1.45515).abs() < 5e-5);
        let sf11 = Ior::glass("SF11").unwrap();
        let mut prev = f32::INFINITY;
        for l in (360..=830).step_by(10) {
            let n = sf11.eval_one(l as f32);
            assert!(n < prev && n > 1.7, "{l} nm: {n}");
            prev = n;
        }
    }

    #[test]
    fn named_constants_are_mitsubas() {
        assert_eq!(Ior::named("bk7"), Some(Ior::Constant(1.5046)));
        assert_eq!(Ior::named("Water"), Some(Ior::Constant(1.333)));
        assert_eq!(Ior::named("air"), Some(Ior::Constant(1.000277)));
        assert_eq!(Ior::named("diamond"), Some(Ior::Constant(2.419)));
        assert_eq!(Ior::named("fused quartz"), Some(Ior::Constant(1.458)));
        assert!(Ior::named("kryptonite").is_none());
        assert_eq!(Ior::names().len(), 23);
    }

    #[test]
    fn cauchy_and_relative_index() {
        // BK7's common two-term Cauchy fit: A = 1.5046, B = 0.00420 µm².
        let c = Ior::Cauchy {
            a: 1.5046,
            b: 0.0042,
        };
        assert!((c.eval_one(500.0) - (1.5046 + 0.0042 / 0.25)).abs() < 1e-6);
        assert!(!c.is_constant());
        let wl = Wavelengths {
            lambda: [450.0, 550.0, 650.0, 750.0],
            pdf: [1.0; 4],
        };
        let fixed = RelativeIor::new(Ior::Constant(1.5), Ior::Constant(1.25));
        assert!(!fixed.dispersive());
        assert_eq!(fixed.eta(&wl).0, [1.2; 4]);
        let glass = RelativeIor::new(Ior::glass("BK7").unwrap(), Ior::named("air").unwrap());
        assert!(glass.dispersive());
        let eta = glass.eta(&wl);
        assert!(eta[0] > eta[1] && eta[1] > eta[2] && eta[2] > eta[3]);
        assert!((eta[1] - Ior::glass("BK7").unwrap().eval_one(550.0) / 1.000277).abs() < 1e-6);
    }
}
