//! The dataset loaded once per process: its config, the base scene, and every check a mistake
//! in the config can trip (names the scene lacks, inverted ranges), made before any frame.

mod check;
mod extremes;

use super::config::{DatasetConfig, Range};
use crate::config::sensor::{SensorField, SensorFile};
use crate::config::{MaterialConfig, SceneConfig};
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
    /// World bounds of each shape of the base scene's config (min, max; a glTF shape's: all
    /// its parts').
    pub bounds: Vec<(Vec3, Vec3)>,
    /// Shape index by name.
    pub names: BTreeMap<String, usize>,
    /// The base scene as built at load, for the first frame's geometry (`GeometryCache::seed`).
    pub built: Option<crate::load::Job>,
    /// Every other file the dataset reads (the base scene's meshes, textures, spectra and
    /// envmap; the variations' envmaps and sensor files), whose contents `dataset.json` hashes.
    pub inputs: Vec<PathBuf>,
    /// The dataset's fixed ids: each base shape's instance id (its first part's; None if it
    /// builds nothing), and the class table (label i has id i + 1).
    pub ids: Vec<Option<u32>>,
    pub labels: Vec<String>,
    /// The base scene's objects, for `dataset.json`'s tables.
    pub objects: crate::load::Objects,
    /// What `prism render` would warn about in the base scene and in each variation's envmap
    /// and sensor files (spectra ending inside the render range, ...), each once.
    pub warnings: Vec<String>,
    /// Each light variation's `illuminant_files`, read and scaled (src/dataset/illuminant_files.rs).
    pub illuminant_files: Vec<Vec<super::illuminant_files::IlluminantFile>>,
    /// The layers the contact sheet shows (`outputs.sheet_layers`, checked).
    pub sheet_layers: Vec<crate::film::Aov>,
    /// Each texture variation's image files (src/dataset/textures.rs).
    pub textures: super::textures::Listed,
    /// The asset folder's meshes and models, the last shapes of `scene`
    /// (src/dataset/asset_folder.rs).
    pub assets: Vec<super::asset_folder::Asset>,
    /// `view::throughout`'s answers by sequence and drawn pose: every frame of a sequence asks
    /// the same question, each in time linear in the sequence's length.
    pub views: std::sync::Mutex<std::collections::HashMap<u64, bool>>,
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
        // Says what the path is (missing, a directory, a FIFO, a device), without opening a FIFO.
        let opened = crate::io::input_file::open(&scene_file, crate::io::input_file::Kind::Scene);
        if let Err(m) = opened {
            return Err(InputError::new(file, format!("the base scene: {m}"))
                .field("scene")
                .hint("give the scene file's path relative to the dataset config")
                .into());
        }
        // `outputs.aovs` names AOVs the scene build then makes for every frame.
        for (i, n) in config.outputs.aovs.iter().flatten().enumerate() {
            if crate::film::Aov::parse(n.trim()).is_none() {
                return Err(InputError::new(file, format!("unknown AOV \"{n}\""))
                    .field(format!("outputs.aovs[{i}]"))
                    .hint(format!("the AOVs are: {}", crate::film::Aov::names()))
                    .into());
            }
        }
        let assets = super::asset_folder::list(&config, file)?;
        // The files the load reads (meshes, textures, spectra, the envmap), for `dataset.json`.
        let (loaded, read) = crate::io::inputs::collect(|| -> Result<_, Error> {
            let mut scene = crate::config::parse_file(&scene_file)?;
            super::asset_folder::append(&assets, config.objects.assets.as_ref(), &mut scene);
            if let Some(a) = &config.outputs.aovs {
                scene.aovs = a.clone();
            }
            if let Some(list) = &config.outputs.sensors {
                scene.sensors = list.clone();
                for s in &mut scene.sensors {
                    if let SensorField::File(SensorFile::File(p)) = &mut s.sensor {
                        *p = super::plan::absolute(&dir.join(&*p));
                    }
                }
            }
            let mut probe = scene.clone();
            drop_flow_layers(&mut probe.aovs);
            let job = crate::load::build(probe, &scene_file)?;
            Ok((scene, job))
        });
        let (mut scene, mut job) = loaded?;
        // By config shape: a glTF shape builds several (the union of its parts' boxes).
        let mut bounds = vec![(Vec3::INFINITY, Vec3::NEG_INFINITY); scene.shapes.len()];
        for (j, s) in job.scene.shapes.iter().enumerate() {
            let i = job.objects.list[job.objects.of_shape[j]].shape;
            let (lo, hi) = shape_bounds(s);
            bounds[i] = (bounds[i].0.min(lo), bounds[i].1.max(hi));
        }
        if let Some(a) = &config.objects.assets {
            super::asset_folder::normalise(&assets, a.size, &mut scene, &mut bounds);
        }
        let mut ids = vec![None; scene.shapes.len()];
        for o in job.objects.list.iter().rev() {
            ids[o.shape] = Some(o.instance_id);
        }
        let objects = job.objects.clone();
        // The ids the frames set are the ones the base scene was built with: its built job
        // stays the first frames' geometry (`GeometryCache::seed` compares configs).
        for (s, id) in job.config.shapes.iter_mut().zip(&ids) {
            s.id = *id;
        }
        job.config.labels = objects.labels.clone();
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
        let classes = config.objects.assets.iter().map(|a| &a.classes);
        for f in variation_files.chain(classes) {
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
            ids,
            labels: objects.labels.clone(),
            objects,
            warnings: Vec::new(),
            illuminant_files: Vec::new(),
            sheet_layers: Vec::new(),
            textures: Vec::new(),
            assets,
            views: Default::default(),
        };
        base.warnings = base
            .built
            .as_ref()
            .map_or(Vec::new(), |j| j.warnings.clone());
        base.check()?;
        base.illuminant_files = super::illuminant_files::load(&base)?;
        super::intrinsics::check(&base)?;
        base.textures = super::textures::load(&base)?;
        let o = &base.config.outputs;
        base.sheet_layers =
            super::sheet_layers::check(&base.file, &o.sheet_layers, &base.scene.aovs, o.preview)?;
        base.check_extremes()?;
        base.envmap_warnings()?;
        let mut lit = super::illuminant_files::paths(&base);
        lit.extend(super::textures::paths(&base.textures));
        for p in base.sensor_inputs()?.into_iter().chain(lit) {
            if !base.inputs.contains(&p) {
                base.inputs.push(p);
            }
        }
        Ok(base)
    }

    pub(crate) fn err(&self, field: &str, message: impl Into<String>) -> InputError {
        // A caller's own hint replaces this pointer to the field's documentation.
        InputError::new(&self.file, message)
            .field(field)
            .hint(format!(
                "configs/README.md documents `{field}` and its values"
            ))
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

    /// The files the variations' sensor files read in turn (spectra they name), set up as a
    /// frame would (`check_sensor` has read each file already).
    fn sensor_inputs(&mut self) -> Result<Vec<PathBuf>, InputError> {
        let dir = self.file.parent().unwrap_or(Path::new(".")).to_path_buf();
        let files: Vec<String> = self
            .config
            .sensor
            .iter()
            .flat_map(|s| s.files.iter().flatten())
            .cloned()
            .collect();
        let mut all = Vec::new();
        for f in files {
            let field = SensorField::File(SensorFile::File(super::plan::absolute(&dir.join(f))));
            let mut warnings = Vec::new();
            let (r, read) = crate::io::inputs::collect(|| {
                crate::load::sensor::build(
                    Some(&field),
                    &Default::default(),
                    &self.scene_file,
                    self.scene.spectral.range,
                    &mut warnings,
                )
            });
            r?;
            all.extend(read);
            self.warn(warnings);
        }
        Ok(all)
    }

    fn warn(&mut self, warnings: Vec<String>) {
        for w in warnings {
            if !self.warnings.contains(&w) {
                self.warnings.push(w);
            }
        }
    }

    /// The warnings of each envmap the variation draws from, as the frame's scene loads it:
    /// the base scene with that map alone (no shapes, so no mesh is read).
    fn envmap_warnings(&mut self) -> Result<(), Error> {
        let Some(e) = &self.config.envmap else {
            return Ok(());
        };
        let Ok(LightRef::Emitter(k)) = self.light(&e.target, "envmap.target") else {
            return Ok(());
        };
        let dir = self.file.parent().unwrap_or(Path::new(".")).to_path_buf();
        for (i, f) in e.files.clone().into_iter().enumerate() {
            let mut cfg = self.scene.clone();
            cfg.shapes.clear();
            cfg.aovs.clear();
            cfg.labels.clear();
            // At the largest intensity the light variations give it (extremes.rs).
            let most = self.max_intensity(k);
            if let crate::config::EmitterConfig::Envmap {
                filename, scale, ..
            } = &mut cfg.emitters[k]
            {
                *filename = super::plan::absolute(&dir.join(&f));
                *scale *= most;
            }
            let job = crate::load::build(cfg, &self.scene_file).map_err(|e| {
                let at = e.field.map_or(String::new(), |x| format!("{x}: "));
                self.err(
                    &format!("envmap.files[{i}]"),
                    format!("`{f}` (at intensity {most}) is refused as the scene's environment map: {at}{}", e.message),
                )
                .hint(e.hint.unwrap_or_else(|| "list environment maps (EXR or PNG images) the scene can take".into()))
            })?;
            let named =
                |w: String| format!("{}: envmap.files[{i}] `{f}`: {w}", self.file.display());
            let warnings = job.warnings.into_iter().map(named).collect();
            self.warn(warnings);
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

/// Removes the flow layers from a base scene's AOVs before it is built on its own: they follow
/// the frames' motion (dataset::sequence), which the base scene lacks.
pub(super) fn drop_flow_layers(aovs: &mut Vec<String>) {
    aovs.retain(|a| {
        crate::film::Aov::parse(a.trim())
            .and_then(|a| a.flow_dir())
            .is_none()
    });
}
