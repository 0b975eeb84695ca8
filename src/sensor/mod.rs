//! The sensor turns each path's radiance at its N wavelengths into output channels.
//!
//! A lane j with radiance L_j at wavelength λ_j of marginal pdf p_j contributes, per camera sample,
//! - to X, Y, Z: L_j · w_j · x̄ȳz̄(λ_j) / ∫ȳ (so a constant spectrum of 1 gives Y = 1, as in
//!   Mitsuba 3 and pbrt-v4), with the observer's colour-matching functions,
//! - to evenly spaced band b = [λ0, λ1): L_j · w_j / (λ1 − λ0) if λ_j ∈ b (the band's mean
//!   radiance),
//! - to each response channel r (an explicit band, a filter curve, a camera's R, G or B):
//!   L_j · w_j · r(λ_j) · scale_r,
//!
//! where w_j = 1 / (N p_j) is the hero-wavelength estimator's lane weight. Channels are averaged
//! over the pixel's samples; `layers` turns those means into the film's channels (RGB spaces
//! from XYZ, the camera's white balance, exposure and colour correction). A sensor without
//! response channels runs exactly the loop it always ran.

pub mod bands;
pub mod camera;
pub mod colour_space;
pub mod develop;
pub mod export;
mod multi;
pub mod names;
mod noise;
pub mod observer;
pub mod raw;
mod response_grid;
pub mod sampling;
mod stderr;

pub use bands::{Bands, Response, Shape};
pub use camera::CameraModel;
pub use colour_space::RgbSpace;
pub use develop::FilmChannels;
pub use multi::Extra;
pub use observer::Observer;

use crate::film::{spectral_channel_name, Channel};
use crate::spectrum::color::Cmf;
use crate::spectrum::{Spectrum, Wavelengths};
use glam::Vec3;

/// A response channel's name: a Fichet spectral channel `S0.<centre>nm`, or a user's layer.
#[derive(Clone, Debug, PartialEq)]
pub enum ChannelName {
    Spectral(f32),
    Layer(String),
}

impl ChannelName {
    /// The name on its own (unpadded); the film writes `Sensor::response_name` (names.rs).
    pub fn text(&self) -> String {
        match self {
            ChannelName::Spectral(c) => spectral_channel_name(*c),
            ChannelName::Layer(s) => s.clone(),
        }
    }
}

/// What the film shows besides the accumulated means.
#[derive(Clone, Debug, PartialEq)]
pub struct Layers {
    /// RGB spaces from XYZ, in output order.
    pub rgb: Vec<RgbSpace>,
    pub xyz: bool,
    /// Names of the response channels that are not the camera's.
    pub responses: Vec<ChannelName>,
    /// The camera, whose three curves are the last three response channels.
    pub camera: Option<CameraModel>,
    /// EXR header attributes describing the sensor.
    pub header: Vec<(String, String)>,
}

impl Default for Layers {
    fn default() -> Self {
        Self {
            rgb: vec![RgbSpace::Srgb],
            xyz: true,
            responses: Vec::new(),
            camera: None,
            header: Vec::new(),
        }
    }
}

#[derive(Clone, Debug)]
pub struct Sensor {
    cmf: &'static Cmf,
    inv_y_integral: f32,
    bands: Option<Bands>,
    inv_band_width: f32,
    responses: Vec<Response>,
    /// `responses` side by side when they share one grid (response_grid.rs).
    response_grid: Option<response_grid::ResponseGrid>,
    /// Slot of the first response channel.
    response_base: usize,
    pub layers: Layers,
    /// The raw sensor, read out once on the finished film (`raw::RawModel::mosaic`).
    pub raw: Option<raw::RawModel>,
    /// Further sensors on the same samples, their slots after this one's (multi.rs).
    extras: Vec<Extra>,
}

/// Accumulator slots: X, Y, Z first, then one per band.
pub const XYZ_SLOTS: usize = 3;

impl Sensor {
    /// Today's sensor: CIE 1931 XYZ, linear sRGB, and `bands`.
    pub fn new(bands: Option<Bands>) -> Self {
        Self::with(Observer::Cie1931, bands, Vec::new(), Layers::default())
    }

    /// A sensor with `responses` channels after the even bands.
    pub fn with(
        observer: Observer,
        bands: Option<Bands>,
        responses: Vec<Response>,
        layers: Layers,
    ) -> Self {
        let cmf = observer.cmf();
        Self {
            cmf,
            inv_y_integral: 1.0 / cmf.y_integral,
            bands,
            inv_band_width: bands.map_or(0.0, |b| 1.0 / b.width()),
            response_base: XYZ_SLOTS + bands.map_or(0, |b| b.count as usize),
            response_grid: response_grid::ResponseGrid::of(&responses),
            responses,
            layers,
            raw: None,
            extras: Vec::new(),
        }
    }

    pub fn bands(&self) -> Option<Bands> {
        self.bands
    }

    pub fn responses(&self) -> &[Response] {
        &self.responses
    }

    /// Number of accumulator slots per pixel (the extra sensors' included).
    pub fn slots(&self) -> usize {
        self.response_base + self.responses.len() + self.extra_slots()
    }

    /// Adds one camera sample: radiance `l` at the lanes, lane weights `w` (see module docs).
    #[inline]
    pub fn add<const N: usize>(
        &self,
        acc: &mut [f64],
        l: &Spectrum<N>,
        w: &Spectrum<N>,
        wl: &Wavelengths<N>,
    ) {
        // The observer read at all lanes at once (SIMD), then each slot summed in lane order
        // (X, Y, Z in registers: one bounds check, no store between lanes).
        let v: [f32; N] = std::array::from_fn(|j| l[j] * w[j]);
        let [xs, ys, zs] = self.cmf.eval_lanes(&wl.lambda);
        let (head, bands) = acc.split_at_mut(XYZ_SLOTS);
        let mut sum = [head[0], head[1], head[2]];
        for j in 0..N {
            if v[j] == 0.0 {
                continue;
            }
            let s = v[j] * self.inv_y_integral;
            sum[0] += (xs[j] * s) as f64;
            sum[1] += (ys[j] * s) as f64;
            sum[2] += (zs[j] * s) as f64;
        }
        head.copy_from_slice(&sum);
        if let Some(b) = &self.bands {
            for (&v, &lambda) in v.iter().zip(&wl.lambda) {
                // In range, truncation is the floor (`floor` itself is a libm call on baseline
                // x86-64, 1% of a render).
                let k = (lambda - b.lo) * self.inv_band_width;
                if v != 0.0 && k >= 0.0 && k < b.count as f32 {
                    bands[k as u32 as usize] += (v * self.inv_band_width) as f64;
                }
            }
        }
        if !self.responses.is_empty() {
            self.add_responses(acc, &v, wl);
        }
        if !self.extras.is_empty() {
            self.add_extras(acc, l, w, wl);
        }
    }

    /// The response channels' share of `add`, given its weighted radiance `v` = L·w per lane.
    #[inline(never)]
    fn add_responses<const N: usize>(&self, acc: &mut [f64], v: &[f32; N], wl: &Wavelengths<N>) {
        let acc = &mut acc[self.response_base..];
        if let Some(grid) = &self.response_grid {
            let acc = &mut acc[..self.responses.len()];
            for (&v, &lambda) in v.iter().zip(&wl.lambda) {
                if v == 0.0 {
                    continue;
                }
                let Some((a, b, t)) = grid.at(lambda) else {
                    continue;
                };
                let slots = acc.iter_mut().zip(&self.responses);
                for ((acc, r), (&a, &b)) in slots.zip(a.iter().zip(b)) {
                    // `Dense::eval`'s interpolation, so the value `r.eval` gives.
                    let e = a + t * (b - a);
                    if e != 0.0 {
                        *acc += (v * e * r.scale) as f64;
                    }
                }
            }
            return;
        }
        // Response by response, each read at all lanes at once; every slot still sums its
        // lanes in lane order, so the bits are those of lane-by-lane lookups.
        for (a, r) in acc.iter_mut().zip(&self.responses) {
            let e = r.eval_lanes(wl);
            for j in 0..N {
                if v[j] != 0.0 && e[j] != 0.0 {
                    *a += (v[j] * e[j] * r.scale) as f64;
                }
            }
        }
    }

    /// The film's channels from per-pixel means (`slots()` values per pixel, `n` pixels), and
    /// the centre wavelengths of its spectral (`S0.`) channels in channel order.
    pub fn channels(&self, means: &[f32], n: usize) -> (Vec<Channel>, Vec<f32>) {
        let slots = self.slots();
        debug_assert_eq!(means.len(), n * slots);
        let mut channels = Vec::new();
        let xyz_at =
            |i: usize| Vec3::new(means[i * slots], means[i * slots + 1], means[i * slots + 2]);
        let push3 =
            |channels: &mut Vec<Channel>, prefix: Option<&str>, names: [&str; 3], v: &[Vec3]| {
                for (c, name) in names.iter().enumerate() {
                    channels.push(Channel {
                        name: match prefix {
                            Some(p) => format!("{p}.{name}"),
                            None => name.to_string(),
                        },
                        data: v.iter().map(|v| v[c]).collect(),
                    });
                }
            };
        // The XYZ, band and response slots, each a channel, gathered in one pass over the
        // means: a pass per channel walked the whole buffer once per channel (50 ms,
        // single-threaded, of a 1.3 s materials render with its 47 bands).
        let gathered = self.response_base + self.layers.responses.len();
        let mut columns: Vec<Vec<f32>> = (0..gathered).map(|_| Vec::with_capacity(n)).collect();
        for px in means.chunks_exact(slots) {
            for (c, &v) in columns.iter_mut().zip(&px[..gathered]) {
                c.push(v);
            }
        }
        let mut slot = |k: usize| std::mem::take(&mut columns[k]);
        let rgb_of = |space: RgbSpace| -> Vec<Vec3> {
            let m = space.from_xyz();
            (0..n).map(|i| m * xyz_at(i)).collect()
        };
        // Today's order first: sRGB, XYZ, even bands.
        if self.layers.rgb.contains(&RgbSpace::Srgb) {
            push3(
                &mut channels,
                None,
                ["R", "G", "B"],
                &rgb_of(RgbSpace::Srgb),
            );
        }
        if self.layers.xyz {
            for (c, name) in ["X", "Y", "Z"].iter().enumerate() {
                channels.push(Channel {
                    name: name.to_string(),
                    data: slot(c),
                });
            }
        }
        for &space in self.layers.rgb.iter().filter(|s| **s != RgbSpace::Srgb) {
            push3(
                &mut channels,
                space.layer(),
                ["R", "G", "B"],
                &rgb_of(space),
            );
        }
        let mut band_centers = Vec::new();
        // Once, not per name: it formats every centre (O(bands²) through band_name).
        let digits = self.name_digits();
        if let Some(b) = self.bands {
            for k in 0..b.count {
                let center = b.center(k);
                band_centers.push(center);
                channels.push(Channel {
                    name: names::padded_name(center, digits),
                    data: slot(XYZ_SLOTS + k as usize),
                });
            }
        }
        for (k, name) in self.layers.responses.iter().enumerate() {
            if let ChannelName::Spectral(c) = name {
                band_centers.push(*c);
            }
            channels.push(Channel {
                name: self.response_name(name),
                data: slot(self.response_base + k),
            });
        }
        if let Some(cam) = &self.layers.camera {
            let base = self.response_base + self.layers.responses.len();
            let raw: Vec<Vec3> = (0..n)
                .map(|i| {
                    let p = &means[i * slots + base..i * slots + base + 3];
                    Vec3::new(p[0], p[1], p[2])
                })
                .collect();
            let (shown, corrected) = cam.develop(&raw);
            push3(&mut channels, Some("camera"), ["R", "G", "B"], &shown);
            push3(
                &mut channels,
                Some("corrected"),
                ["R", "G", "B"],
                &corrected,
            );
        }
        channels.extend(self.extra_channels(means, n));
        (channels, band_centers)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::{WavelengthSampler, WavelengthSampling};

    /// A constant spectrum of 1 must give Y = 1 and every band = 1 in expectation. With uniform
    /// sampling over 200k samples, the band means have relative standard error ≈ √(10/200k·4) ≈
    /// 0.35%; the tolerance of 2% is > 5σ.
    #[test]
    fn constant_spectrum_is_unit_in_y_and_bands() {
        let bands = Bands {
            lo: 360.0,
            hi: 830.0,
            count: 47,
        };
        let sensor = Sensor::new(Some(bands));
        let ws = WavelengthSampler::new(WavelengthSampling::Uniform, 360.0, 830.0);
        let mut acc = vec![0.0; sensor.slots()];
        let n = 200_000;
        let mut rng = crate::math::rng::Pcg32::new(1, 2);
        for _ in 0..n {
            let wl = ws.sample::<4>(rng.next_f32());
            let w = Spectrum::from_fn(|j| 1.0 / (4.0 * wl.pdf[j]));
            sensor.add(&mut acc, &Spectrum::one(), &w, &wl);
        }
        let y = acc[1] / n as f64;
        assert!((y - 1.0).abs() < 0.01, "Y = {y}");
        for b in 0..47 {
            let v = acc[XYZ_SLOTS + b] / n as f64;
            assert!((v - 1.0).abs() < 0.02, "band {b}: {v}");
        }
    }

    /// A response box [500, 600) with scale 1/100 reads 1 for a constant spectrum of 1 (same
    /// sampling and tolerance argument as above: σ ≈ 0.2% over 200k samples; 2% tolerance).
    #[test]
    fn response_box_is_its_mean() {
        let r = Response {
            shape: Shape::Box {
                lo: 500.0,
                hi: 600.0,
            },
            scale: 0.01,
        };
        let layers = Layers {
            responses: vec![ChannelName::Spectral(550.0)],
            ..Layers::default()
        };
        let sensor = Sensor::with(Observer::Cie1931, None, vec![r], layers);
        assert_eq!(sensor.slots(), 4);
        let ws = WavelengthSampler::new(WavelengthSampling::Uniform, 360.0, 830.0);
        let mut acc = vec![0.0; sensor.slots()];
        let n = 200_000;
        let mut rng = crate::math::rng::Pcg32::new(3, 4);
        for _ in 0..n {
            let wl = ws.sample::<4>(rng.next_f32());
            sensor.add(&mut acc, &Spectrum::one(), &wl.estimator_weights(), &wl);
        }
        let v = acc[3] / n as f64;
        assert!((v - 1.0).abs() < 0.02, "{v}");
    }
}
