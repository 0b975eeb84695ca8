//! The rendered image: named float channels, one value per pixel, in row-major order (row 0 at
//! the top). The integrator fills it (through `sensor::FilmChannels::develop`); the output
//! writers read it. A plain image of the base floor: it knows no sensor.

pub mod aov;

pub use aov::{Aov, UintChannel};

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
    /// 32-bit unsigned channels (the id AOVs); float AOVs are in `channels`, after the colours.
    pub uint_channels: Vec<UintChannel>,
    /// EXR header attributes the sensor adds (camera matrix, white balance, …).
    pub header: Vec<(String, String)>,
}

/// The Fichet et al. 2021 name of an emissive spectral channel: `S0.550,000000nm`.
pub fn spectral_channel_name(nm: f32) -> String {
    format!("S0.{}nm", format!("{nm:.6}").replace('.', ","))
}

impl Film {
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

    #[test]
    fn fichet_channel_names() {
        assert_eq!(spectral_channel_name(550.0), "S0.550,000000nm");
        assert_eq!(spectral_channel_name(365.0), "S0.365,000000nm");
    }
}
