//! Spectral channel names (Fichet et al. 2021, `S0.<λ>nm`) that sort in wavelength order.
//!
//! OpenEXR stores channels sorted by name, and readers (colour-science's
//! `read_spectral_image_Fichet2021`, OpenImageIO) return them in that order: `S0.1025,000000nm`
//! would come before `S0.325,000000nm`. When a sensor's spectral channels span integer widths,
//! every wavelength is zero-padded to the widest (`S0.0325,000000nm`), which still parses as the
//! same number (colour-science's pattern `\d*,?\d*`); with one width (a visible-only render) the
//! names are unchanged. With equal widths and six decimals, name order is wavelength order.

use super::{ChannelName, Sensor};

/// `S0.<nm>nm` with the integer part zero-padded to `digits` characters.
pub fn padded_name(nm: f32, digits: usize) -> String {
    let text = format!("{nm:.6}");
    let int = text.find('.').unwrap_or(text.len());
    let pad = "0".repeat(digits.saturating_sub(int));
    format!("S0.{pad}{}nm", text.replace('.', ","))
}

/// Characters before the decimal point of `nm` as the name writes it.
fn integer_digits(nm: f32) -> usize {
    let text = format!("{nm:.6}");
    text.find('.').unwrap_or(text.len())
}

impl Sensor {
    /// The integer width every spectral channel name is padded to (module docs).
    pub fn name_digits(&self) -> usize {
        let even = self
            .bands()
            .into_iter()
            .flat_map(|b| (0..b.count).map(move |k| b.center(k)));
        let responses = self.layers.responses.iter().filter_map(|n| match n {
            ChannelName::Spectral(c) => Some(*c),
            ChannelName::Layer(_) => None,
        });
        even.chain(responses).map(integer_digits).max().unwrap_or(0)
    }

    /// The channel name of even band `k`.
    pub fn band_name(&self, k: u32) -> String {
        let b = self.bands().expect("band_name needs even bands");
        padded_name(b.center(k), self.name_digits())
    }

    /// The channel name of a response channel.
    pub fn response_name(&self, name: &ChannelName) -> String {
        match name {
            ChannelName::Spectral(c) => padded_name(*c, self.name_digits()),
            ChannelName::Layer(_) => name.text(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::{Bands, Layers, Observer, Response, Shape};
    use super::*;

    #[test]
    fn names_pad_only_across_widths() {
        assert_eq!(padded_name(550.0, 3), "S0.550,000000nm");
        assert_eq!(padded_name(325.0, 4), "S0.0325,000000nm");
        assert_eq!(padded_name(1025.0, 4), "S0.1025,000000nm");
        // Visible-only: today's names.
        let vis = Sensor::new(Some(Bands {
            lo: 360.0,
            hi: 830.0,
            count: 47,
        }));
        assert_eq!(vis.band_name(0), "S0.365,000000nm");
        // 300–1100 nm: every name padded to 4 digits, so name order is wavelength order.
        let wide = Sensor::new(Some(Bands {
            lo: 300.0,
            hi: 1100.0,
            count: 16,
        }));
        let names: Vec<String> = (0..16).map(|k| wide.band_name(k)).collect();
        assert_eq!(names[0], "S0.0325,000000nm");
        assert_eq!(names[15], "S0.1075,000000nm");
        let mut sorted = names.clone();
        sorted.sort();
        assert_eq!(sorted, names);
        // A NIR response past 1000 nm pads the visible bands too.
        let r = Response {
            shape: Shape::Box {
                lo: 1000.0,
                hi: 1050.0,
            },
            scale: 0.02,
        };
        let layers = Layers {
            responses: vec![ChannelName::Spectral(1025.0)],
            ..Layers::default()
        };
        let s = Sensor::with(Observer::Cie1931, vis.bands(), vec![r], layers);
        assert_eq!(s.band_name(0), "S0.0365,000000nm");
        assert_eq!(s.response_name(&s.layers.responses[0]), "S0.1025,000000nm");
    }
}
