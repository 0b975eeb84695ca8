//! The `stderr` layer of every sensor of a render: each output channel's standard error from
//! the spread of the pixel's camera samples (`integrator::render_film` keeps, per accumulator
//! slot, √(s²/n) with s² the unbiased variance of the samples' own slot values; with caustic
//! light tracing, the variance of the light paths' mean added under the root).
//!
//! A channel that is one slot (Y, an even band, a response channel such as a filter or an
//! explicit band) has that slot's standard error: each sample adds its own estimate of that
//! channel, so the spread is the channel's own, not a sum of the bands' errors. `camera.R/G/B`
//! is its raw slot times the white-balance multiplier and the exposure factor (a diagonal map),
//! so its error is the raw slot's times the same factor. `corrected.*` and the RGB spaces mix
//! slots and would need their covariances, which are not accumulated: they have no stderr.
//! The main sensor's channels are `stderr.<channel>`; an extra sensor's
//! `<name>.stderr.<channel>`, as its colour channels are `<name>.<channel>`.

use super::{Sensor, XYZ_SLOTS};
use crate::film::Channel;

impl Sensor {
    /// This sensor's own channels with a standard error: (channel name, its slot in this
    /// sensor's layout, the factor from the slot to the channel).
    fn error_slots(&self) -> Vec<(String, usize, f32)> {
        let mut out = vec![("Y".to_string(), 1, 1.0)];
        if let Some(b) = self.bands() {
            out.extend((0..b.count).map(|k| (self.band_name(k), XYZ_SLOTS + k as usize, 1.0)));
        }
        let named = self.layers.responses.iter().enumerate();
        out.extend(named.map(|(k, n)| (self.response_name(n), self.response_base + k, 1.0)));
        if let Some(cam) = &self.layers.camera {
            let base = self.response_base + self.layers.responses.len();
            let factor = cam.white_balance * cam.exposure;
            for (c, name) in ["R", "G", "B"].iter().enumerate() {
                out.push((format!("camera.{name}"), base + c, factor[c]));
            }
        }
        out
    }

    /// The stderr channels of this sensor and its extras, from each pixel's standard error of
    /// every slot (`slots()` per pixel, as `render_film` returns them).
    pub fn stderr_channels(&self, se: &[f32]) -> Vec<Channel> {
        let stride = self.slots();
        let pick = |slot: usize, factor: f32| -> Vec<f32> {
            let px = se.iter().skip(slot).step_by(stride);
            px.map(|&v| v * factor).collect()
        };
        let own = self
            .error_slots()
            .into_iter()
            .map(|(name, slot, f)| Channel {
                name: format!("stderr.{name}"),
                data: pick(slot, f),
            });
        let extras = self.extras().iter().flat_map(|e| {
            let slots = e.sensor.error_slots().into_iter();
            slots.map(|(name, slot, f)| Channel {
                name: format!("{}.stderr.{name}", e.name),
                data: pick(e.offset + slot, f),
            })
        });
        own.chain(extras).collect()
    }

    /// The names of the channels `stderr_channels` gives, in order.
    pub fn stderr_names(&self) -> Vec<String> {
        let zeros = vec![0.0; self.slots()];
        let channels = self.stderr_channels(&zeros);
        channels.into_iter().map(|c| c.name).collect()
    }
}
