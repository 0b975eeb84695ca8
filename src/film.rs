//! The rendered image: named float channels, one value per pixel, in row-major order (row 0 at
//! the top). The integrator fills it; the output writers read it.

use crate::sensor::{Bands, XYZ_SLOTS};
use crate::spectrum::color::XYZ_TO_SRGB;
use glam::Vec3;

/// Which channels the film keeps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilmChannels {
    pub rgb: bool,
    pub xyz: bool,
    pub bands: Option<Bands>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Channel {
    pub name: String,
    pub data: Vec<f32>,
}

#[derive(Clone, Debug)]
pub struct Film {
    pub width: u32,
    pub height: u32,
    pub channels: Vec<Channel>,
    /// Centre wavelengths of the spectral channels, in channel order after the colour channels.
    pub band_centers: Vec<f32>,
}

/// The Fichet et al. 2021 name of an emissive spectral channel: `S0.550,000000nm`.
pub fn spectral_channel_name(nm: f32) -> String {
    format!("S0.{}nm", format!("{nm:.6}").replace('.', ","))
}

impl Film {
    /// Builds the film from per-pixel accumulator means (`slots` values per pixel: X, Y, Z, then
    /// one per band).
    pub fn from_means(
        width: u32,
        height: u32,
        spec: &FilmChannels,
        means: &[f32],
        slots: usize,
    ) -> Film {
        let n = (width * height) as usize;
        debug_assert_eq!(means.len(), n * slots);
        let mut channels = Vec::new();
        let xyz_at =
            |i: usize| Vec3::new(means[i * slots], means[i * slots + 1], means[i * slots + 2]);
        if spec.rgb {
            let rgb: Vec<Vec3> = (0..n).map(|i| XYZ_TO_SRGB * xyz_at(i)).collect();
            for (c, name) in ["R", "G", "B"].iter().enumerate() {
                channels.push(Channel {
                    name: name.to_string(),
                    data: rgb.iter().map(|v| v[c]).collect(),
                });
            }
        }
        if spec.xyz {
            for (c, name) in ["X", "Y", "Z"].iter().enumerate() {
                channels.push(Channel {
                    name: name.to_string(),
                    data: (0..n).map(|i| means[i * slots + c]).collect(),
                });
            }
        }
        let mut band_centers = Vec::new();
        if let Some(b) = spec.bands {
            for k in 0..b.count {
                let center = b.center(k);
                band_centers.push(center);
                let slot = XYZ_SLOTS + k as usize;
                channels.push(Channel {
                    name: spectral_channel_name(center),
                    data: (0..n).map(|i| means[i * slots + slot]).collect(),
                });
            }
        }
        Film {
            width,
            height,
            channels,
            band_centers,
        }
    }

    /// Pixels with a non-finite value in any channel: an accumulation that overflowed f32
    /// although every sample was finite. One pass over the image, after rendering.
    pub fn nonfinite_pixels(&self) -> u64 {
        let n = (self.width * self.height) as usize;
        (0..n)
            .filter(|&i| self.channels.iter().any(|c| !c.data[i].is_finite()))
            .count() as u64
    }

    pub fn channel(&self, name: &str) -> Option<&[f32]> {
        self.channels
            .iter()
            .find(|c| c.name == name)
            .map(|c| c.data.as_slice())
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
            rgb: true,
            xyz: true,
            bands: None,
        };
        let means = [0.2, 0.3, 0.1, 3e38, 3e38, 3e38];
        let film = Film::from_means(2, 1, &spec, &means, 3);
        assert!(film.channel("X").unwrap().iter().all(|v| v.is_finite()));
        assert_eq!(film.nonfinite_pixels(), 1);
    }

    #[test]
    fn fichet_channel_names() {
        assert_eq!(spectral_channel_name(550.0), "S0.550,000000nm");
        assert_eq!(spectral_channel_name(365.0), "S0.365,000000nm");
    }
}
