//! One frame: a scene config rendered into an EXR (every channel the config asks for), an
//! optional PNG preview and the frame's JSON, each written atomically. Nothing in these files
//! depends on time, thread count or the path of the output folder, so a frame rendered alone is
//! byte-identical to the same frame of the full run.

use crate::config::SceneConfig;
use crate::error::Error;
use crate::integrator;
use crate::output;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What rendering a frame gave.
pub struct FrameResult {
    /// The files written, in order: EXR, JSON, then the PNG if asked for.
    pub files: Vec<PathBuf>,
    pub invalid_samples: u64,
    pub seconds: f64,
}

/// Renders `scene` (its relative paths relative to `scene_file`) in the current rayon pool and
/// writes `<stem>.exr`, `<stem>.json` (`params`) and, with `preview = Some(exposure)`,
/// `<stem>.png`, each atomically; the manifest line the caller appends afterwards is what marks
/// the frame complete.
pub fn render_frame(
    scene: SceneConfig,
    scene_file: &Path,
    stem: &Path,
    params: &Value,
    preview: Option<f32>,
) -> Result<FrameResult, Error> {
    let t = Instant::now();
    let job = crate::scene::build(scene, scene_file)?;
    let s = &job.settings;
    let (film, stats) = integrator::render(&job.scene, s, &job.channels, &|_| {});
    let exr = stem.with_extension("exr");
    let extra = vec![
        ("prism:version".into(), env!("CARGO_PKG_VERSION").into()),
        ("prism:spp".into(), s.spp.to_string()),
        ("prism:seed".into(), s.seed.to_string()),
        (
            "prism:invalidSamples".into(),
            stats.invalid_samples.to_string(),
        ),
    ];
    output::exr::write(&film, &exr, &extra)?;
    let mut files = vec![exr];
    if let Some(exposure) = preview {
        let png = stem.with_extension("png");
        output::png::write(&film, &png, exposure)?;
        files.push(png);
    }
    let json = stem.with_extension("json");
    let mut text = serde_json::to_string_pretty(params)
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
