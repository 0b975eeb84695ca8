//! The `sensor:` section of a scene (or a sensor file of its own): what the camera records.
//!
//! ```ron
//! sensor: File("../configs/sensors/nikon_d810.ron")   // relative to the scene file
//! sensor: (
//!     observer: Cie1931,                 // or Cie1964
//!     xyz: true,
//!     rgb: [Srgb, Rec2020, AcesCg],      // Srgb, Rec2020, DisplayP3, Aces2065, AcesCg
//!     bands: [
//!         Even(count: 31, range: (400, 710)),
//!         Boxes([(840, 860)]),
//!         Filter(name: "nir", curve: Gaussian(centre: 850, fwhm: 40)),
//!     ],
//!     camera: (curves: Named("nikon_d810"), white_balance: Illuminant("D65"),
//!              exposure: (iso: 100, shutter: 0.01, f_number: 4)),
//!     raw: (pattern: Rggb, bits: 14),     // the chip's mosaic with noise: channel `raw.Y`
//! )
//! ```

use super::SpectrumConfig;
pub use crate::sensor::raw::{BayerPattern, Gain};
use crate::sensor::{Observer, RgbSpace};
use serde::de::value::MapAccessDeserializer;
use serde::de::{self, MapAccess, SeqAccess, Visitor};
use serde::{Deserialize, Serialize};
use std::fmt;

/// `sensor:` in a scene: a file holding a `SensorConfig`, or one written inline.
///
/// Read with `deserialize_any` rather than serde's untagged enums, which buffer the value and
/// lose both RON's error positions and some of its syntax (`Even()`): an inline sensor is a
/// RON struct (a map), `File("x.ron")` a one-element tuple, `()` every default.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum SensorField {
    File(SensorFile),
    Inline(Box<SensorConfig>),
    /// `sensor: ()`: every default.
    Empty(()),
}

/// One of a scene's further sensors: `(name: "nikon", sensor: File("nikon.ron"))`; `name`
/// prefixes its channels (`nikon.camera.R`) and header keys.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NamedSensor {
    pub name: String,
    pub sensor: SensorField,
}

/// `File("path.ron")`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum SensorFile {
    File(String),
}

impl<'de> Deserialize<'de> for SensorField {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(FieldVisitor)
    }
}

struct FieldVisitor;

impl<'de> Visitor<'de> for FieldVisitor {
    type Value = SensorField;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(
            f,
            "File(\"sensor.ron\") or an inline sensor (observer: ..., rgb: [...], bands: [...])"
        )
    }

    fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<SensorField, A::Error> {
        let cfg = SensorConfig::deserialize(MapAccessDeserializer::new(map))?;
        Ok(SensorField::Inline(Box::new(cfg)))
    }

    fn visit_unit<E: de::Error>(self) -> Result<SensorField, E> {
        Ok(SensorField::Empty(()))
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<SensorField, A::Error> {
        let path: String = seq
            .next_element()?
            .ok_or_else(|| de::Error::custom("File(...) needs the sensor file's path"))?;
        if seq.next_element::<de::IgnoredAny>()?.is_some() {
            return Err(de::Error::custom("File(...) takes one path"));
        }
        Ok(SensorField::File(SensorFile::File(path)))
    }

    fn visit_newtype_struct<D: serde::Deserializer<'de>>(
        self,
        d: D,
    ) -> Result<SensorField, D::Error> {
        Ok(SensorField::File(SensorFile::File(String::deserialize(d)?)))
    }
}

/// What the sensor records. Every part is optional; the defaults give prism's classic output
/// (CIE 1931 XYZ, linear sRGB, 10 nm bands over the spectral range).
///
/// ```ron
/// (observer: Cie1964, rgb: [Srgb], bands: [])
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SensorConfig {
    /// `Cie1931` (default) or `Cie1964`: the X, Y, Z channels and every RGB space's source.
    pub observer: Observer,
    /// The X, Y, Z channels. Default true.
    pub xyz: bool,
    /// RGB spaces, one layer each: `Srgb` (channels R, G, B), `Rec2020` (`rec2020.R` …),
    /// `DisplayP3` (`p3.`), `Aces2065` (`aces.`), `AcesCg` (`acescg.`). Default `[Srgb]`.
    pub rgb: Vec<RgbSpace>,
    /// Spectral channels; default `[Even()]` (10 nm bands over the spectral range); `[]` for none.
    pub bands: Option<Vec<BandConfig>>,
    /// A camera's colour channels (`camera.R/G/B`) and its colour-corrected RGB (`corrected.R/G/B`).
    pub camera: Option<CameraConfig>,
    /// What the sensor chip records (`raw.Y`: a Bayer mosaic of the camera's curves in DN, with
    /// shot, read and dark noise). Needs `camera` with `exposure`. Default none.
    pub raw: Option<RawConfig>,
}

impl Default for SensorConfig {
    fn default() -> Self {
        Self {
            observer: Observer::Cie1931,
            xyz: true,
            rgb: vec![RgbSpace::Srgb],
            bands: None,
            camera: None,
            raw: None,
        }
    }
}

/// A group of spectral channels.
///
/// ```ron
/// Even(count: 47, range: (360, 830))    // S0.<centre>nm, each the band's mean radiance
/// Boxes([(400, 500), (840, 860)])       // [lo, hi) nm each, named after their centres
/// Box(lo: 840, hi: 860, name: "nir")    // a named box: channel `nir.Y`
/// Filter(name: "nir", curve: Gaussian(centre: 850, fwhm: 40))   // ∫L f / ∫f: `nir.Y`
/// Filter(curve: File(path: "filters/f.txt"))                    // unnamed: S0.<centroid>nm
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum BandConfig {
    /// `count` bands (default: 10 nm wide) evenly over `range` (default: the spectral range).
    Even {
        #[serde(default)]
        count: Option<u32>,
        #[serde(default)]
        range: Option<(f32, f32)>,
    },
    Boxes(Vec<(f32, f32)>),
    Box {
        lo: f32,
        hi: f32,
        #[serde(default)]
        name: Option<String>,
    },
    /// A filter curve: `Tabulated`, `File` or `Gaussian` (a spectrum as scenes write it).
    Filter {
        #[serde(default)]
        name: Option<String>,
        curve: SpectrumConfig,
    },
}

/// `camera: (curves: Named("sony_ilce_7m3"), white_balance: Temperature(5000), exposure: (iso: 200, shutter: 0.005, f_number: 2.8))`
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraConfig {
    /// `Named("nikon_d810")` (one of the 19 in `spectra/cameras/`) or
    /// `Curves(r: File(path: "cam.txt", column: "r"), g: ..., b: ...)`.
    pub curves: CameraCurves,
    /// `Off` (default), `Illuminant("D65")` (any named illuminant) or `Temperature(5000)` (a
    /// blackbody, K).
    #[serde(default)]
    pub white_balance: WhiteBalance,
    /// Scales the camera layers by (ISO/100)·t·π/(4N²); default none (factor 1).
    #[serde(default)]
    pub exposure: Option<ExposureConfig>,
    /// The colour-corrected layer's RGB space. Default `Srgb`.
    #[serde(default = "srgb")]
    pub corrected: RgbSpace,
}

fn srgb() -> RgbSpace {
    RgbSpace::Srgb
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum CameraCurves {
    Named(String),
    Curves {
        r: SpectrumConfig,
        g: SpectrumConfig,
        b: SpectrumConfig,
    },
}

#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum WhiteBalance {
    #[default]
    Off,
    Illuminant(String),
    Temperature(f32),
}

/// `exposure: (iso: 100, shutter: 0.01, f_number: 8)`: ISO speed, shutter time in seconds,
/// f-number.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExposureConfig {
    pub iso: f32,
    pub shutter: f32,
    pub f_number: f32,
}

/// `raw: (...)`: the sensor chip's record, one value per pixel (`raw.Y`, uint32 DN) from the
/// camera curve of its Bayer site (src/sensor/raw.rs has the model). Every field has a default:
///
/// ```ron
/// raw: (
///     pattern: Rggb,            // Rggb, Bggr, Grbg, Gbrg: the 2×2 tile from the top-left pixel
///     pixel_pitch: 4.0,         // µm; the pixel's area is pitch²
///     quantum_efficiency: 0.5,  // at the peak of the most sensitive curve (curves are relative)
///     full_well: 30000,         // e⁻: the collected charge clips here
///     read_noise: 3.0,          // e⁻ rms (Gaussian)
///     dark_current: 0.1,        // e⁻/s per pixel (Poisson over the shutter time)
///     gain: UnityIso(400),      // DN per e⁻ = ISO / 400 (camera.exposure.iso); or PerElectron(0.25)
///     black_level: 512,         // DN added before quantisation
///     bits: 14,                 // DN clamp to [0, 2^bits − 1]
///     noise: true,              // false: the expected values, rounded (no random draws)
/// )
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RawConfig {
    pub pattern: BayerPattern,
    pub pixel_pitch: f64,
    pub quantum_efficiency: f64,
    pub full_well: f64,
    pub read_noise: f64,
    pub dark_current: f64,
    pub gain: Gain,
    pub black_level: f64,
    pub bits: u32,
    pub noise: bool,
}

impl Default for RawConfig {
    fn default() -> Self {
        Self {
            pattern: BayerPattern::Rggb,
            pixel_pitch: 4.0,
            quantum_efficiency: 0.5,
            full_well: 30000.0,
            read_noise: 3.0,
            dark_current: 0.1,
            gain: Gain::UnityIso(400.0),
            black_level: 512.0,
            bits: 14,
            noise: true,
        }
    }
}
