//! A blackbody emission spectrum: Planck's law, tabulated once per curve for the render.
//!
//! Why a table: Planck's law in f64 (a fifth power, a division and `expm1` per wavelength) was
//! 5% of the instructions of the kept-back benchmark scenes and 9% of a tabletop dataset frame,
//! evaluated per lane, once per path. A 0.2 nm table over 300–1100 nm (4001 samples, 16 KB)
//! evaluates four lanes at a time through `Dense::eval_lanes`; where the curve holds at least
//! 1e-3 of its peak there, linear interpolation is within 8e-6 of the law, and within 2e-6 of
//! the peak everywhere, at 500–40000 K (`tests::table_follows_the_law`). Outside the table the
//! law itself is evaluated.

use super::curve::Dense;
use crate::math::portable;

// Planck's law constants (CODATA 2018, exact in SI).
const PLANCK_H: f64 = 6.626_070_15e-34;
const LIGHT_C: f64 = 299_792_458.0;
const BOLTZMANN_K: f64 = 1.380_649e-23;

/// The table's first and last wavelengths (nm) and its samples per nm.
const TABLE_LO: f32 = 300.0;
const TABLE_HI: f32 = 1100.0;
const PER_NM: u32 = 5;

/// Blackbody spectral radiance in W m⁻² sr⁻¹ nm⁻¹ at `lambda` nm and `kelvin` K.
pub fn planck(lambda: f32, kelvin: f32) -> f32 {
    let l = lambda as f64 * 1e-9;
    let t = kelvin as f64;
    let radiance_per_m = 2.0 * PLANCK_H * LIGHT_C * LIGHT_C
        / (l.powi(5) * (portable::exp_m1(PLANCK_H * LIGHT_C / (l * BOLTZMANN_K * t))));
    (radiance_per_m * 1e-9) as f32
}

/// `scale` × Planck's law at `kelvin`, with its table.
#[derive(Clone, Debug, PartialEq)]
pub struct Blackbody {
    // Private: the table is made from them.
    kelvin: f32,
    scale: f32,
    /// `scale · planck` every 1/PER_NM nm over [TABLE_LO, TABLE_HI].
    table: Dense,
}

impl Blackbody {
    pub fn new(kelvin: f32, scale: f32) -> Blackbody {
        let n = ((TABLE_HI - TABLE_LO) as u32 * PER_NM) as usize;
        let values = (0..=n)
            .map(|i| scale * planck(TABLE_LO + i as f32 / PER_NM as f32, kelvin))
            .collect();
        Blackbody {
            kelvin,
            scale,
            table: Dense::new(TABLE_LO, PER_NM as f32, values),
        }
    }

    /// The curve times `k` (the table's samples scaled, so `eval_one` and `eval_lanes` keep
    /// agreeing bit for bit).
    pub fn scaled(mut self, k: f32) -> Blackbody {
        self.scale *= k;
        self.table.scale_values(k);
        self
    }

    #[inline]
    pub fn eval_one(&self, lambda: f32) -> f32 {
        if (TABLE_LO..=TABLE_HI).contains(&lambda) {
            self.table.eval(lambda)
        } else {
            self.scale * planck(lambda, self.kelvin)
        }
    }

    /// `eval_one` at every lane: the table four lanes at a time when every lane is in it (the
    /// same bits: `Dense::eval_lanes` is `Dense::eval` per lane).
    #[inline]
    pub fn eval_lanes<const N: usize>(&self, lambda: &[f32; N]) -> [f32; N] {
        if lambda.iter().all(|l| (TABLE_LO..=TABLE_HI).contains(l)) {
            self.table.eval_lanes(lambda)
        } else {
            std::array::from_fn(|i| self.eval_one(lambda[i]))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Tolerances: over 300–1100 nm, wherever the law is at least 1e-3 of its peak there, the
    /// table is within 1e-5 of it (measured 7.6e-6 at worst, 2500 K), and within 3e-6 of the
    /// peak everywhere (measured 1.7e-6, 500 K); outside the table it is the law exactly.
    #[test]
    fn table_follows_the_law() {
        for kelvin in [
            500.0, 1000.0, 1500.0, 2500.0, 4000.0, 6504.0, 20000.0, 40000.0,
        ] {
            let b = Blackbody::new(kelvin, 1.0);
            let probes: Vec<f32> = (0..=80_000).map(|i| 300.0 + i as f32 * 0.01).collect();
            let law: Vec<f32> = probes.iter().map(|&l| planck(l, kelvin)).collect();
            let peak = law.iter().cloned().fold(0.0f32, f32::max);
            for (&l, &p) in probes.iter().zip(&law) {
                let t = b.eval_one(l);
                assert!(
                    (t - p).abs() <= 3e-6 * peak,
                    "{kelvin} K, {l} nm: {t} vs {p}"
                );
                if p >= 1e-3 * peak {
                    assert!(
                        (t / p - 1.0).abs() <= 1e-5,
                        "{kelvin} K, {l} nm: {t} vs {p}"
                    );
                }
            }
            for l in [200.0, 299.9, 1100.1, 2500.0] {
                assert_eq!(
                    b.eval_one(l).to_bits(),
                    planck(l, kelvin).to_bits(),
                    "{l} nm"
                );
            }
        }
    }

    /// Lanes give `eval_one`'s bits, all in the table or some outside it.
    #[test]
    fn lanes_are_eval_one() {
        let b = Blackbody::new(3200.0, 0.37).scaled(2.5);
        let mut rng = crate::math::rng::Pcg32::new(5, 11);
        for outside in [false, true] {
            for _ in 0..2_000 {
                let mut l: [f32; 8] = std::array::from_fn(|_| 360.0 + 470.0 * rng.next_f32());
                if outside {
                    l[3] = 1500.0 * rng.next_f32();
                }
                let v = b.eval_lanes(&l);
                for k in 0..8 {
                    assert_eq!(v[k].to_bits(), b.eval_one(l[k]).to_bits(), "{}", l[k]);
                }
            }
        }
    }
}
