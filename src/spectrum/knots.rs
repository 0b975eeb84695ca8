//! `Knots`: the sorted wavelengths of an unevenly spaced table, with an index that finds a
//! wavelength's interval in a step or two instead of a binary search.
//!
//! Why: measured conductors (η and κ per metal, on grids even in photon energy, so uneven in
//! nm) are looked up at every lane of every conductor hit, and `partition_point` over their
//! ~50–500 knots was 6.9% of the instructions of the metals benchmark scene. The index gives
//! exactly `partition_point`'s answer (the walk below corrects any guess), so every lookup, and
//! so every image, keeps its bits.

/// The most cells an index holds (4 bytes each): enough for 2 cells per interval of any table
/// we ship; a denser table only walks a few more steps.
const MAX_CELLS: usize = 1 << 14;

#[derive(Clone, Debug, PartialEq)]
pub struct Knots {
    nm: Vec<f32>,
    /// The first knot's wavelength and the cells per nm.
    lo: f32,
    inv_cell: f32,
    /// Per cell: how many knots lie before the cell's start (a guess the walk corrects; 0 for
    /// the first cell, which is where NaN lands, whose answer is 0).
    first: Vec<u32>,
}

impl Knots {
    /// `nm` strictly increasing, at least one knot.
    pub fn new(nm: Vec<f32>) -> Knots {
        let (lo, hi) = (nm[0], nm[nm.len() - 1]);
        let gap = nm
            .windows(2)
            .map(|w| w[1] - w[0])
            .fold(f32::INFINITY, f32::min);
        // Two cells per smallest interval: each cell then starts at most one knot before its
        // answer.
        let cells = if gap.is_finite() && gap > 0.0 {
            (((hi - lo) / gap * 2.0).ceil() as usize).clamp(1, MAX_CELLS)
        } else {
            1
        };
        let inv_cell = if hi > lo {
            cells as f32 / (hi - lo)
        } else {
            0.0
        };
        let first = (0..cells)
            .map(|c| {
                let start = lo + c as f32 / inv_cell.max(f32::MIN_POSITIVE);
                nm.partition_point(|&w| w < start) as u32
            })
            .collect();
        Knots {
            nm,
            lo,
            inv_cell,
            first,
        }
    }

    pub fn nm(&self) -> &[f32] {
        &self.nm
    }

    /// `self.nm().partition_point(|&w| w <= lambda)`, bit for bit the same index (tested),
    /// NaN included.
    #[inline]
    pub fn upper(&self, lambda: f32) -> usize {
        // Saturating float → int conversion: NaN and below-range give cell 0.
        let c = (((lambda - self.lo) * self.inv_cell) as usize).min(self.first.len() - 1);
        let mut i = self.first[c] as usize;
        while i < self.nm.len() && self.nm[i] <= lambda {
            i += 1;
        }
        while i > 0 && self.nm[i - 1] > lambda {
            i -= 1;
        }
        i
    }
}

/// The most samples `on_common_grid` makes of a table (4 bytes each).
const MAX_GRID: usize = 1 << 13;

/// The table (`nm` strictly increasing) sampled at even steps, if every knot lies on the grid
/// of its smallest interval (within 10⁻⁶ of a step) and that grid has at most `MAX_GRID`
/// points: `(step, values)` from `nm[0]`, each grid point linearly interpolated between the
/// knots around it (in f64) and the knots' own values kept. The same piecewise-linear curve, so
/// it can be a `Dense` one, looked up in SIMD without a search: a reflectance table padded with
/// far knots (ColorChecker from 300 nm, 10 nm steps, out to 1130 nm) was an `Irregular`
/// curve looked up one lane at a time, 4.7% of the tabletop dataset's frames.
pub fn on_common_grid(nm: &[f64], values: &[f64]) -> Option<(f64, Vec<f64>)> {
    let step = nm
        .windows(2)
        .map(|w| w[1] - w[0])
        .fold(f64::INFINITY, f64::min);
    if !(step.is_finite() && step > 0.0) {
        return None;
    }
    let position = |w: f64| (w - nm[0]) / step;
    let last = position(nm[nm.len() - 1]).round();
    if last.is_nan()
        || last >= MAX_GRID as f64
        || nm
            .iter()
            .any(|&w| (position(w) - position(w).round()).abs() > 1e-6)
    {
        return None;
    }
    let mut grid = Vec::with_capacity(last as usize + 1);
    let mut j = 0;
    for k in 0..=last as usize {
        // The knot interval [j, j + 1] that holds grid point k.
        while j + 2 < nm.len() && position(nm[j + 1]).round() as usize <= k {
            j += 1;
        }
        let (k0, k1) = (position(nm[j]).round(), position(nm[j + 1]).round());
        grid.push(match k as f64 {
            k if k == k0 => values[j],
            k if k == k1 => values[j + 1],
            k => values[j] + (k - k0) / (k1 - k0) * (values[j + 1] - values[j]),
        });
    }
    Some((step, grid))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every lookup of every metal table we ship, at random, knot, next-float and out-of-range
    /// wavelengths and NaN, equals `partition_point`'s: exact equality, since the point of the
    /// index is to change no bit.
    #[test]
    fn upper_is_partition_point() {
        let mut tables: Vec<Vec<f32>> = vec![vec![500.0], vec![400.0, 400.5, 700.0]];
        for name in crate::spectrum::metals::metal_names() {
            let text = crate::spectrum::data::embedded(&format!("metals/{name}")).unwrap();
            let t = crate::spectrum::table::parse(text).unwrap();
            tables.push(t.wavelengths.iter().map(|&w| w as f32).collect());
        }
        let mut rng = crate::math::rng::Pcg32::new(3, 9);
        for nm in tables {
            let k = Knots::new(nm.clone());
            let (lo, hi) = (nm[0], nm[nm.len() - 1]);
            let mut probes = vec![f32::NAN, f32::INFINITY, -f32::INFINITY, lo - 1.0, hi + 1.0];
            for &w in &nm {
                probes.extend([w, w.next_up(), w.next_down()]);
            }
            for _ in 0..20_000 {
                probes.push(lo - 10.0 + (hi - lo + 20.0) * rng.next_f32());
            }
            for l in probes {
                assert_eq!(k.upper(l), nm.partition_point(|&w| w <= l), "λ = {l}");
            }
        }
    }
}
