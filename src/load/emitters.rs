//! Emitters that are not attached to a shape, from the config, with their parameters checked.

use super::check::{check, finite3};
use super::geometry::transform;
use crate::config::{EmitterConfig, SpectrumConfig};
use crate::emitter::Emitter;
use crate::emitter::{EnvMap, Spot};
use crate::error::InputError;
use crate::load::{spectrum_ctx, Role};
use crate::texture;
use glam::{Mat3, Vec3};
use std::path::Path;

/// Builds emitter `e`, called `field` in errors; spectra are checked over `range`, image paths
/// are relative to the scene `file`.
pub fn emitter(
    e: &EmitterConfig,
    file: &Path,
    field: &str,
    range: (f32, f32),
    warnings: &mut Vec<String>,
) -> Result<Emitter, InputError> {
    let mut emission = |s: &SpectrumConfig, name: &str| {
        s.resolve(
            Role::Emission,
            &spectrum_ctx(file, &format!("{field}.{name}"), range),
            warnings,
        )
    };
    Ok(match e {
        EmitterConfig::Point {
            position,
            intensity,
            ..
        } => {
            check(
                finite3(*position),
                file,
                &format!("{field}.position"),
                "the position must be finite",
            )?;
            super::extent::check_point(
                Vec3::from(*position),
                file,
                &format!("{field}.position"),
                "the light",
            )?;
            Emitter::Point {
                position: Vec3::from(*position),
                intensity: emission(intensity, "intensity")?,
            }
        }
        EmitterConfig::Constant { radiance } => Emitter::Constant {
            radiance: emission(radiance, "radiance")?,
        },
        EmitterConfig::Spot {
            intensity,
            cutoff_angle,
            beam_width,
            to_world,
            ..
        } => {
            let cutoff = *cutoff_angle;
            check(
                cutoff.is_finite() && cutoff > 0.0 && cutoff <= 90.0,
                file,
                &format!("{field}.cutoff_angle"),
                format!("cutoff_angle {cutoff} must lie in (0, 90] degrees"),
            )?;
            let beam = beam_width.unwrap_or(0.75 * cutoff);
            check(
                beam.is_finite() && beam >= 0.0 && beam <= cutoff,
                file,
                &format!("{field}.beam_width"),
                format!("beam_width {beam} must lie in [0, cutoff_angle = {cutoff}] degrees"),
            )?;
            let t = transform(to_world, file, &format!("{field}.to_world"))?;
            super::extent::check_point(
                t.m.w_axis.truncate(),
                file,
                &format!("{field}.to_world"),
                "the light",
            )?;
            Emitter::Spot(Spot::new(
                &t,
                emission(intensity, "intensity")?,
                cutoff,
                beam,
            ))
        }
        EmitterConfig::Directional {
            irradiance,
            direction,
            to_world,
            ..
        } => {
            let d = match direction {
                Some(d) => {
                    if !to_world.is_empty() {
                        return Err(InputError::new(
                            file,
                            "give either `direction` or `to_world`, not both",
                        )
                        .field(field.to_string())
                        .hint("drop `to_world`: `direction` alone says where the light points"));
                    }
                    let v = Vec3::from(*d);
                    check(
                        finite3(*d) && v.length_squared() > 0.0,
                        file,
                        &format!("{field}.direction"),
                        format!("the direction {d:?} must be finite and non-zero"),
                    )?;
                    v
                }
                None => transform(to_world, file, &format!("{field}.to_world"))?.vector(Vec3::Z),
            };
            // A huge finite vector's squared length overflows: its normalisation would be NaN.
            check(
                d.normalize_or_zero() != Vec3::ZERO,
                file,
                field,
                format!("the direction {d} cannot be normalised (too long or too short)"),
            )?;
            Emitter::Directional {
                direction: d.normalize(),
                irradiance: emission(irradiance, "irradiance")?,
            }
        }
        EmitterConfig::Envmap {
            filename,
            scale,
            colour_space,
            to_world,
            ..
        } => {
            let gamut = match colour_space {
                Some(name) => crate::load::colour_space::by_name(
                    file,
                    &format!("{field}.colour_space"),
                    name,
                )?,
                None => crate::spectrum::gamut::Gamut::Srgb,
            };
            check(
                scale.is_finite() && *scale >= 0.0,
                file,
                &format!("{field}.scale"),
                format!("scale {scale} must be finite and ≥ 0"),
            )?;
            let t = transform(to_world, file, &format!("{field}.to_world"))?;
            let m = Mat3::from_mat4(t.m);
            let rotation = (m * m.transpose()).abs_diff_eq(Mat3::IDENTITY, 1e-4);
            check(
                rotation,
                file,
                &format!("{field}.to_world"),
                "an environment map's to_world may only rotate it (no scale or shear)",
            )?;
            let full = file.parent().unwrap_or(Path::new(".")).join(filename);
            let err = |m: String| {
                InputError::new(file, m)
                    .field(format!("{field}.filename"))
                    .hint("an environment map is an equirectangular EXR or PNG image, twice as wide as high")
            };
            let img = texture::load_rgb(&full, false).map_err(|m| {
                let hint = "image paths are relative to the scene file";
                super::inputs::missing_hint(err(m), &full, hint)
            })?;
            // Equirectangular: 360° across, 180° down, so twice as wide as high.
            let (mw, mh) = EnvMap::MIN_SIZE;
            let (mw, mh) = (mw.max(2 * mh), mh);
            if img.width != 2 * img.height || img.height < mh {
                return Err(err(format!(
                    "`{}` is {}×{} pixels; an environment map must be an equirectangular \
                     (latitude-longitude) image, twice as wide as high and at least {mw}×{mh}",
                    full.display(),
                    img.width,
                    img.height
                ))
                .hint("e.g. 2048×1024; crop or resample the image to a 2:1 aspect ratio"));
            }
            if let Some(k) = img
                .pixels
                .iter()
                .position(|p| p.iter().any(|c| !c.is_finite()))
            {
                return Err(err(format!(
                    "`{}` has a non-finite value at pixel ({}, {})",
                    full.display(),
                    k % img.width,
                    k / img.width
                )));
            }
            let peak = img.pixels.iter().flatten().fold(0.0f32, |m, &c| m.max(c));
            if peak * scale > crate::config::MAX_EMISSION {
                return Err(err(format!(
                    "`{}`'s brightest texel, {peak:e}, times scale {scale} exceeds the {:e} prism accepts",
                    full.display(),
                    crate::config::MAX_EMISSION
                ))
                .hint("the radiance would overflow 32-bit floats while the map is sampled; scale the map down"));
            }
            let negative = img
                .pixels
                .iter()
                .filter(|p| p.iter().any(|&c| c < 0.0))
                .count();
            let mut img = img;
            if negative > 0 {
                warnings.push(format!(
                    "{}: {field}.filename: {negative} pixels of `{}` have negative components, read as 0",
                    file.display(),
                    full.display()
                ));
                for p in &mut img.pixels {
                    *p = p.map(|c| c.max(0.0));
                }
            }
            // Texels are RGB × D65 (EnvMap::new_in): past the D65 table they follow its
            // blackbody tail, a chosen extension the user should know about.
            if let Some((a, b)) = crate::spectrum::data::named_illuminant("D65")
                .and_then(|d| d.support())
                .filter(|&(a, b)| a > range.0 || b < range.1)
            {
                let (k, end) = (crate::emitter::TAIL_KELVIN, crate::emitter::TAIL_END);
                let mut parts = Vec::new();
                if b < range.1 {
                    parts.push(format!("past {b} nm it continues as a {k} K blackbody scaled to D65 at {b} nm (a chosen tail, not data; 0 past {end} nm)"));
                }
                if a > range.0 {
                    parts.push(format!("below {a} nm it is 0"));
                }
                warnings.push(format!(
                    "{}: {field}.filename: an environment map's radiance is its RGB × D65, whose data cover {a}–{b} nm only: {} in the render range {}–{} nm",
                    file.display(),
                    parts.join("; "),
                    range.0,
                    range.1
                ));
            }
            Emitter::Envmap(Box::new(EnvMap::new_in(gamut, &img, *scale, m)))
        }
    })
}

#[cfg(test)]
mod tests {
    use crate::math::portable;
    use crate::spectrum::Wavelengths;
    use glam::Vec3;

    /// Radiance HDR and OpenEXR maps of the same linear pixels load alike. The pixels are chosen
    /// exactly representable in RGBE (8-bit mantissas sharing an exponent), so the two must agree
    /// to f32 rounding (1e-6 relative).
    #[test]
    fn hdr_and_exr_maps_load_alike() {
        let dir = std::env::temp_dir().join(format!("prism-hdr-exr-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let choices = [
            [0.75, 0.5, 0.25],
            [2.0, 1.0, 0.5],
            [0.125, 0.25, 0.5],
            [6.0, 3.0, 1.5],
        ];
        let (w, h) = (8, 4);
        let pixel = |i: usize, j: usize| choices[(i * 3 + j * 5) % choices.len()];
        let rgb: Vec<image::Rgb<f32>> = (0..h)
            .flat_map(|j| (0..w).map(move |i| image::Rgb(pixel(i, j))))
            .collect();
        let f = std::fs::File::create(dir.join("map.hdr")).unwrap();
        image::codecs::hdr::HdrEncoder::new(std::io::BufWriter::new(f))
            .encode(&rgb, w, h)
            .unwrap();
        exr::prelude::write_rgb_file(dir.join("map.exr"), w, h, |i, j| {
            let p = pixel(i, j);
            (p[0], p[1], p[2])
        })
        .unwrap();
        let load = |name: &str| {
            let text = format!(
                "(film: (width: 2, height: 2), emitters: [Envmap(filename: \"{name}\")], outputs: (bands: 0))"
            );
            let job = crate::load::load_str(&text, &dir.join("scene.ron")).unwrap();
            job.scene.emitters[0].clone()
        };
        let (hdr, exr) = (load("map.hdr"), load("map.exr"));
        let wl = Wavelengths::<4> {
            lambda: [420.0, 510.0, 600.0, 690.0],
            pdf: [1.0; 4],
        };
        for k in 0..200 {
            let z = 1.0 - 2.0 * (k as f32 + 0.5) / 200.0;
            let phi = k as f32 * 2.399_963;
            let s = (1.0 - z * z).sqrt();
            let d = Vec3::new(s * portable::cos(phi), z, s * portable::sin(phi));
            let (a, b) = (hdr.le_env(d, &wl), exr.le_env(d, &wl));
            for l in 0..4 {
                assert!(
                    (a[l] - b[l]).abs() <= 1e-6 * b[l].abs(),
                    "{d}: HDR {} vs EXR {}",
                    a[l],
                    b[l]
                );
            }
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}
