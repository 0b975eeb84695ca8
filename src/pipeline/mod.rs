//! The render pipeline: a loaded job → the colour pass → the AOV layers → EXR, JSON sidecar and
//! PNG preview. One function each for `prism render` and `prism dataset` (and, later, the
//! Python module), so both write the same files with the same EXR header keys.

mod layers;
pub mod workers;

pub use layers::add_layers;
pub use workers::{worker_pool, WorkerArgs};

use crate::error::Error;
use crate::film::{Aov, Film};
use crate::integrator::aov::Hit;
use crate::integrator::{self, RenderStats};
use crate::io::paths;
use crate::load::Job;
use crate::math::portable;
use crate::output;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What rendering a job gave.
pub struct Rendered {
    pub film: Film,
    pub stats: RenderStats,
    /// The pixel-centre hits the sidecar's boxes come from (when a layer or `boxes` asked).
    pub hits: Option<Vec<Option<Hit>>>,
    /// Seconds of the colour pass.
    pub seconds: f64,
    /// The dataset exposure applied to the sensor's channels (1 for `prism render`), and the
    /// channels it scaled: recorded in the EXR header and the sidecar with its meaning.
    pub exposure_scale: f32,
    pub scaled: Vec<String>,
}

/// Renders `job` in the current rayon pool: the colour pass (`progress` gets sample counts),
/// the sensor's channels scaled by `exposure_scale`, then the AOV layers.
pub fn render(job: &Job, exposure_scale: f32, progress: &(dyn Fn(u64) + Sync)) -> Rendered {
    let s = &job.settings;
    let t = Instant::now();
    let stderr = job.aovs.contains(&Aov::Stderr);
    let (mut film, stats, mut se) =
        integrator::render_film(&job.scene, s, &job.channels, stderr, progress);
    let seconds = t.elapsed().as_secs_f64();
    // A dataset's sensor variation: before the AOVs join, the film holds the sensor's channels
    // alone (one multiply per pixel and channel, none per sample); their standard errors scale
    // with them, so `stderr` is that of the values in the file.
    let mut scaled = Vec::new();
    if exposure_scale != 1.0 {
        for c in &mut film.channels {
            c.data.iter_mut().for_each(|v| *v *= exposure_scale);
            scaled.push(c.name.clone());
        }
        se.stderr.iter_mut().for_each(|v| *v *= exposure_scale);
        if stderr {
            scaled.push("stderr.*".into());
            let extras = job.channels.sensor.extras().iter();
            scaled.extend(extras.map(|e| format!("{}.stderr.*", e.name)));
        }
    }
    let hits = add_layers(job, &mut film, Some(&se));
    Rendered {
        film,
        stats,
        hits,
        seconds,
        exposure_scale,
        scaled,
    }
}

/// Which sidecar a render writes.
pub enum Sidecar<'a> {
    /// `prism render`: the render's sidecar, its time included.
    Render,
    /// A dataset frame: its sampled parameters under `frame`, and no wall-clock time (a frame's
    /// files depend on (config, frame index) alone; the manifest has the time).
    Frame(&'a serde_json::Value),
}

/// Where a render's files go.
pub struct Files<'a> {
    /// The scene file the job came from (recorded in the header and sidecar).
    pub scene: &'a Path,
    pub exr: &'a Path,
    pub sidecar: Sidecar<'a>,
    /// A PNG preview and its exposure in stops.
    pub preview: Option<(&'a Path, f32)>,
}

/// Checks a render's outputs before it starts: the EXR at `exr`, its sidecar and the preview
/// are never one of the scene's inputs (nor a link, FIFO or folder: `guard::check_output`), and
/// a preview has colour to show.
pub fn check_outputs(job: &Job, exr: &Path, preview: Option<&Path>) -> Result<(), Error> {
    output::guard::check_output(exr, "-o", &job.inputs)?;
    // The sidecar is an output too: `-o s.exr` would write `s.json` over a scene or sensor
    // file of that name.
    output::guard::check_output(
        &output::sidecar::path_for(exr),
        "-o (its sidecar .json)",
        &job.inputs,
    )?;
    if let Some(p) = preview {
        output::guard::check_output(p, "--preview", &job.inputs)?;
        let layers = &job.channels.sensor.layers;
        if !(layers.rgb.contains(&crate::sensor::RgbSpace::Srgb) || layers.xyz) {
            return Err(crate::error::InputError::new(
                p,
                "a PNG preview needs the rgb or xyz output",
            )
            .field("--preview")
            .hint("keep `outputs: (rgb: true)` in the scene, or drop --preview")
            .into());
        }
    }
    Ok(())
}

/// Writes the EXR, the JSON sidecar beside it and the preview, each atomically; returns them
/// in that order.
pub fn write(job: &Job, r: &Rendered, files: &Files) -> Result<Vec<PathBuf>, Error> {
    // A non-finite value in any channel fails the render before anything is written.
    output::check_finite(&r.film, files.scene)?;
    let timed = matches!(files.sidecar, Sidecar::Render);
    // A frame records its scene relative to the scene's own folder: its files must not depend
    // on the directory the run started from.
    let folder = paths::normal(files.scene.parent().unwrap_or(Path::new(".")));
    let rel = |p: &Path| paths::relative(&paths::normal(p), &folder);
    let mut extra = header(job, files.scene, &r.stats, timed.then_some(r.seconds));
    if !timed {
        if let Some(kv) = extra.iter_mut().find(|(k, _)| k == "prism:scene") {
            kv.1 = rel(files.scene);
        }
    }
    let exposure = exposure(r);
    if let Some(e) = &exposure {
        extra.push((
            "prism:datasetExposureScale".into(),
            r.exposure_scale.to_string(),
        ));
        extra.push((
            "prism:datasetExposureChannels".into(),
            e["channels"].to_string(),
        ));
    }
    output::exr::write(&r.film, files.exr, &extra, job.config.film.exr_compression)?;
    let json = output::sidecar::path_for(files.exr);
    match files.sidecar {
        Sidecar::Render => output::sidecar::write(
            &json,
            job,
            files.scene,
            files.exr,
            r.hits.as_deref(),
            &r.stats,
            r.seconds,
        )?,
        Sidecar::Frame(params) => {
            let mut sidecar = output::sidecar::value(
                job,
                files.scene,
                files.exr,
                r.hits.as_deref(),
                &r.stats,
                r.seconds,
            );
            sidecar["frame"] = params.clone();
            if let Some(e) = exposure {
                sidecar["sensor"]["exposure"] = e;
            }
            if let Some(r) = sidecar["render"].as_object_mut() {
                r.remove("seconds");
                let rel = |p: &serde_json::Value| match p.as_str() {
                    Some(p) => rel(Path::new(p)).into(),
                    None => p.clone(),
                };
                r["scene_file"] = rel(&r["scene_file"]);
                for f in r["files"].as_array_mut().into_iter().flatten() {
                    f["path"] = rel(&f["path"]);
                }
            }
            let mut text = serde_json::to_string_pretty(&sidecar)
                .map_err(|e| Error::Other(format!("frame parameters: {e}")))?;
            text.push('\n');
            output::write_atomic(&json, |tmp| {
                std::fs::write(tmp, &text).map_err(|e| e.to_string())
            })?;
        }
    }
    let mut written = vec![files.exr.to_path_buf(), json];
    if let Some((png, exposure)) = files.preview {
        output::png::write(&r.film, png, exposure)?;
        written.push(png.to_path_buf());
    }
    Ok(written)
}

/// The sidecar's `sensor.exposure` of a render whose sensor channels were scaled (a dataset's
/// exposure variation): the scale, the channels and what it means; None when nothing was scaled.
fn exposure(r: &Rendered) -> Option<serde_json::Value> {
    (r.exposure_scale != 1.0).then(|| {
        serde_json::json!({
            "stops": portable::log2(r.exposure_scale),
            "scale": r.exposure_scale,
            "channels": r.scaled,
            "meaning": "each listed channel is the scene's value (in the units above) times `scale`, as if every light were `scale` times as bright; the AOVs are not scaled",
        })
    })
}

/// The `prism:` attributes of every render's EXR header. `seconds`: the colour pass's time, or
/// None for a dataset frame (whose files must not depend on the clock).
pub fn header(
    job: &Job,
    scene: &Path,
    stats: &RenderStats,
    seconds: Option<f64>,
) -> Vec<(String, String)> {
    let s = &job.settings;
    let (lo, hi) = s.wavelengths.range();
    vec![
        ("prism:version".into(), env!("CARGO_PKG_VERSION").into()),
        ("prism:scene".into(), scene.display().to_string()),
        ("prism:spp".into(), crate::config::Spp::of(s).to_string()),
        ("prism:seed".into(), s.seed.to_string()),
        ("prism:sampler".into(), format!("{:?}", s.sampler)),
        ("prism:accel".into(), format!("{:?}", job.config.accel)),
        (
            "prism:simd".into(),
            crate::integrator::packet::describe(&job.scene, s),
        ),
        (
            "prism:wavelengths".into(),
            format!(
                "{} per path, {:?} over {lo}-{hi} nm",
                s.lanes,
                s.wavelengths.kind()
            ),
        ),
        (
            "prism:integrator".into(),
            format!(
                "path max_depth {} rr_depth {} hide_emitters {} clamp {} caustics {}",
                s.path.max_depth,
                s.path.rr_depth,
                s.path.hide_emitters,
                s.path.clamp.map_or("off".into(), |c| c.to_string()),
                s.path.caustics.map_or("off".into(), |c| format!(
                    "(light_paths {}, bright_ratio {}, max_roughness {}, area_lights {})",
                    c.light_paths, c.bright_ratio, c.max_roughness, c.area_lights
                ))
            ),
        ),
        (
            "prism:clampedSamples".into(),
            stats.clamped_samples.to_string(),
        ),
        (
            "prism:invalidSamples".into(),
            stats.invalid_samples.to_string(),
        ),
        (
            "prism:renderSeconds".into(),
            seconds.map_or("see manifest.jsonl".into(), |t| format!("{t:.3}")),
        ),
    ]
}
