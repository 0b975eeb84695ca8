//! Response curves that share one wavelength grid (a camera's three curves, filters sampled
//! alike), read once per lane: the grid position and interpolation weight are found once and
//! the curves' samples sit side by side, instead of one table lookup per curve and lane (three
//! lookups a lane were 17% of a tabletop frame's render loop with a Nikon D810 sensor).
//!
//! **Bits.** Each curve's value is `Dense::eval`'s: the same start and step give the same
//! position x, index and weight, and the same a + t·(b − a) per curve.

use super::bands::{Response, Shape};
use crate::spectrum::Curve;

#[derive(Clone, Debug, PartialEq)]
pub(super) struct ResponseGrid {
    start: f32,
    inv_step: f32,
    /// The last sample's position (samples − 1).
    last: f32,
    /// Samples per curve.
    len: usize,
    /// Sample k of curve r at `values[k * curves + r]`.
    values: Vec<f32>,
    curves: usize,
}

impl ResponseGrid {
    /// The grid of `responses` if every one is a tabulated curve (`Curve::Dense`, at least two
    /// samples) on the same start, step and length; else None (each is then read on its own).
    pub(super) fn of(responses: &[Response]) -> Option<ResponseGrid> {
        let tables: Vec<_> = responses
            .iter()
            .map(|r| match &r.shape {
                Shape::Curve(Curve::Dense(d)) => Some(d.grid()),
                _ => None,
            })
            .collect::<Option<_>>()?;
        let &(start, inv_step, first) = tables.first()?;
        let len = first.len();
        let same = |&(s, i, v): &(f32, f32, &[f32])| {
            s.to_bits() == start.to_bits() && i.to_bits() == inv_step.to_bits() && v.len() == len
        };
        if len < 2 || !tables.iter().all(same) {
            return None;
        }
        let curves = tables.len();
        let values = (0..len * curves)
            .map(|n| tables[n % curves].2[n / curves])
            .collect();
        Some(ResponseGrid {
            start,
            inv_step,
            last: (len - 1) as f32,
            len,
            values,
            curves,
        })
    }

    /// The samples around `lambda` (each curve's sample below, then each curve's sample
    /// above) and the weight of the upper ones; None off the grid (where every curve is 0).
    #[inline(always)]
    pub(super) fn at(&self, lambda: f32) -> Option<(&[f32], &[f32], f32)> {
        let x = (lambda - self.start) * self.inv_step;
        if !(0.0..=self.last).contains(&x) {
            return None;
        }
        let i = (x as i32 as usize).min(self.len - 2);
        let t = x - i as f32;
        let (a, b) = self.values[i * self.curves..(i + 2) * self.curves].split_at(self.curves);
        Some((a, b, t))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn curve(start: f64, step: f64, values: Vec<f64>) -> Response {
        let nm: Vec<f64> = (0..values.len()).map(|k| start + k as f64 * step).collect();
        let shape = Shape::Curve(Curve::from_samples(&nm, &values));
        assert!(matches!(shape, Shape::Curve(Curve::Dense(_))));
        Response { shape, scale: 1.0 }
    }

    #[test]
    fn each_curve_reads_as_its_own_table_bit_for_bit() {
        let mut seed = 7u64;
        let mut rnd = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 40) as f64 / (1u64 << 24) as f64
        };
        let rs: Vec<Response> = (0..3)
            .map(|_| curve(380.0, 5.0, (0..69).map(|_| rnd()).collect()))
            .collect();
        let grid = ResponseGrid::of(&rs).expect("one grid");
        let mut ls: Vec<f32> = (0..40_000).map(|k| 370.0 + k as f32 * 0.0093).collect();
        ls.extend([380.0, 720.0, 380f32.next_down(), 720f32.next_up(), f32::NAN]);
        for l in ls {
            let mut got = [0.0f32; 3];
            if let Some((a, b, t)) = grid.at(l) {
                for r in 0..3 {
                    got[r] = a[r] + t * (b[r] - a[r]);
                }
            }
            for (r, resp) in rs.iter().enumerate() {
                assert_eq!(got[r].to_bits(), resp.eval(l).to_bits(), "λ {l}, curve {r}");
            }
        }
    }

    #[test]
    fn curves_on_other_grids_are_read_on_their_own() {
        let a = curve(380.0, 5.0, vec![0.1; 69]);
        assert!(ResponseGrid::of(&[a.clone(), curve(380.0, 10.0, vec![0.1; 35])]).is_none());
        assert!(ResponseGrid::of(&[a.clone(), curve(385.0, 5.0, vec![0.1; 69])]).is_none());
        let boxed = Response {
            shape: Shape::Box {
                lo: 400.0,
                hi: 500.0,
            },
            scale: 1.0,
        };
        assert!(ResponseGrid::of(&[a, boxed]).is_none());
        assert!(ResponseGrid::of(&[]).is_none());
    }
}
