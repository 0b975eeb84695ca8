//! One frame: a scene config rendered into an EXR (every channel the config asks for), an
//! optional PNG preview and the frame's JSON, each written atomically. Nothing in these files
//! depends on time, thread count or the path of the output folder, so a frame rendered alone is
//! byte-identical to the same frame of the full run.

use crate::config::{SceneConfig, ShapeKind};
use crate::error::Error;
use crate::integrator;
use crate::output;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The last frame's built scene, kept while the next frames have the same geometry: a frame
/// that changes only camera, lights, materials or film then builds those alone (meshes are
/// neither read nor put into a BVH again).
#[derive(Default)]
pub struct GeometryCache {
    key: String,
    job: Option<crate::scene::Job>,
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
    pub fn seed(job: crate::scene::Job) -> GeometryCache {
        GeometryCache {
            key: geometry_key(&job.config),
            job: Some(job),
            builds: 1,
        }
    }

    /// The job for `cfg`: built in full when its geometry differs from the cached one's, else the
    /// cached geometry with everything else built from `cfg`.
    fn job(&mut self, cfg: SceneConfig, file: &Path) -> Result<&crate::scene::Job, Error> {
        let key = geometry_key(&cfg);
        match &mut self.job {
            Some(job) if key == self.key => {
                // Non-emitting meshes stand in as unit spheres: their geometry is the cached one.
                let mut light = cfg;
                for s in &mut light.shapes {
                    if s.emitter.is_none() && matches!(s.shape, ShapeKind::Mesh { .. }) {
                        s.shape = ShapeKind::Sphere {
                            center: [0.0; 3],
                            radius: 1.0,
                        };
                        s.to_world.clear();
                    }
                }
                let new = crate::scene::build(light, file)?;
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
            }
            _ => {
                self.job = Some(crate::scene::build(cfg, file)?);
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
    let s = &job.settings;
    let stderr = job.aovs.contains(&crate::film::Aov::Stderr);
    let (mut film, stats, se) =
        integrator::render_film(&job.scene, s, &job.channels, stderr, &|_| {});
    // The sensor variation's exposure: before the AOVs join, the film holds the sensor's
    // channels alone (one multiply per pixel and channel, none per sample).
    if exposure_scale != 1.0 {
        for c in &mut film.channels {
            c.data.iter_mut().for_each(|v| *v *= exposure_scale);
        }
    }
    // The scene's AOV layers, and the pixel-centre hits the sidecar's boxes come from (when
    // a layer or `boxes` asked for them).
    let hits = integrator::aov::add_layers(job, &mut film, Some(&se));
    let exr = stem.with_extension("exr");
    let extra = vec![
        ("prism:version".into(), env!("CARGO_PKG_VERSION").into()),
        ("prism:spp".into(), s.spp_config().to_string()),
        ("prism:seed".into(), s.seed.to_string()),
        (
            "prism:invalidSamples".into(),
            stats.invalid_samples.to_string(),
        ),
    ];
    output::exr::write(&film, &exr, &extra)?;
    let mut files = vec![exr.clone()];
    if let Some(exposure) = preview {
        let png = stem.with_extension("png");
        output::png::write(&film, &png, exposure)?;
        files.push(png);
    }
    let json = stem.with_extension("json");
    // The frame's sidecar (camera, sensor, objects; docs/sidecar.md) with its sampled
    // parameters under `frame`.
    let mut sidecar = output::sidecar::value(
        job,
        scene_file,
        &exr,
        hits.as_deref(),
        &stats,
        t.elapsed().as_secs_f64(),
    );
    sidecar["frame"] = params.clone();
    // A frame's files depend on (config, frame index) alone; its render time is in the
    // manifest.
    if let Some(r) = sidecar["render"].as_object_mut() {
        r.remove("seconds");
    }
    let mut text = serde_json::to_string_pretty(&sidecar)
        .map_err(|e| Error::Other(format!("frame parameters: {e}")))?;
    text.push('\n');
    output::write_atomic(&json, |tmp| {
        std::fs::write(tmp, &text).map_err(|e| e.to_string())
    })?;
    files.insert(1, json);
    Ok(FrameResult {
        files,
        invalid_samples: stats.invalid_samples,
        seconds: t.elapsed().as_secs_f64(),
    })
}
