//! A light variation's `illuminant_files`: measured spectral power distributions drawn per frame
//! beside the named CIE illuminants. Each file is read once at load (so `--check` refuses a
//! missing, unreadable or short one before any frame) and scaled to unit luminance, as the named
//! illuminants are, so `intensity` means the same whichever the frame draws.

use super::base::{Base, LightRef};
use crate::config::{EmitterConfig, SpectrumConfig};
use crate::error::InputError;
use crate::spectrum::{table, Curve};
use std::path::{Path, PathBuf};

/// One illuminant file, ready to put in a frame's scene.
#[derive(Clone, Debug, PartialEq)]
pub struct IlluminantFile {
    /// As written in the dataset config (for the frame's JSON: no absolute path there).
    pub name: String,
    /// Absolute, so the frame's scene finds it from anywhere.
    pub path: String,
    /// ∫ S ȳ dλ / ∫ ȳ dλ of the file's first column.
    pub luminance: f32,
}

impl IlluminantFile {
    /// The file's spectrum at unit luminance, times `intensity`.
    pub fn spectrum(&self, intensity: f32) -> SpectrumConfig {
        SpectrumConfig::Scaled(
            intensity / self.luminance,
            Box::new(SpectrumConfig::File {
                path: self.path.clone(),
                column: None,
            }),
        )
    }
}

/// Every light variation's files (one list per entry of `lights`, empty where it has none),
/// checked: readable spectrum tables of finite, non-negative values, covering the scene's
/// spectral range, of positive luminance, on a light that takes a spectrum.
pub fn load(base: &Base) -> Result<Vec<Vec<IlluminantFile>>, InputError> {
    let dir = base.file.parent().unwrap_or(Path::new("."));
    let range = base.scene.spectral.range;
    let mut all = Vec::new();
    for (k, l) in base.config.lights.iter().enumerate() {
        let mut list = Vec::new();
        let field = format!("lights[{k}].illuminant_files");
        if !l.illuminant_files.is_empty() {
            if l.temperature.is_some() {
                return Err(base
                    .err(
                        &field,
                        "a light takes `temperature` or illuminants, not both",
                    )
                    .hint("drop `temperature` or the illuminants"));
            }
            if let LightRef::Emitter(e) = base.light(&l.target, &format!("lights[{k}].target"))? {
                if matches!(base.scene.emitters[e], EmitterConfig::Envmap { .. }) {
                    return Err(base
                        .err(&field, "an environment map's spectrum is its image")
                        .hint("vary its `intensity` only"));
                }
            }
        }
        for (j, name) in l.illuminant_files.iter().enumerate() {
            let f = format!("{field}[{j}]");
            let full = dir.join(name);
            let luminance = read(&full, range).map_err(|m| {
                base.err(&f, format!("`{}`: {m}", full.display())).hint(format!(
                    "give a spectrum table (columns: nm, value; as `File(path: ..)` in a scene reads) relative to the dataset config, covering the scene's spectral range {}–{} nm (extend its ends, or narrow the scene's `spectral.range`)",
                    range.0, range.1
                ))
            })?;
            list.push(IlluminantFile {
                name: name.clone(),
                path: super::plan::absolute(&full),
                luminance,
            });
        }
        all.push(list);
    }
    Ok(all)
}

/// The files every light variation reads, for `dataset.json`'s hashes.
pub fn paths(base: &Base) -> Vec<PathBuf> {
    let dir = base.file.parent().unwrap_or(Path::new("."));
    let files = base.config.lights.iter().flat_map(|l| &l.illuminant_files);
    files.map(|f| dir.join(f)).collect()
}

/// The luminance of the table at `path`, or why it cannot light a frame over `range` nm.
fn read(path: &Path, range: (f32, f32)) -> Result<f32, String> {
    use crate::io::input_file::{self, Kind};
    let bytes = input_file::read(path, Kind::Spectrum)?;
    let text = String::from_utf8(bytes).map_err(|_| "is not UTF-8 text".to_string())?;
    let t = table::parse(&text).map_err(|e| e.to_string())?;
    let v = t
        .values
        .first()
        .ok_or("has no value column (columns: nm, value)")?;
    let wl = &t.wavelengths;
    let (lo, hi) = (wl[0], *wl.last().expect("a table has rows"));
    // A spectrum ending inside the range would be held at its end value there: not a
    // measurement, so it is refused rather than extrapolated.
    if lo > range.0 as f64 || hi < range.1 as f64 {
        return Err(format!(
            "covers {lo}–{hi} nm, not the scene's spectral range {}–{} nm",
            range.0, range.1
        ));
    }
    if let Some(i) = v.iter().position(|x| !x.is_finite() || *x < 0.0) {
        return Err(format!(
            "the value at {} nm is {} (an emission spectrum is finite and non-negative)",
            wl[i], v[i]
        ));
    }
    let y = Curve::from_samples(wl, v).luminance();
    if !(y > 0.0 && y.is_finite()) {
        return Err(format!(
            "has luminance {y} (no emission the eye sees), so it cannot be scaled to unit luminance"
        ));
    }
    Ok(y)
}
