//! The rendered image: named float channels, one value per pixel, in row-major order (row 0 at
//! the top). The integrator fills it (through `sensor::FilmChannels::develop`); the output
//! writers read it. A plain image of the base floor: it knows no sensor.

pub mod aov;

pub use aov::{Aov, Dir, UintChannel};

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
        // Channel by channel first, a pass the compiler vectorises: the pixel-major count
        // strides across every channel (1% of a 16-spp Cornell render), for films that are
        // almost always clean.
        if self.channels.iter().all(|c| all_finite(&c.data)) {
            return 0;
        }
        let n = (self.width * self.height) as usize;
        (0..n)
            .filter(|&i| self.channels.iter().any(|c| !c.data[i].is_finite()))
            .count() as u64
    }

    /// The first value an output must not hold, with how many pixels hold one: NaN or ±inf
    /// in any float channel, except +inf in `distance` and `depth`, their documented "no
    /// surface". Returns (channel, x, y, value, pixels).
    pub fn first_nonfinite(&self) -> Option<(&str, u32, u32, f32, u64)> {
        let allowed = |c: &Channel, v: f32| {
            v == f32::INFINITY && (c.name.starts_with("distance.") || c.name.starts_with("depth."))
        };
        let bad = |c: &Channel, v: f32| !v.is_finite() && !allowed(c, v);
        // As in `nonfinite_pixels`: a clean film is told by a channel-major pass (a distance
        // or depth channel with its +inf "no surface" takes the pixel-major one).
        if self.channels.iter().all(|c| all_finite(&c.data)) {
            return None;
        }
        let n = (self.width * self.height) as usize;
        let count = (0..n)
            .filter(|&i| self.channels.iter().any(|c| bad(c, c.data[i])))
            .count() as u64;
        let i = (0..n).find(|&i| self.channels.iter().any(|c| bad(c, c.data[i])))?;
        let c = self.channels.iter().find(|c| bad(c, c.data[i]))?;
        let w = self.width as usize;
        Some((&c.name, (i % w) as u32, (i / w) as u32, c.data[i], count))
    }

    pub fn channel(&self, name: &str) -> Option<&[f32]> {
        self.channels
            .iter()
            .find(|c| c.name == name)
            .map(|c| c.data.as_slice())
    }
}

/// Whether every value is finite, branch-free over blocks so that it vectorises.
fn all_finite(data: &[f32]) -> bool {
    let mut blocks = data.chunks_exact(64);
    let clean = |b: &[f32]| b.iter().fold(true, |ok, v| ok & v.is_finite());
    blocks.all(clean) && clean(blocks.remainder())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The output rule: NaN or ±inf anywhere fails the render, bar the +inf that `depth` and
    /// `distance` write where no surface is.
    #[test]
    fn nonfinite_outputs_are_found_except_the_depth_background() {
        let ch = |name: &str, data: Vec<f32>| Channel {
            name: name.into(),
            data,
        };
        let mut film = Film {
            width: 2,
            height: 1,
            channels: vec![
                ch("R", vec![0.5, 1.0]),
                ch("depth.Z", vec![f32::INFINITY, 2.0]),
                ch("distance.Y", vec![3.0, f32::INFINITY]),
            ],
            band_centers: vec![],
            uint_channels: vec![],
            header: vec![],
        };
        assert_eq!(film.first_nonfinite(), None);
        film.channels[1].data[1] = f32::NAN;
        let (c, x, y, _, n) = film.first_nonfinite().unwrap();
        assert_eq!((c, x, y, n), ("depth.Z", 1, 0, 1));
        film.channels[0].data[0] = f32::NEG_INFINITY;
        let (c, x, y, v, n) = film.first_nonfinite().unwrap();
        assert_eq!((c, x, y, v, n), ("R", 0, 0, f32::NEG_INFINITY, 2));
        film.channels[1].data[0] = f32::NEG_INFINITY;
        film.channels[0].data[0] = 0.0;
        assert_eq!(film.first_nonfinite().unwrap().0, "depth.Z");
        let e = crate::output::check_finite(&film, std::path::Path::new("s.ron")).unwrap_err();
        assert_eq!(e.exit_code(), 2);
        assert!(e.to_string().contains("s.ron") && e.to_string().contains("depth.Z"));
    }

    /// The channel-major pass finds a bad value at every place: the blocks of 64, their
    /// edges and the remainder (130 values: two blocks and 2 over).
    #[test]
    fn a_clean_film_is_told_from_one_bad_value_anywhere() {
        for at in [
            None,
            Some(0),
            Some(63),
            Some(64),
            Some(127),
            Some(128),
            Some(129),
        ] {
            for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
                let mut data = vec![1.0f32; 130];
                if let Some(i) = at {
                    data[i] = bad;
                }
                assert_eq!(all_finite(&data), at.is_none(), "{bad} at {at:?}");
                let film = Film {
                    width: 13,
                    height: 10,
                    channels: vec![Channel {
                        name: "G".into(),
                        data,
                    }],
                    band_centers: vec![],
                    uint_channels: vec![],
                    header: vec![],
                };
                assert_eq!(film.nonfinite_pixels(), at.is_some() as u64);
                let found = film
                    .first_nonfinite()
                    .map(|(_, x, y, _, n)| (x + 13 * y, n));
                assert_eq!(found, at.map(|i| (i as u32, 1)));
            }
        }
    }

    #[test]
    fn fichet_channel_names() {
        assert_eq!(spectral_channel_name(550.0), "S0.550,000000nm");
        assert_eq!(spectral_channel_name(365.0), "S0.365,000000nm");
    }
}
