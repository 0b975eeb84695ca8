//! The module's one contact with prism's render steps: load → (overrides) → the one render
//! pipeline (`prism::pipeline`, as `prism render` and `prism dataset` use it), so the same
//! arguments give the same bits and the same files.

use prism_core::error::{Error, InputError};
use prism_core::load::Job;
use prism_core::output;
use prism_core::pipeline;
pub use prism_core::pipeline::Rendered;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

/// Where a scene came from: a file is reloaded as the CLI loads it when render arguments
/// change the config; text and dicts are rebuilt from their parsed config.
#[derive(Clone)]
pub enum Source {
    File(PathBuf),
    Config,
}

/// The render arguments the module takes, as `prism render`'s flags.
#[derive(Clone, Default)]
pub struct Overrides {
    pub spp: Option<u32>,
    pub seed: Option<u64>,
    pub aovs: Option<Vec<String>>,
    pub sensor: Option<PathBuf>,
    pub threads: Option<usize>,
}

impl Overrides {
    /// Whether the scene must be rebuilt (the thread count changes nothing in the config).
    pub fn change_config(&self) -> bool {
        self.spp.is_some() || self.seed.is_some() || self.aovs.is_some() || self.sensor.is_some()
    }

    /// The CLI's edit of the parsed config for these flags (src/cli/mod.rs `render`).
    fn edit(&self, cfg: &mut prism_core::config::SceneConfig) {
        if let Some(spp) = self.spp {
            cfg.sampler.spp = prism_core::config::Spp::Fixed(spp);
        }
        if let Some(seed) = self.seed {
            cfg.sampler.seed = seed;
        }
        if let Some(p) = &self.sensor {
            cfg.sensor = Some(prism_core::load::sensor::cli_override(p));
            cfg.outputs = Default::default();
        }
        if let Some(a) = &self.aovs {
            cfg.aovs = a.iter().filter(|n| !n.is_empty()).cloned().collect();
        }
    }
}

/// Runs `f` (a scene load or rebuild) on a pool of its own, ended when `f` returns. The BVH
/// builder (obvhs) runs on rayon's current pool, which outside one is rayon's global pool: a
/// process-wide set of threads a call would leave behind, and which a child forked from this
/// process (a `DataLoader`'s or `multiprocessing`'s worker) inherits without its threads, so
/// the child's first load waited for them forever.
pub fn in_pool<T: Send>(
    threads: Option<usize>,
    file: &Path,
    f: impl FnOnce() -> T + Send,
) -> Result<T, Error> {
    Ok(pipeline::worker_pool(threads, file)?.install(f))
}

/// Loads a scene file as `prism render` does (RON or glTF by its name).
pub fn load_file(path: &Path, o: &Overrides) -> Result<Job, Error> {
    prism_core::resources::configure(None, o.threads);
    in_pool(o.threads, path, || {
        prism_core::load::load(path, |cfg| o.edit(cfg))
    })?
}

/// Builds a scene from a parsed config; `file` names it in errors and anchors relative paths.
pub fn build(
    mut cfg: prism_core::config::SceneConfig,
    file: &Path,
    o: &Overrides,
) -> Result<Job, Error> {
    prism_core::resources::configure(None, o.threads);
    o.edit(&mut cfg);
    Ok(in_pool(o.threads, file, || {
        prism_core::load::build(cfg, file)
    })??)
}

/// Builds `cfg` (the scene's current config, `source`'s with its parameters set) in full with
/// the overrides applied; a file is read again as the CLI reads it (its inputs recorded).
pub fn rebuild(
    source: &Source,
    file: &Path,
    o: &Overrides,
    cfg: &prism_core::config::SceneConfig,
) -> Result<Job, Error> {
    match source {
        Source::File(p) => {
            prism_core::resources::configure(None, o.threads);
            in_pool(o.threads, p, || {
                prism_core::load::load(p, |c| {
                    *c = cfg.clone();
                    o.edit(c)
                })
            })?
        }
        Source::Config => build(cfg.clone(), file, o),
    }
}

/// Whether the scene's geometry comes from a glTF file, which only a full load builds.
pub fn has_gltf(source: &Source, cfg: &prism_core::config::SceneConfig) -> bool {
    matches!(source, Source::File(p) if prism_core::load::gltf::is_gltf(p))
        || cfg
            .shapes
            .iter()
            .any(|s| matches!(s.shape, prism_core::config::ShapeKind::Gltf { .. }))
}

/// Rebuilds `job` for `cfg` of the same geometry (`load::relight`): all but shapes and the
/// accelerator; files the new config reads (a spectrum, a texture) join the job's inputs.
pub fn relight(
    job: &mut Job,
    cfg: prism_core::config::SceneConfig,
    file: &Path,
) -> Result<(), Error> {
    let (r, read) = in_pool(None, file, || {
        prism_core::io::inputs::collect(|| prism_core::load::relight(job, cfg, file))
    })?;
    r?;
    for p in read {
        if !job.inputs.contains(&p) {
            job.inputs.push(p);
        }
    }
    Ok(())
}

/// `job` without its geometry: what a finished render keeps to write its files and sidecar
/// (which read the camera, never the shapes), so the scene stays free to change.
pub fn shell(job: &Job) -> Job {
    let scene = prism_core::scene::Scene::new(
        job.scene.camera.clone(),
        Vec::new(),
        Vec::new(),
        Vec::new(),
        Vec::new(),
        Vec::new(),
        prism_core::accel::AccelKind::Bvh,
    );
    Job {
        scene,
        settings: job.settings.clone(),
        channels: job.channels.clone(),
        warnings: job.warnings.clone(),
        config: job.config.clone(),
        inputs: job.inputs.clone(),
        aovs: job.aovs.clone(),
        objects: job.objects.clone(),
        // The flow layers are in the film by now; the sidecar needs none of its geometry.
        flow: None,
    }
}

/// The render was stopped (Ctrl-C): raised through the workers by `progress` and caught here.
pub struct Cancelled;

/// Renders `job` on `threads` workers (None: one per core), as `prism render`, the sensor's
/// channels scaled by `exposure_scale` (a dataset frame's sensor exposure; 1: none). `progress` is
/// told each finished tile's samples; once `cancel` is set the next tile to begin or finish
/// unwinds the render (`resume_unwind` runs no panic hook, so nothing is printed) and `Err(Cancelled)` is
/// returned with every buffer freed.
pub fn render(
    job: &Job,
    file: &Path,
    threads: Option<usize>,
    exposure_scale: f32,
    cancel: &AtomicBool,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Result<Rendered, Cancelled>, Error> {
    let pool = pipeline::worker_pool(threads, file)?;
    let tick = |n: u64| {
        if cancel.load(Ordering::Relaxed) {
            std::panic::resume_unwind(Box::new(Cancelled));
        }
        progress(n)
    };
    let run = std::panic::AssertUnwindSafe(|| {
        pool.install(|| pipeline::render(job, exposure_scale, &tick))
    });
    match std::panic::catch_unwind(run) {
        Ok(r) => Ok(Ok(r)),
        Err(p) if p.is::<Cancelled>() => Ok(Err(Cancelled)),
        Err(p) => std::panic::resume_unwind(p),
    }
}

/// Writes the EXR at `out`, its sidecar beside it and, with `preview`, the PNG, as `prism
/// render -o out [--preview preview --exposure exposure]` does, with the same checks first:
/// names, and never over one of the scene's inputs.
pub fn write(
    job: &Job,
    r: &Rendered,
    file: &Path,
    out: &Path,
    preview: Option<&Path>,
    exposure: f32,
) -> Result<(), Error> {
    if !exposure.is_finite() {
        return Err(InputError::new(
            file,
            format!("exposure {exposure} is not a finite number of stops"),
        )
        .field("exposure")
        .hint("give a number such as exposure=-1.5")
        .into());
    }
    output::guard::check_names(out, preview)?;
    pipeline::check_outputs(job, out, preview)?;
    let files = pipeline::Files {
        scene: file,
        exr: out,
        sidecar: pipeline::Sidecar::Render,
        preview: preview.map(|p| (p, exposure)),
    };
    pipeline::write(job, r, &files)?;
    Ok(())
}

/// The sidecar's JSON for a render written to `out`.
pub fn sidecar(job: &Job, r: &Rendered, file: &Path, out: &Path) -> serde_json::Value {
    output::sidecar::value(job, file, out, r.hits.as_deref(), &r.stats, r.seconds)
}
