//! Pixel reconstruction filters, applied by filter importance sampling: each camera sample's
//! film position is drawn from the filter's distribution around the pixel centre and counts
//! fully towards that one pixel. Unbiased for the filtered image (Ernst et al. 2006), no splatting
//! across pixels, so a pixel's value depends only on its own samples, whatever the threads.

use crate::math::distribution::Distribution1D;
use glam::Vec2;
use serde::{Deserialize, Serialize};

/// A separable, non-negative pixel filter.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum FilterConfig {
    /// Uniform over a square of half-width `radius` pixels (Mitsuba's `box`, radius 0.5).
    Box {
        #[serde(default = "half")]
        radius: f32,
    },
    /// Mitsuba's `gaussian`: exp(−x²/2σ²) minus its value at the radius 4σ, clamped at 0.
    Gaussian {
        #[serde(default = "half")]
        stddev: f32,
    },
}

fn half() -> f32 {
    0.5
}

impl Default for FilterConfig {
    fn default() -> Self {
        FilterConfig::Gaussian { stddev: 0.5 }
    }
}

#[derive(Clone, Debug)]
pub enum Filter {
    Box { radius: f32 },
    Tabulated { radius: f32, dist: Distribution1D },
}

/// Cells of the tabulated 1D filter: the piecewise-constant approximation of the Gaussian then
/// differs from it by < 0.1% of its peak.
const TABLE_CELLS: usize = 1024;

impl Filter {
    pub fn new(cfg: &FilterConfig) -> Self {
        match *cfg {
            FilterConfig::Box { radius } => Filter::Box { radius },
            FilterConfig::Gaussian { stddev } => {
                let radius = 4.0 * stddev;
                let alpha = -1.0 / (2.0 * stddev * stddev);
                let bias = (alpha * radius * radius).exp();
                let weights: Vec<f32> = (0..TABLE_CELLS)
                    .map(|i| {
                        let x = -radius + 2.0 * radius * (i as f32 + 0.5) / TABLE_CELLS as f32;
                        ((alpha * x * x).exp() - bias).max(0.0)
                    })
                    .collect();
                Filter::Tabulated {
                    radius,
                    dist: Distribution1D::new(&weights),
                }
            }
        }
    }

    /// Offset from the pixel centre, in pixels.
    #[inline]
    pub fn sample(&self, u: Vec2) -> Vec2 {
        match self {
            Filter::Box { radius } => (2.0 * u - Vec2::ONE) * *radius,
            Filter::Tabulated { radius, dist } => {
                let x = dist.sample_continuous(u.x).0;
                let y = dist.sample_continuous(u.y).0;
                (2.0 * Vec2::new(x, y) - Vec2::ONE) * *radius
            }
        }
    }

    pub fn radius(&self) -> f32 {
        match self {
            Filter::Box { radius } | Filter::Tabulated { radius, .. } => *radius,
        }
    }
}
