//! The dataset loaded once per process: its config, the base scene, and every check a mistake
//! in the config can trip (names the scene lacks, inverted ranges), made before any frame.

use super::config::{DatasetConfig, LookAtVariation, Range, ReflectanceSource};
use super::library;
use crate::config::sensor::{SensorField, SensorFile};
use crate::config::{EmitterConfig, MaterialConfig, SceneConfig};
use crate::error::{Error, InputError};
use glam::Vec3;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A dataset ready to plan frames from.
pub struct Base {
    pub config: DatasetConfig,
    /// The dataset config file.
    pub file: PathBuf,
    /// The base scene file and its parsed config.
    pub scene_file: PathBuf,
    pub scene: SceneConfig,
    /// World bounds of each shape of the base scene (min, max).
    pub bounds: Vec<(Vec3, Vec3)>,
    /// Shape index by name.
    pub names: BTreeMap<String, usize>,
    /// The base scene as built at load, for the first frame's geometry (`GeometryCache::seed`).
    pub built: Option<crate::scene::Job>,
    /// Every other file the dataset reads (the base scene's meshes, textures, spectra and
    /// envmap; the variations' envmaps and sensor files), whose contents `dataset.json` hashes.
    pub inputs: Vec<PathBuf>,
}

/// Where a light variation points.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LightRef {
    /// The area light of shape i.
    Shape(usize),
    /// The scene's emitters[i].
    Emitter(usize),
}

impl Base {
    /// Reads the dataset config and its scene, builds the scene once (which checks it and gives
    /// the shapes' bounds), and checks every variation against it.
    pub fn load(file: &Path) -> Result<Base, Error> {
        let config = DatasetConfig::load(file)?;
        let dir = file.parent().unwrap_or(Path::new("."));
        let scene_file = dir.join(&config.scene);
        if !scene_file.is_file() {
            return Err(InputError::new(
                file,
                format!("the base scene `{}` does not exist", scene_file.display()),
            )
            .field("scene")
            .hint("give the scene file's path relative to the dataset config")
            .into());
        }
        // The files the load reads (meshes, textures, spectra, the envmap), for `dataset.json`.
        let (loaded, read) = crate::scene::inputs::collect(|| -> Result<_, Error> {
            let scene = crate::config::parse_file(&scene_file)?;
            let job = crate::scene::build(scene.clone(), &scene_file)?;
            Ok((scene, job))
        });
        let (scene, job) = loaded?;
        let bounds = job.scene.shapes.iter().map(shape_bounds).collect();
        let mut names = BTreeMap::new();
        for (i, s) in scene.shapes.iter().enumerate() {
            if let Some(n) = &s.name {
                if names.insert(n.clone(), i).is_some() {
                    return Err(InputError::new(
                        &scene_file,
                        format!("two shapes are named \"{n}\""),
                    )
                    .field(format!("shapes[{i}].name"))
                    .hint("a dataset refers to shapes by name: make the names unique")
                    .into());
                }
            }
        }
        // The two configs are hashed as parsed (a comment does not change the dataset).
        let mut inputs: Vec<PathBuf> = read.iter().filter(|p| **p != scene_file).cloned().collect();
        let variation_files = config
            .envmap
            .iter()
            .flat_map(|e| &e.files)
            .chain(config.sensor.iter().flat_map(|s| s.files.iter().flatten()));
        for f in variation_files {
            let p = dir.join(f);
            if !inputs.contains(&p) {
                inputs.push(p);
            }
        }
        let mut base = Base {
            config,
            file: file.to_path_buf(),
            scene_file,
            scene,
            bounds,
            names,
            built: Some(job),
            inputs,
        };
        base.check()?;
        for p in base.sensor_inputs()? {
            if !base.inputs.contains(&p) {
                base.inputs.push(p);
            }
        }
        Ok(base)
    }

    fn err(&self, field: &str, message: impl Into<String>) -> InputError {
        InputError::new(&self.file, message).field(field)
    }

    /// The index of the shape called `name`.
    pub fn shape(&self, name: &str, field: &str) -> Result<usize, InputError> {
        self.names.get(name).copied().ok_or_else(|| {
            let known: Vec<String> = self.names.keys().map(|n| format!("\"{n}\"")).collect();
            self.err(
                field,
                format!(
                    "the scene `{}` has no shape named \"{name}\"",
                    self.scene_file.display()
                ),
            )
            .hint(if known.is_empty() {
                "give the shape a `name: \"...\"` in the scene file".to_string()
            } else {
                format!("the named shapes are: {}", known.join(", "))
            })
        })
    }

    /// Resolves a light target: a shape name (its area light) or `emitters[i]`.
    pub fn light(&self, target: &str, field: &str) -> Result<LightRef, InputError> {
        if let Some(i) = target
            .strip_prefix("emitters[")
            .and_then(|r| r.strip_suffix(']'))
        {
            let n = self.scene.emitters.len();
            return match i.parse::<usize>() {
                Ok(i) if i < n => Ok(LightRef::Emitter(i)),
                _ => Err(self
                    .err(field, format!("\"{target}\": the scene has {n} emitter(s)"))
                    .hint("write emitters[0] for the scene's first emitter")),
            };
        }
        let i = self.shape(target, field)?;
        if self.scene.shapes[i].emitter.is_none() {
            return Err(self
                .err(field, format!("shape \"{target}\" is not a light"))
                .hint(
                    "name a shape with an `emitter`, or one of the scene's emitters as emitters[i]",
                ));
        }
        Ok(LightRef::Shape(i))
    }

    fn material(&self, name: &str, field: &str) -> Result<&MaterialConfig, InputError> {
        self.scene.materials.get(name).ok_or_else(|| {
            let known: Vec<String> = self
                .scene
                .materials
                .keys()
                .map(|n| format!("\"{n}\""))
                .collect();
            self.err(field, format!("the scene has no material \"{name}\""))
                .hint(format!("the materials are: {}", known.join(", ")))
        })
    }

    fn range(&self, field: &str, r: Range, lo: f32, hi: f32, what: &str) -> Result<(), InputError> {
        if !(r.0.is_finite() && r.1.is_finite()) {
            return Err(self.err(field, format!("the range {r:?} is not finite")));
        }
        if r.0 > r.1 {
            return Err(self
                .err(field, format!("the range ({}, {}) is inverted", r.0, r.1))
                .hint(format!("write it as ({}, {})", r.1, r.0)));
        }
        if r.0 < lo || r.1 > hi {
            return Err(self.err(
                field,
                format!("{what}: the range {r:?} must lie in [{lo}, {hi}]"),
            ));
        }
        Ok(())
    }

    /// The sensor variation: every file there and a sensor file, the exposure a finite range.
    fn check_sensor(&self, v: &super::config::SensorVariation) -> Result<(), InputError> {
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
                crate::sensor::setup::read_file(&p)?;
            }
        }
        if let Some(e) = v.exposure {
            self.range("sensor.exposure", e, -64.0, 64.0, "exposure in stops")?;
        }
        Ok(())
    }

    /// The files the variations' sensor files read in turn (spectra they name), set up as a
    /// frame would (`check_sensor` has read each file already).
    fn sensor_inputs(&self) -> Result<Vec<PathBuf>, InputError> {
        let dir = self.file.parent().unwrap_or(Path::new("."));
        let files = self
            .config
            .sensor
            .iter()
            .flat_map(|s| s.files.iter().flatten());
        let mut all = Vec::new();
        for f in files {
            let field = SensorField::File(SensorFile::File(super::plan::absolute(&dir.join(f))));
            let (r, read) = crate::scene::inputs::collect(|| {
                crate::sensor::setup::build(
                    Some(&field),
                    &Default::default(),
                    &self.scene_file,
                    self.scene.spectral.range,
                    &mut Vec::new(),
                )
            });
            r?;
            all.extend(read);
        }
        Ok(all)
    }

    fn check(&self) -> Result<(), InputError> {
        let c = &self.config;
        if c.frames == 0 {
            return Err(self.err("frames", "a dataset needs at least one frame"));
        }
        if c.outputs.spp == Some(0) {
            return Err(self.err("outputs.spp", "spp must be at least 1"));
        }
        if matches!(c.outputs.resolution, Some((w, h)) if w == 0 || h == 0 || w > 1 << 15 || h > 1 << 15)
        {
            return Err(self.err(
                "outputs.resolution",
                "the resolution must be between 1×1 and 32768×32768",
            ));
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
                if super::apply::reflectance_slot(&mut mat.clone()).is_none() {
                    return Err(self.err(&format!("{f}.reflectance"), format!("material \"{}\" has no base reflectance to vary", m.target)).hint("reflectances vary on Diffuse, Plastic, RoughPlastic, Conductor and RoughConductor (also inside Twosided)"));
                }
            }
            if let Some(r) = m.roughness {
                self.range(&format!("{f}.roughness"), r, 1e-4, 1.0, "roughness alpha")?;
                if !super::apply::set_roughness(&mut mat.clone(), 0.1) {
                    return Err(self
                        .err(
                            &format!("{f}.roughness"),
                            format!("material \"{}\" has no roughness", m.target),
                        )
                        .hint(
                            "roughness varies on RoughConductor, RoughDielectric and RoughPlastic",
                        ));
                }
            }
            if let Some(r) = m.ior {
                self.range(&format!("{f}.ior"), r, 1e-3, 10.0, "index of refraction")?;
                if !super::apply::set_ior(&mut mat.clone(), 1.5) {
                    return Err(self
                        .err(
                            &format!("{f}.ior"),
                            format!("material \"{}\" has no interior IOR", m.target),
                        )
                        .hint("the IOR varies on the dielectrics and plastics"));
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
}

/// World bounds of a shape: the union of its primitives' boxes.
fn shape_bounds(s: &crate::shape::Shape) -> (Vec3, Vec3) {
    (0..s.prim_count()).fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), i| {
        let (a, b) = s.prim_geom(i).bounds();
        (lo.min(a), hi.max(b))
    })
}
