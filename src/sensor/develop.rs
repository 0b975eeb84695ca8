//! Develop: the accumulators' per-pixel means → the film's channels, and the raw sensor's
//! mosaic when there is one. Every stage after the accumulators lives here or in the sensor, so
//! a new stage does not touch the integrator; the film is a plain image that knows no sensor
//! (it sits below it, on the base floor).

use super::Sensor;
use crate::film::Film;

/// Which channels the film keeps: the sensor's.
#[derive(Clone, Debug)]
pub struct FilmChannels {
    pub sensor: Sensor,
}

impl FilmChannels {
    /// Builds the film from per-pixel accumulator means (`slots` values per pixel, laid out
    /// as the sensor's `add` accumulates them); the raw mosaic's noise is drawn from `seed`.
    pub fn develop(&self, width: u32, height: u32, means: &[f32], slots: usize, seed: u64) -> Film {
        let n = (width * height) as usize;
        debug_assert_eq!(means.len(), n * slots);
        let (channels, band_centers) = self.sensor.channels(means, n);
        let mut film = Film {
            width,
            height,
            channels,
            band_centers,
            uint_channels: Vec::new(),
            header: self.sensor.layers.header.clone(),
        };
        film.header.extend(self.sensor.extra_header());
        if let Some(raw) = &self.sensor.raw {
            film.uint_channels
                .push(raw.mosaic(means, slots, width, height, seed));
        }
        film.uint_channels
            .extend(self.sensor.extra_mosaics(means, width, height, seed));
        film
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Finite means can still overflow in the RGB conversion (3e38 · 3.24 > f32::MAX): such a
    /// pixel is counted, a normal one is not.
    #[test]
    fn overflowed_pixels_are_counted() {
        let spec = FilmChannels {
            sensor: Sensor::new(None),
        };
        let means = [0.2, 0.3, 0.1, 3e38, 3e38, 3e38];
        let film = spec.develop(2, 1, &means, 3, 0);
        assert!(film.channel("X").unwrap().iter().all(|v| v.is_finite()));
        assert_eq!(film.nonfinite_pixels(), 1);
    }
}
