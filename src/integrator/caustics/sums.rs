//! What the light paths add to the pixels: the sums of their splats, and (for the `stderr`
//! layer) the sums of their squares, so a pixel's standard error counts the light tracer's
//! noise as well as the camera samples'.
//!
//! A pixel's light-traced value is the mean over all P light paths of c_k, path k's
//! contribution to it (zero for most paths). Its variance is s²/P, s² the sample variance of
//! the c_k: each path's splats into one pixel are summed before squaring (a path that connects
//! twice near one pixel adds one c_k, not two).

use crate::sensor::Sensor;
use crate::spectrum::{Spectrum, Wavelengths};

/// One light path's contribution to one pixel.
pub(super) struct Splat<const N: usize> {
    pub(super) pixel: u32,
    pub(super) l: Spectrum<N>,
    pub(super) wl: Wavelengths<N>,
}

/// The splats of one chunk of light paths, in path order, and (for squares) where each path
/// with splats starts.
#[derive(Default)]
pub(super) struct Chunk<const N: usize> {
    pub(super) splats: Vec<Splat<N>>,
    pub(super) starts: Vec<u32>,
}

/// Per pixel and slot: the sum of the splats and, with squares, of each path's squared
/// contribution.
pub(super) struct Sums {
    slots: usize,
    acc: Vec<f64>,
    acc2: Vec<f64>,
    /// One path's contributions by pixel (pixels, then `slots` values each), reused.
    path_pixels: Vec<u32>,
    path_values: Vec<f64>,
}

impl Sums {
    pub(super) fn new(pixels: usize, slots: usize, squares: bool) -> Self {
        Sums {
            slots,
            acc: vec![0.0; pixels * slots],
            acc2: if squares {
                vec![0.0; pixels * slots]
            } else {
                Vec::new()
            },
            path_pixels: Vec::new(),
            path_values: Vec::new(),
        }
    }

    /// Adds a chunk's splats, in order (the sums are the same whatever the thread count).
    pub(super) fn add<const N: usize, const SE: bool>(&mut self, sensor: &Sensor, c: &Chunk<N>) {
        let slots = self.slots;
        for s in &c.splats {
            let at = s.pixel as usize * slots;
            let w = s.wl.estimator_weights();
            sensor.add(&mut self.acc[at..at + slots], &s.l, &w, &s.wl);
        }
        if !SE {
            return;
        }
        for (i, &start) in c.starts.iter().enumerate() {
            let end = c.starts.get(i + 1).map_or(c.splats.len(), |&e| e as usize);
            self.add_squares(sensor, &c.splats[start as usize..end]);
        }
    }

    /// Adds the squares of one path's contributions (`path`: its splats).
    fn add_squares<const N: usize>(&mut self, sensor: &Sensor, path: &[Splat<N>]) {
        let slots = self.slots;
        self.path_pixels.clear();
        self.path_values.clear();
        for s in path {
            let k = match self.path_pixels.iter().position(|&p| p == s.pixel) {
                Some(k) => k,
                None => {
                    self.path_pixels.push(s.pixel);
                    self.path_values.resize(self.path_values.len() + slots, 0.0);
                    self.path_pixels.len() - 1
                }
            };
            let w = s.wl.estimator_weights();
            sensor.add(
                &mut self.path_values[k * slots..(k + 1) * slots],
                &s.l,
                &w,
                &s.wl,
            );
        }
        for (&p, v) in self
            .path_pixels
            .iter()
            .zip(self.path_values.chunks_exact(slots))
        {
            let at = p as usize * slots;
            for (q, &x) in self.acc2[at..at + slots].iter_mut().zip(v) {
                *q += x * x;
            }
        }
    }

    /// The means over `paths` light paths, and with squares the variance of each mean
    /// (unbiased sample variance / paths; empty without).
    pub(super) fn finish(mut self, paths: u64) -> (Vec<f64>, Vec<f64>) {
        let inv = 1.0 / paths as f64;
        self.acc.iter_mut().for_each(|a| *a *= inv);
        let n = paths as f64;
        let var = self
            .acc
            .iter()
            .zip(&self.acc2)
            .map(|(&m, &q)| {
                if n > 1.0 {
                    ((q - n * m * m) / (n - 1.0)).max(0.0) / n
                } else {
                    0.0
                }
            })
            .collect();
        (self.acc, var)
    }
}
