//! The module's one contact with prism's render steps: load → (overrides) → render → AOV layers,
//! and the writing of EXR, sidecar and preview, each as `prism render` does them (src/cli.rs), so
//! the same arguments give the same bits. When prism gains one function for these steps
//! (src/pipeline.rs), this file is what points at it; nothing else here knows the order.

use prism_core::cli::{RenderArgs, WorkerArgs};
use prism_core::error::{Error, InputError};
use prism_core::film::Film;
use prism_core::integrator::{self, aov::Hit, RenderStats};
use prism_core::output;
use prism_core::scene::Job;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// Where a scene came from: a file is reloaded as the CLI loads it when render arguments
/// change the config; text and dicts are rebuilt from their parsed config.
#[derive(Clone)]
pub enum Source {
    File(PathBuf),
    Config(Box<prism_core::config::SceneConfig>),
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

    /// The CLI's edit of the parsed config for these flags (src/cli.rs `render`).
    fn edit(&self, cfg: &mut prism_core::config::SceneConfig) {
        if let Some(spp) = self.spp {
            cfg.sampler.spp = spp;
        }
        if let Some(seed) = self.seed {
            cfg.sampler.seed = seed;
        }
        if let Some(p) = &self.sensor {
            cfg.sensor = Some(prism_core::sensor::setup::cli_override(p));
            cfg.outputs = Default::default();
        }
        if let Some(a) = &self.aovs {
            cfg.aovs = a.iter().filter(|n| !n.is_empty()).cloned().collect();
        }
    }

    /// The CLI arguments these stand for (the EXR header names the scene from them).
    fn args(&self, scene: &Path) -> RenderArgs {
        RenderArgs {
            scene: scene.to_path_buf(),
            output: None,
            spp: self.spp,
            seed: self.seed,
            accel: None,
            sampler: None,
            wavelengths: None,
            wavelength_sampling: None,
            caustics: None,
            clamp: None,
            aovs: self.aovs.clone(),
            boxes: false,
            sensor: self.sensor.clone(),
            preview: None,
            exposure: 0.0,
            max_memory: None,
            workers: WorkerArgs {
                threads: self.threads,
                quiet: true,
            },
        }
    }
}

/// Loads a scene file as `prism render` does (RON or glTF by its name).
pub fn load_file(path: &Path, o: &Overrides) -> Result<Job, Error> {
    prism_core::resources::configure(None, o.threads);
    prism_core::scene::load(path, |cfg| o.edit(cfg))
}

/// Builds a scene from a parsed config; `file` names it in errors and anchors relative paths.
pub fn build(
    mut cfg: prism_core::config::SceneConfig,
    file: &Path,
    o: &Overrides,
) -> Result<Job, Error> {
    prism_core::resources::configure(None, o.threads);
    o.edit(&mut cfg);
    Ok(prism_core::scene::build(cfg, file)?)
}

/// Rebuilds `source` with the overrides applied.
pub fn rebuild(source: &Source, file: &Path, o: &Overrides) -> Result<Job, Error> {
    match source {
        Source::File(p) => load_file(p, o),
        Source::Config(cfg) => build((**cfg).clone(), file, o),
    }
}

/// A finished render: what the CLI writes comes from these.
pub struct Rendered {
    pub film: Film,
    pub stats: RenderStats,
    pub hits: Option<Vec<Option<Hit>>>,
    pub seconds: f64,
}

/// The render was stopped (Ctrl-C): raised through the workers by `progress` and caught here.
pub struct Cancelled;

/// Renders `job` on `threads` workers (None: one per core), as `prism render`. `progress` is
/// told each finished tile's samples; once `cancel` is set the next tile to begin or finish
/// unwinds the render (`resume_unwind` runs no panic hook, so nothing is printed) and `Err(Cancelled)` is
/// returned with every buffer freed.
pub fn render(
    job: &Job,
    file: &Path,
    threads: Option<usize>,
    cancel: &AtomicBool,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Result<Rendered, Cancelled>, Error> {
    let pool = prism_core::cli::worker_pool(threads, file)?;
    let s = &job.settings;
    let stderr = job.aovs.contains(&prism_core::film::Aov::Stderr);
    let tick = |n: u64| {
        if cancel.load(Ordering::Relaxed) {
            std::panic::resume_unwind(Box::new(Cancelled));
        }
        progress(n)
    };
    let run = std::panic::AssertUnwindSafe(|| {
        let t = Instant::now();
        let (mut film, stats, se) =
            pool.install(|| integrator::render_film(&job.scene, s, &job.channels, stderr, &tick));
        let seconds = t.elapsed().as_secs_f64();
        let hits = pool.install(|| integrator::aov::add_layers(job, &mut film, Some(&se)));
        Rendered {
            film,
            stats,
            hits,
            seconds,
        }
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
    o: &Overrides,
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
    output::guard::check_output(out, "-o", &job.inputs)?;
    if let Some(p) = preview {
        output::guard::check_output(p, "--preview", &job.inputs)?;
        let layers = &job.channels.sensor.layers;
        if !(layers.rgb.contains(&prism_core::sensor::RgbSpace::Srgb) || layers.xyz) {
            return Err(
                InputError::new(p, "a PNG preview needs the rgb or xyz output")
                    .field("preview")
                    .hint("keep `outputs: (rgb: true)` in the scene, or give no preview")
                    .into(),
            );
        }
    }
    let extra = prism_core::cli::metadata(&o.args(file), job, &r.stats, r.seconds);
    output::exr::write(&r.film, out, &extra)?;
    output::sidecar::write(
        &output::sidecar::path_for(out),
        job,
        file,
        out,
        r.hits.as_deref(),
        &r.stats,
        r.seconds,
    )?;
    if let Some(p) = preview {
        output::png::write(&r.film, p, exposure)?;
    }
    Ok(())
}

/// The sidecar's JSON for a render written to `out`.
pub fn sidecar(job: &Job, r: &Rendered, file: &Path, out: &Path) -> serde_json::Value {
    output::sidecar::value(job, file, out, r.hits.as_deref(), &r.stats, r.seconds)
}
