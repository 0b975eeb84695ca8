//! RGB -> spectrum uplifting for reflectances (Jakob & Hanika 2019): a linear RGB colour maps to
//! the smooth spectrum `s(λ) = S(c0 λ² + c1 λ + c2)`, `S(x) = 1/2 + x / (2 sqrt(1 + x²))`, whose
//! colour under D65 is that RGB colour. The coefficients come from a 64³ × 3 table per input
//! space (linear sRGB, Rec. 2020, Display P3, ACEScg: `gamut.rs`) fitted by `build.rs` (see
//! `rgb2spec_fit.rs`) and interpolated trilinearly here. A table is decoded on first use, so a
//! scene that uses only sRGB never decodes the others.

use super::gamut::Gamut;
use super::rgb2spec_fit::CoeffTable;
use std::sync::OnceLock;

macro_rules! table_bytes {
    ($file:literal) => {
        include_bytes!(concat!(env!("OUT_DIR"), "/", $file))
    };
}

/// The tables' bytes, in the order of `gamut::ALL_GAMUTS` (names as `Gamut::table_file`).
static TABLE_BYTES: [&[u8]; 4] = [
    table_bytes!("srgb_sigmoid.bin"),
    table_bytes!("rec2020_sigmoid.bin"),
    table_bytes!("display_p3_sigmoid.bin"),
    table_bytes!("acescg_sigmoid.bin"),
];

fn table(gamut: Gamut) -> &'static CoeffTable {
    static TABLES: [OnceLock<CoeffTable>; 4] = [const { OnceLock::new() }; 4];
    let i = gamut as usize;
    TABLES[i].get_or_init(|| {
        CoeffTable::from_bytes(TABLE_BYTES[i])
            .unwrap_or_else(|e| panic!("embedded {} sigmoid table: {e}", gamut.name()))
    })
}

/// A reflectance spectrum `S(c0 λ² + c1 λ + c2)`, λ in nm; values lie in [0, 1]. The colour is
/// matched over 360–830 nm; beyond, the polynomial just extends (still within [0, 1]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sigmoid {
    c: [f32; 3],
}

impl Sigmoid {
    /// s = 0 everywhere. The sigmoid reaches 0 only as its argument tends to -∞, so black is
    /// c2 = -∞, which [`Sigmoid::eval`] maps to exactly 0.
    pub const BLACK: Sigmoid = Sigmoid {
        c: [0.0, 0.0, f32::NEG_INFINITY],
    };
    /// s = 1 everywhere (c2 = +∞).
    pub const WHITE: Sigmoid = Sigmoid {
        c: [0.0, 0.0, f32::INFINITY],
    };

    /// The value at `lambda_nm`.
    #[inline]
    pub fn eval(&self, lambda_nm: f32) -> f32 {
        let x = (self.c[0] * lambda_nm + self.c[1]) * lambda_nm + self.c[2];
        // Clamping (branch-free min/max) keeps x² finite in f32, so ±∞ (black/white) and huge
        // arguments give exactly 0 or 1 instead of ∞/∞ = NaN; beyond |x| of a few thousand the
        // ratio below already rounds to ±1, so the clamp changes nothing else.
        let x = x.clamp(-1e18, 1e18);
        0.5 + 0.5 * x / (1.0 + x * x).sqrt()
    }

    /// The values at every lane, four lanes at a time: the same IEEE operations as
    /// [`Sigmoid::eval`], so the same bits (tested), with one SIMD square root and division
    /// per four lanes instead of four scalar ones (those were 8% of a Cornell render).
    #[inline]
    pub fn eval_lanes<const N: usize>(&self, lambda: &[f32; N]) -> [f32; N] {
        use wide::f32x4;
        let [c0, c1, c2] = self.c.map(f32x4::splat);
        let (half, one) = (f32x4::splat(0.5), f32x4::splat(1.0));
        let (lo, hi) = (f32x4::splat(-1e18), f32x4::splat(1e18));
        let mut out = [0.0; N];
        let mut chunks = out.chunks_exact_mut(4);
        for (o, l) in (&mut chunks).zip(lambda.chunks_exact(4)) {
            let l = f32x4::from([l[0], l[1], l[2], l[3]]);
            let x = ((c0 * l + c1) * l + c2).max(lo).min(hi);
            o.copy_from_slice(&(half + half * x / (one + x * x).sqrt()).to_array());
        }
        let done = N - chunks.into_remainder().len();
        for k in done..N {
            out[k] = self.eval(lambda[k]);
        }
        out
    }

    /// The coefficients (c0, c1, c2) of the polynomial in λ (nm); c2 = ∓∞ for black/white.
    pub fn coefficients(&self) -> [f32; 3] {
        self.c
    }
}

/// The reflectance spectrum of the linear sRGB colour `rgb`, whose components must lie in
/// [0, 1] (clamping is the caller's job: reflectances outside that range have no bounded
/// spectrum; checked in debug builds). Exact black and white give [`Sigmoid::BLACK`] and
/// [`Sigmoid::WHITE`].
pub fn fetch(rgb: [f32; 3]) -> Sigmoid {
    fetch_in(Gamut::Srgb, rgb)
}

/// [`fetch`] for a colour of the RGB space `gamut` (its table; components in [0, 1]).
pub fn fetch_in(gamut: Gamut, rgb: [f32; 3]) -> Sigmoid {
    debug_assert!(
        rgb.iter().all(|v| (0.0..=1.0).contains(v)),
        "rgb {rgb:?} outside [0, 1]"
    );
    let t = table(gamut);
    let res = t.res;
    let i = if rgb[0] >= rgb[1] && rgb[0] >= rgb[2] {
        0
    } else if rgb[1] >= rgb[2] {
        1
    } else {
        2
    };
    let z = rgb[i];
    // The table has no usable black entry (x, y = 0/0), and its z = 1 entries only approach white.
    if z <= 0.0 {
        return Sigmoid::BLACK;
    }
    if rgb.iter().all(|&v| v >= 1.0) {
        return Sigmoid::WHITE;
    }
    let scale = (res - 1) as f32 / z;
    let x = rgb[(i + 1) % 3] * scale;
    let y = rgb[(i + 2) % 3] * scale;
    let xi = (x as usize).min(res - 2);
    let yi = (y as usize).min(res - 2);
    let zi = t
        .scale
        .partition_point(|&s| s <= z)
        .saturating_sub(1)
        .min(res - 2);
    let (tx, ty) = (x - xi as f32, y - yi as f32);
    let tz = (z - t.scale[zi]) / (t.scale[zi + 1] - t.scale[zi]);
    let at = |dz: usize, dy: usize, dx: usize| {
        let k = (((i * res + zi + dz) * res + yi + dy) * res + xi + dx) * 3;
        [t.data[k], t.data[k + 1], t.data[k + 2]]
    };
    let lerp = |a: [f32; 3], b: [f32; 3], w: f32| [0, 1, 2].map(|k| a[k] + w * (b[k] - a[k]));
    let plane = |dz: usize| {
        let row0 = lerp(at(dz, 0, 0), at(dz, 0, 1), tx);
        let row1 = lerp(at(dz, 1, 0), at(dz, 1, 1), tx);
        lerp(row0, row1, ty)
    };
    Sigmoid {
        c: lerp(plane(0), plane(1), tz),
    }
}

#[cfg(test)]
mod tests {
    use super::super::rgb2spec_fit::{mat_vec, FitData, XYZ_TO_SRGB};
    use super::*;

    #[test]
    fn simd_lanes_match_scalar_bit_for_bit() {
        let mut sigmoids = vec![Sigmoid::BLACK, Sigmoid::WHITE];
        for r in [0.0f32, 0.05, 0.3, 0.7, 1.0] {
            for g in [0.0f32, 0.2, 0.9] {
                for b in [0.0f32, 0.5, 1.0] {
                    sigmoids.push(fetch([r, g, b]));
                }
            }
        }
        let lambda: [f32; 8] = [300.0, 360.5, 412.25, 500.0, 555.5, 700.125, 830.0, 1100.0];
        for s in &sigmoids {
            let scalar = lambda.map(|l| s.eval(l));
            assert_eq!(
                s.eval_lanes(&lambda).map(f32::to_bits),
                scalar.map(f32::to_bits)
            );
            let five: [f32; 5] = lambda[..5].try_into().unwrap();
            assert_eq!(s.eval_lanes(&five), five.map(|l| s.eval(l)));
            assert_eq!(s.eval_lanes(&[lambda[3]]), [s.eval(lambda[3])]);
        }
    }

    fn data() -> FitData {
        FitData::from_texts(
            include_str!("../../spectra/cmf/CIE1931_2deg.txt"),
            include_str!("../../spectra/illuminants/D65.txt"),
        )
        .unwrap()
    }

    /// Fixed-seed 64-bit LCG (Knuth's MMIX constants); the top 24 bits give a uniform [0, 1).
    struct Lcg(u64);
    impl Lcg {
        fn next(&mut self) -> f32 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (self.0 >> 40) as f32 / (1u64 << 24) as f32
        }
    }

    fn srgb_of(d: &FitData, s: Sigmoid) -> [f64; 3] {
        mat_vec(&XYZ_TO_SRGB, d.xyz(|l| s.eval(l as f32) as f64))
    }

    #[test]
    fn round_trip_random_colours() {
        // Every table entry is fitted to < 1e-3 (nearly all to < 1e-5); what remains is the
        // trilinear interpolation of coefficients between 64³ entries, in which the spectrum
        // (hence its colour) is not linear. Typically that is ~2e-4 (here at most ~5e-4); it
        // peaks near the white corner (one component 1, the others above ~0.9), where the
        // coefficients grow fast: up to ~1e-2 there, as in Mitsuba's table of the same design.
        let d = data();
        let mut rng = Lcg(0x5eed);
        let mut worst = 0.0f64;
        for _ in 0..200 {
            let rgb = [rng.next(), rng.next(), rng.next()];
            let got = srgb_of(&d, fetch(rgb));
            for k in 0..3 {
                worst = worst.max((got[k] - rgb[k] as f64).abs());
            }
        }
        assert!(worst < 2e-3, "worst sRGB error {worst}");
    }

    #[test]
    fn black_white_grey() {
        let (black, white, grey) = (fetch([0.0; 3]), fetch([1.0; 3]), fetch([0.5; 3]));
        for l in 360..=830 {
            let l = l as f32;
            assert_eq!(black.eval(l), 0.0);
            assert_eq!(white.eval(l), 1.0);
            assert!(
                (grey.eval(l) - 0.5).abs() < 1e-3,
                "grey at {l}: {}",
                grey.eval(l)
            );
        }
    }

    #[test]
    fn values_are_bounded() {
        let mut rng = Lcg(7);
        let corners = [
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 1.0, 0.0],
            [1e-7, 0.0, 0.0],
        ];
        let random = (0..500).map(|_| [rng.next(), rng.next(), rng.next()]);
        for rgb in corners.into_iter().chain(random) {
            let s = fetch(rgb);
            for l in (300..=1100).step_by(5) {
                let v = s.eval(l as f32);
                assert!((0.0..=1.0).contains(&v), "{rgb:?} at {l}: {v}");
            }
        }
    }

    #[test]
    fn fit_one_converges() {
        let d = data();
        for rgb in [
            [0.5, 0.2, 0.1],
            [0.1, 0.6, 0.3],
            [0.05, 0.05, 0.4],
            [0.9, 0.9, 0.2],
            [0.18; 3],
        ] {
            let fit = d.fit_one(rgb, [0.0; 3]);
            // Recompute ΔE independently of the solver's own bookkeeping.
            let c = FitData::to_nm(fit.coeffs);
            let s = |l: f64| {
                let x = (c[0] * l + c[1]) * l + c[2];
                0.5 + 0.5 * x / (1.0 + x * x).sqrt()
            };
            let lab = d.lab(d.xyz(s));
            let target = d.lab(mat_vec(&super::super::rgb2spec_fit::SRGB_TO_XYZ, rgb));
            let de = (0..3)
                .map(|k| (lab[k] - target[k]).powi(2))
                .sum::<f64>()
                .sqrt();
            assert!(de < 1e-3, "{rgb:?}: ΔE {de} (solver says {})", fit.residual);
        }
    }

    #[test]
    fn table_bytes_round_trip() {
        let t = table(Gamut::Srgb);
        assert_eq!(CoeffTable::from_bytes(&t.to_bytes()).as_ref(), Ok(t));
        let mut bad = t.to_bytes();
        bad[8] ^= 1; // res no longer matches the size
        assert!(CoeffTable::from_bytes(&bad).is_err());
        assert!(CoeffTable::from_bytes(b"NOTATABL\x40\0\0\0").is_err());
    }
}
