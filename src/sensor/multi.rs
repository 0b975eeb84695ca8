//! Several sensors from one render: the scene's `sensors: [(name, sensor)]` beside its own.
//!
//! Each extra sensor accumulates the same camera samples (radiance, lane weights, wavelengths)
//! into slots of its own after the main sensor's, so three cameras and a hyperspectral cube
//! come from one set of paths. Its channels are its single-sensor channels prefixed with
//! `<name>.` (`nikon.camera.R`, `hsi.S0.850,000000nm`), its header keys `prism:<name>.<key>`.
//! With the scene's wavelength sampling (uniform or visible) an extra sensor's accumulators
//! see the very samples, in the same order, that a render with that sensor alone sees, so its
//! channels equal that render's bit for bit (tests/sensor_multi.rs). `sampling: Sensor` draws
//! from the mean of every sensor's density instead, so the channels then agree in expectation
//! only. Each sensor has its `stderr` channels (stderr.rs: `<name>.stderr.<channel>`) and an
//! extra sensor with bands its `albedo` bands (`<name>.albedo.<band>`); the main sensor alone
//! drives adaptive sampling and the preview.

use super::Sensor;
use crate::film::{Channel, UintChannel};
use crate::spectrum::{Spectrum, Wavelengths};

/// An extra sensor and where its slots start in each pixel's accumulators.
#[derive(Clone, Debug)]
pub struct Extra {
    /// The prefix of its channels and header keys.
    pub name: String,
    pub sensor: Sensor,
    /// Its first slot (after the main sensor's and earlier extras' slots).
    pub offset: usize,
}

impl Extra {
    /// `channels` named as this sensor's: `<name>.<channel>`.
    pub fn prefixed(&self, channels: Vec<Channel>) -> Vec<Channel> {
        let named = channels.into_iter().map(|c| Channel {
            name: format!("{}.{}", self.name, c.name),
            data: c.data,
        });
        named.collect()
    }
}

impl Sensor {
    /// This sensor with `extras` (name, sensor) accumulating beside it, in order.
    pub fn with_extras(mut self, extras: Vec<(String, Sensor)>) -> Self {
        let mut offset = self.slots();
        for (name, sensor) in extras {
            let n = sensor.slots();
            self.extras.push(Extra {
                name,
                sensor,
                offset,
            });
            offset += n;
        }
        self
    }

    pub fn extras(&self) -> &[Extra] {
        &self.extras
    }

    /// The slots of the extra sensors (after `own_slots`).
    pub(super) fn extra_slots(&self) -> usize {
        self.extras.iter().map(|e| e.sensor.slots()).sum()
    }

    /// Each extra sensor's `add` on its own slots.
    #[inline(never)]
    pub(super) fn add_extras<const N: usize>(
        &self,
        acc: &mut [f64],
        l: &Spectrum<N>,
        w: &Spectrum<N>,
        wl: &Wavelengths<N>,
    ) {
        for e in &self.extras {
            e.sensor.add(&mut acc[e.offset..], l, w, wl);
        }
    }

    /// One extra sensor's per-pixel means, in its own layout, out of the full means.
    fn extra_means(&self, e: &Extra, means: &[f32], n: usize) -> Vec<f32> {
        let (stride, k) = (self.slots(), e.sensor.slots());
        (0..n)
            .flat_map(|i| &means[i * stride + e.offset..i * stride + e.offset + k])
            .copied()
            .collect()
    }

    /// The extra sensors' float channels, each named `<name>.<its own name>`.
    pub(super) fn extra_channels(&self, means: &[f32], n: usize) -> Vec<Channel> {
        let mut out = Vec::new();
        for e in &self.extras {
            let (channels, _) = e.sensor.channels(&self.extra_means(e, means, n), n);
            out.extend(e.prefixed(channels));
        }
        out
    }

    /// The extra sensors' raw mosaics (`<name>.raw.Y`), drawn from `seed` as a render with that
    /// sensor alone draws its own.
    pub fn extra_mosaics(
        &self,
        means: &[f32],
        width: u32,
        height: u32,
        seed: u64,
    ) -> Vec<UintChannel> {
        let n = width as usize * height as usize;
        let mut out = Vec::new();
        for e in &self.extras {
            if let Some(raw) = &e.sensor.raw {
                let sub = self.extra_means(e, means, n);
                let mut c = raw.mosaic(&sub, e.sensor.slots(), width, height, seed);
                c.name = format!("{}.{}", e.name, c.name);
                out.push(c);
            }
        }
        out
    }

    /// The channels of the `albedo` layer (`pipeline::add_layers`): `albedo.R/G/B`, one
    /// `albedo.<band>` per band of this sensor, then each extra sensor's bands,
    /// `<name>.albedo.<band>`.
    pub fn albedo_names(&self) -> Vec<String> {
        let bands = |s: &Sensor| -> Vec<String> {
            let b = s.bands().map_or(0, |b| b.count);
            (0..b)
                .map(|k| format!("albedo.{}", s.band_name(k)))
                .collect()
        };
        let mut out: Vec<String> = ["R", "G", "B"].map(|c| format!("albedo.{c}")).to_vec();
        out.extend(bands(self));
        for e in &self.extras {
            out.extend(
                bands(&e.sensor)
                    .into_iter()
                    .map(|c| format!("{}.{c}", e.name)),
            );
        }
        out
    }

    /// The extra sensors' EXR header attributes, `prism:<name>.<key>`.
    pub fn extra_header(&self) -> Vec<(String, String)> {
        let mut out = Vec::new();
        for e in &self.extras {
            for (k, v) in &e.sensor.layers.header {
                let key = k.strip_prefix("prism:").unwrap_or(k);
                out.push((format!("prism:{}.{key}", e.name), v.clone()));
            }
        }
        out
    }

    /// The names of the channels this sensor alone writes (float channels, then the raw
    /// mosaic's), without the extras'.
    pub fn own_channel_names(&self) -> Vec<String> {
        let zeros = vec![0.0; self.slots()];
        let (channels, _) = self.channels(&zeros, 1);
        let own = channels.len() - self.extra_channels(&zeros, 1).len();
        let mut names: Vec<String> = channels.into_iter().take(own).map(|c| c.name).collect();
        if let Some(raw) = &self.raw {
            names.push(raw.mosaic(&zeros, self.slots(), 1, 1, 0).name);
        }
        names
    }
}
