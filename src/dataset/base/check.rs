//! The checks of a dataset config against its base scene (names the scene lacks, inverted or
//! out-of-range ranges, missing files), made at load, before any frame.

use super::{Base, LightRef};
use crate::config::{EmitterConfig, MaterialConfig};
use crate::dataset::config::{LookAtVariation, ReflectanceSource};
use crate::dataset::library;
use crate::error::InputError;
use std::path::Path;

impl Base {
    /// Every check of the config; the first failing one is the error.
    pub(super) fn check(&self) -> Result<(), InputError> {
        let c = &self.config;
        if c.frames == 0 {
            return Err(self.err("frames", "a dataset needs at least one frame"));
        }
        if let Some(spp) = &c.outputs.spp {
            if let Some((sub, message)) = spp.problem(self.scene.sampler.kind) {
                return Err(self.err(&format!("outputs.spp{sub}"), message));
            }
        }
        if matches!(c.outputs.resolution, Some((w, h)) if w == 0 || h == 0 || w > 1 << 15 || h > 1 << 15)
        {
            return Err(self.err(
                "outputs.resolution",
                "the resolution must be between 1×1 and 32768×32768",
            ));
        }
        let mut splits: Vec<(&String, &(u32, u32))> = c.splits.iter().collect();
        splits.sort_by_key(|s| s.1);
        for (k, (name, &(lo, hi))) in splits.iter().enumerate() {
            let field = format!("splits.{name}");
            if lo >= hi || hi > c.frames {
                return Err(self
                    .err(
                        &field,
                        format!(
                            "the range ({lo}, {hi}) is not a range of frames lo..hi within 0..{}",
                            c.frames
                        ),
                    )
                    .hint("give (lo, hi) with lo < hi ≤ frames (hi is not included)"));
            }
            if let Some((other, &(_, prev_hi))) = k.checked_sub(1).map(|j| splits[j]) {
                if lo < prev_hi {
                    return Err(self
                        .err(
                            &field,
                            format!("the range ({lo}, {hi}) overlaps split \"{other}\""),
                        )
                        .hint("splits must not share frames"));
                }
            }
        }
        if !c.outputs.exposure.is_finite() {
            return Err(self.err("outputs.exposure", "the exposure must be finite"));
        }
        if let Some(cam) = &c.camera {
            match &cam.look_at {
                Some(LookAtVariation::Shell {
                    radius,
                    elevation,
                    azimuth,
                    ..
                }) => {
                    self.range("camera.look_at.radius", *radius, 1e-6, f32::MAX, "radius")?;
                    self.range(
                        "camera.look_at.elevation",
                        *elevation,
                        -89.9,
                        89.9,
                        "elevation in degrees (the up vector is +y)",
                    )?;
                    self.range(
                        "camera.look_at.azimuth",
                        *azimuth,
                        -720.0,
                        720.0,
                        "azimuth in degrees",
                    )?;
                }
                Some(LookAtVariation::Poses(p)) if p.is_empty() => {
                    return Err(self.err("camera.look_at", "Poses needs at least one pose"));
                }
                _ => {}
            }
            if let Some(f) = cam.fov {
                self.range("camera.fov", f, 1e-3, 179.9, "field of view in degrees")?;
            }
            if !(cam.roll.is_finite() && (0.0..=180.0).contains(&cam.roll)) {
                return Err(self.err(
                    "camera.roll",
                    "roll is the largest roll angle in degrees, in [0, 180]",
                ));
            }
            if cam.max_attempts == 0 {
                return Err(self.err("camera.max_attempts", "max_attempts must be at least 1"));
            }
            for (i, n) in cam.keep_in_view.iter().enumerate() {
                self.shape(n, &format!("camera.keep_in_view[{i}]"))?;
            }
        }
        for (i, l) in c.lights.iter().enumerate() {
            let f = format!("lights[{i}]");
            let r = self.light(&l.target, &format!("{f}.target"))?;
            if let Some(k) = l.intensity {
                self.range(&format!("{f}.intensity"), k, 0.0, f32::MAX, "intensity")?;
            }
            if let Some(t) = l.temperature {
                self.range(
                    &format!("{f}.temperature"),
                    t,
                    100.0,
                    1e6,
                    "temperature in K",
                )?;
                if let LightRef::Emitter(e) = r {
                    if matches!(self.scene.emitters[e], EmitterConfig::Envmap { .. }) {
                        return Err(self
                            .err(
                                &format!("{f}.temperature"),
                                "an environment map has no colour temperature",
                            )
                            .hint("vary its `intensity` only"));
                    }
                }
            }
            self.check_illuminants(l, r, &f)?;
        }
        if let Some(e) = &c.envmap {
            let r = self.light(&e.target, "envmap.target")?;
            if !matches!(r, LightRef::Emitter(i) if matches!(self.scene.emitters[i], EmitterConfig::Envmap { .. }))
            {
                return Err(self
                    .err(
                        "envmap.target",
                        format!("\"{}\" is not an Envmap emitter", e.target),
                    )
                    .hint("name the scene's environment map as emitters[i]"));
            }
            let dir = self.file.parent().unwrap_or(Path::new("."));
            for (i, f) in e.files.iter().enumerate() {
                if !dir.join(f).is_file() {
                    return Err(self
                        .err(
                            &format!("envmap.files[{i}]"),
                            format!("`{}` does not exist", dir.join(f).display()),
                        )
                        .hint("paths are relative to the dataset config"));
                }
            }
        }
        if let Some(v) = &c.sensor {
            self.check_sensor(v)?;
        }
        for (i, m) in c.materials.iter().enumerate() {
            let f = format!("materials[{i}]");
            let mat = self.material(&m.target, &format!("{f}.target"))?;
            if let Some(src) = &m.reflectance {
                let (set, only) = match src {
                    ReflectanceSource::Library(s) => (s, &[][..]),
                    ReflectanceSource::Patches(s, p) => (s, &p[..]),
                };
                let t = library::set(set).ok_or_else(|| {
                    self.err(
                        &format!("{f}.reflectance"),
                        format!("no reflectance set \"{set}\""),
                    )
                    .hint(format!("the sets are: {}", library::names().join(", ")))
                })?;
                for p in only {
                    if !t.columns.contains(p) {
                        return Err(self
                            .err(
                                &format!("{f}.reflectance"),
                                format!("set \"{set}\" has no entry \"{p}\""),
                            )
                            .hint(format!("its entries are: {}", t.columns.join(", "))));
                    }
                }
                if matches!(src, ReflectanceSource::Patches(_, p) if p.is_empty()) {
                    return Err(self.err(
                        &format!("{f}.reflectance"),
                        "Patches needs at least one entry",
                    ));
                }
                if crate::dataset::apply::reflectance_slot(&mut mat.clone()).is_none() {
                    return Err(self
                        .err(
                            &format!("{f}.reflectance"),
                            format!("material \"{}\" has no base reflectance to vary", m.target),
                        )
                        .hint(format!(
                            "reflectances vary on {}",
                            MaterialConfig::WITH_BASE_REFLECTANCE
                        )));
                }
            }
            if let Some(r) = m.roughness {
                self.range(&format!("{f}.roughness"), r, 1e-4, 1.0, "roughness alpha")?;
                if !crate::dataset::apply::set_roughness(&mut mat.clone(), 0.1) {
                    return Err(self
                        .err(
                            &format!("{f}.roughness"),
                            format!("material \"{}\" has no roughness", m.target),
                        )
                        .hint(format!(
                            "roughness varies on {}",
                            MaterialConfig::WITH_ROUGHNESS
                        )));
                }
            }
            if let Some(r) = m.ior {
                self.range(&format!("{f}.ior"), r, 1e-3, 10.0, "index of refraction")?;
                if !crate::dataset::apply::set_ior(&mut mat.clone(), 1.5) {
                    return Err(self
                        .err(
                            &format!("{f}.ior"),
                            format!("material \"{}\" has no interior IOR", m.target),
                        )
                        .hint(format!(
                            "the IOR varies on {}",
                            MaterialConfig::WITH_INT_IOR
                        )));
                }
            }
        }
        for (i, s) in c.swaps.iter().enumerate() {
            let f = format!("swaps[{i}]");
            self.shape(&s.shape, &format!("{f}.shape"))?;
            if s.materials.is_empty() {
                return Err(self.err(
                    &format!("{f}.materials"),
                    "a swap needs at least one material",
                ));
            }
            for (j, m) in s.materials.iter().enumerate() {
                self.material(m, &format!("{f}.materials[{j}]"))?;
            }
        }
        for (i, s) in c.objects.subsets.iter().enumerate() {
            let f = format!("objects.subsets[{i}]");
            for (j, n) in s.shapes.iter().enumerate() {
                self.shape(n, &format!("{f}.shapes[{j}]"))?;
            }
            let (lo, hi) = s.shown;
            if lo > hi {
                return Err(self
                    .err(
                        &format!("{f}.shown"),
                        format!("the range ({lo}, {hi}) is inverted"),
                    )
                    .hint(format!("write it as ({hi}, {lo})")));
            }
            if hi as usize > s.shapes.len() {
                return Err(self.err(
                    &format!("{f}.shown"),
                    format!("cannot show {hi} of {} shapes", s.shapes.len()),
                ));
            }
        }
        if let Some(p) = &c.objects.place {
            self.shape(&p.support, "objects.place.support")?;
            for (j, n) in p.shapes.iter().enumerate() {
                let k = self.shape(n, &format!("objects.place.shapes[{j}]"))?;
                if n == &p.support {
                    return Err(self.err(
                        &format!("objects.place.shapes[{j}]"),
                        "a shape cannot stand on itself",
                    ));
                }
                let _ = k;
            }
            if let Some(y) = p.yaw {
                self.range("objects.place.yaw", y, -720.0, 720.0, "yaw in degrees")?;
            }
            if let Some(s) = p.scale {
                self.range("objects.place.scale", s, 1e-4, 1e4, "scale factor")?;
            }
            if !(p.gap.is_finite() && p.gap >= 0.0) {
                return Err(self.err("objects.place.gap", "gap must be ≥ 0"));
            }
            if p.max_attempts == 0 {
                return Err(self.err(
                    "objects.place.max_attempts",
                    "max_attempts must be at least 1",
                ));
            }
        }
        Ok(())
    }

    /// The sensor variation: every file there and a sensor file, the exposure a finite range.
    fn check_sensor(&self, v: &crate::dataset::config::SensorVariation) -> Result<(), InputError> {
        if let Some(files) = &v.files {
            if files.is_empty() {
                return Err(self
                    .err("sensor.files", "the list of sensor files is empty")
                    .hint("list at least one sensor file (e.g. \"../sensors/cie1931.ron\"), or leave `files` out to keep the scene's sensor"));
            }
            let dir = self.file.parent().unwrap_or(Path::new("."));
            for (i, f) in files.iter().enumerate() {
                let p = dir.join(f);
                if !p.is_file() {
                    return Err(self
                        .err(
                            &format!("sensor.files[{i}]"),
                            format!("`{}` does not exist", p.display()),
                        )
                        .hint("paths are relative to the dataset config (configs/sensors/ holds presets)"));
                }
                crate::load::sensor::read_file(&p)?;
            }
        }
        if let Some(e) = v.exposure {
            self.range("sensor.exposure", e, -64.0, 64.0, "exposure in stops")?;
        }
        Ok(())
    }
}

impl Base {
    /// A light's `illuminants`: known CIE names, not beside `temperature`, not on an envmap.
    fn check_illuminants(
        &self,
        l: &crate::dataset::config::LightVariation,
        r: LightRef,
        f: &str,
    ) -> Result<(), InputError> {
        if l.illuminants.is_empty() {
            return Ok(());
        }
        let field = format!("{f}.illuminants");
        if l.temperature.is_some() {
            return Err(self
                .err(
                    &field,
                    "a light takes `temperature` or `illuminants`, not both",
                )
                .hint("drop one of them"));
        }
        if let LightRef::Emitter(e) = r {
            if matches!(self.scene.emitters[e], EmitterConfig::Envmap { .. }) {
                return Err(self
                    .err(&field, "an environment map's spectrum is its image")
                    .hint("vary its `intensity` only"));
            }
        }
        let known = crate::spectrum::data::illuminant_names();
        for (j, n) in l.illuminants.iter().enumerate() {
            if !known.contains(&n.as_str()) {
                return Err(self
                    .err(
                        &format!("{field}[{j}]"),
                        format!("unknown illuminant \"{n}\""),
                    )
                    .hint(format!("the CIE illuminants are: {}", known.join(", "))));
            }
        }
        Ok(())
    }
}
