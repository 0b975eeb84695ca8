//! One frame: a scene config rendered into an EXR (every channel the config asks for), an
//! optional PNG preview and the frame's JSON, each written atomically. Nothing in these files
//! depends on time, thread count or the path of the output folder, so a frame rendered alone is
//! byte-identical to the same frame of the full run.

use crate::config::SceneConfig;
use crate::error::Error;
use crate::load::geometry_key;
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
            Some(job) if key == self.key => crate::load::relight(job, cfg, file)?,
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
