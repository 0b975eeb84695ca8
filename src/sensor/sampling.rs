//! `spectral.sampling: Sensor`: wavelengths drawn from the sensor's own curves (as Mitsuba 3's
//! `specfilm` does), so a channel gets samples where it responds, e.g. a NIR band past the
//! visible range.
//!
//! The density is the sum over the sensor's channel groups, each normalised to unit area over the
//! spectral range (so a narrow band weighs as much as the whole of XYZ): the observer
//! (x̄ + ȳ + z̄, when XYZ or RGB is written), the even bands (flat over their range), each box
//! band and filter, the camera (r̄ + ḡ + b̄); plus 1% of a uniform density, so p > 0 everywhere
//! in the range and every channel stays unbiased whatever its shape. It is tabulated per 1 nm
//! cell (piecewise constant), which the sampler inverts exactly.

use super::Sensor;

/// Share of the uniform density in the mixture.
const FLOOR: f64 = 0.01;

impl Sensor {
    /// The unnormalised sampling density on `cells` equal cells over `range` (cell means).
    pub fn sampling_density(&self, range: (f32, f32), cells: usize) -> Vec<f32> {
        if self.extras.is_empty() {
            return self.own_density(range, cells);
        }
        // Several sensors (multi.rs): the mean of their densities, each of unit area, so
        // every sensor's channels get samples where they respond.
        let k = 1 + self.extras.len();
        let mut total = self.own_density(range, cells);
        for e in &self.extras {
            for (t, d) in total
                .iter_mut()
                .zip(e.sensor.sampling_density(range, cells))
            {
                *t += d;
            }
        }
        total.iter().map(|t| t / k as f32).collect()
    }

    /// This sensor's density, without the extra sensors'.
    fn own_density(&self, range: (f32, f32), cells: usize) -> Vec<f32> {
        let (lo, hi) = range;
        let h = (hi - lo) as f64 / cells as f64;
        let mut total = vec![0.0f64; cells];
        // Adds one group, normalised to unit area, from its per-cell means.
        let mut add = |f: &dyn Fn(f32) -> f64| {
            let means: Vec<f64> = (0..cells)
                .map(|i| {
                    // Cell mean by the midpoint rule on 8 sub-cells.
                    (0..8)
                        .map(|k| f((lo as f64 + (i as f64 + (k as f64 + 0.5) / 8.0) * h) as f32))
                        .sum::<f64>()
                        / 8.0
                })
                .collect();
            let area: f64 = means.iter().sum::<f64>() * h;
            if area > 0.0 {
                for (t, m) in total.iter_mut().zip(&means) {
                    *t += m / area;
                }
            }
        };
        if self.layers.xyz || !self.layers.rgb.is_empty() {
            add(&|l| self.cmf.eval(l).iter().map(|&v| v as f64).sum());
        }
        if let Some(b) = self.bands {
            add(&|l| if l >= b.lo && l < b.hi { 1.0 } else { 0.0 });
        }
        let camera_from = self.layers.responses.len();
        for r in &self.responses[..camera_from] {
            add(&|l| r.eval(l) as f64);
        }
        if self.layers.camera.is_some() {
            add(&|l| {
                // The camera's three curves (the raw sensor's photon slots follow them).
                self.responses[camera_from..camera_from + 3]
                    .iter()
                    .map(|r| r.eval(l) as f64)
                    .sum()
            });
        }
        let area: f64 = total.iter().sum::<f64>() * h;
        let uniform = 1.0 / (hi - lo) as f64;
        total
            .iter()
            .map(|t| {
                let p = if area > 0.0 { t / area } else { uniform };
                ((1.0 - FLOOR) * p + FLOOR * uniform) as f32
            })
            .collect()
    }
}
