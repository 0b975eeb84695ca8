//! One frame: a scene config rendered into an EXR (every channel the config asks for), an
//! optional PNG preview and the frame's JSON, each written atomically. Nothing in these files
//! depends on time, thread count or the path of the output folder, so a frame rendered alone is
//! byte-identical to the same frame of the full run.

use crate::config::{SceneConfig, ShapeKind};
use crate::error::Error;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The last frame's built scene, kept while the next frames have the same geometry: a frame
/// that changes only camera, lights, materials or film then builds those alone (meshes are
/// neither read nor put into a BVH again).
#[derive(Default)]
pub struct GeometryCache {
    key: String,
    job: Option<crate::load::Job>,
    /// How many times geometry was built.
    pub builds: u32,
}

/// What decides a scene's geometry: its shapes without their materials and emitted spectra
/// (whether a shape emits stays: area lights are built from their shapes), and the accelerator.
fn geometry_key(cfg: &SceneConfig) -> String {
    let shapes: Vec<_> = cfg
        .shapes
        .iter()
        .map(|s| {
            let mut s = s.clone();
            s.material = None;
            if let Some(e) = &mut s.emitter {
                e.radiance = crate::config::SpectrumConfig::Constant(0.0);
            }
            s
        })
        .collect();
    serde_json::to_string(&(shapes, cfg.accel)).expect("configs serialise")
}

impl GeometryCache {
    /// A cache holding an already built job (the base scene's, built at load).
    pub fn seed(job: crate::load::Job) -> GeometryCache {
        GeometryCache {
            key: geometry_key(&job.config),
            job: Some(job),
            builds: 1,
        }
    }

    /// The job for `cfg`: built in full when its geometry differs from the cached one's, else the
    /// cached geometry with everything else built from `cfg`.
    fn job(&mut self, cfg: SceneConfig, file: &Path) -> Result<&crate::load::Job, Error> {
        let key = geometry_key(&cfg);
        match &mut self.job {
            Some(job) if key == self.key => {
                // Non-emitting meshes stand in as unit spheres: their geometry is the cached one.
                let mut light = cfg;
                let dir = file.parent().unwrap_or(Path::new("."));
                let mut meshes = Vec::new();
                for s in &mut light.shapes {
                    if s.emitter.is_none() && matches!(s.shape, ShapeKind::Mesh { .. }) {
                        if let ShapeKind::Mesh { path } = &s.shape {
                            meshes.push(crate::io::paths::normal(&dir.join(path)));
                        }
                        s.shape = ShapeKind::Sphere {
                            center: [0.0; 3],
                            radius: 1.0,
                        };
                        s.to_world.clear();
                    }
                }
                let new = crate::load::build(light, file)?;
                let (sc, n) = (&mut job.scene, new.scene);
                sc.camera = n.camera;
                sc.shape_material = n.shape_material;
                sc.shape_emitter = n.shape_emitter;
                sc.materials = n.materials;
                sc.emitters = n.emitters;
                sc.environment = n.environment;
                job.settings = new.settings;
                job.channels = new.channels;
                job.config = new.config;
                job.aovs = new.aovs;
                // The frame's inputs, as a fresh build records them: this frame's files and
                // the cached meshes it stands in for (the sidecar hashes them).
                let mut inputs: Vec<PathBuf> = job
                    .inputs
                    .iter()
                    .filter(|p| meshes.contains(&crate::io::paths::normal(p)))
                    .cloned()
                    .collect();
                inputs.extend(new.inputs);
                job.inputs = inputs;
                // Names, labels and materials are this frame's; where the objects are, the
                // cached geometry's (the stand-in spheres are nowhere).
                let mut objects = new.objects;
                for (n, o) in objects.list.iter_mut().zip(&job.objects.list) {
                    (n.to_world, n.bounds) = (o.to_world, o.bounds);
                }
                job.objects = objects;
            }
            _ => {
                self.job = Some(crate::load::build(cfg, file)?);
                self.key = key;
                self.builds += 1;
            }
        }
        Ok(self.job.as_ref().expect("just set"))
    }
}

/// What rendering a frame gave.
pub struct FrameResult {
    /// The files written, in order: EXR, JSON, then the PNG if asked for.
    pub files: Vec<PathBuf>,
    pub invalid_samples: u64,
    pub seconds: f64,
}

/// Renders `scene` (its relative paths relative to `scene_file`; its geometry from `cache` when
/// unchanged) in the current rayon pool and
/// writes `<stem>.exr`, `<stem>.json` (`params`) and, with `preview = Some(exposure)`,
/// `<stem>.png`, each atomically, the sensor's channels scaled by `exposure_scale`; the manifest line the caller appends afterwards is what marks
/// the frame complete.
pub fn render_frame(
    cache: &mut GeometryCache,
    scene: SceneConfig,
    scene_file: &Path,
    stem: &Path,
    params: &Value,
    preview: Option<f32>,
    exposure_scale: f32,
) -> Result<FrameResult, Error> {
    let t = Instant::now();
    let job = cache.job(scene, scene_file)?;
    let r = crate::pipeline::render(job, exposure_scale, &|_| {});
    let exr = stem.with_extension("exr");
    let png = stem.with_extension("png");
    // The frame's files: the same pipeline as `prism render`, its sidecar with the sampled
    // parameters under `frame` (docs/sidecar.md).
    let files = crate::pipeline::Files {
        scene: scene_file,
        exr: &exr,
        sidecar: crate::pipeline::Sidecar::Frame(params),
        preview: preview.map(|e| (png.as_path(), e)),
    };
    let files = crate::pipeline::write(job, &r, &files)?;
    let stats = r.stats;
    Ok(FrameResult {
        files,
        invalid_samples: stats.invalid_samples,
        seconds: t.elapsed().as_secs_f64(),
    })
}
