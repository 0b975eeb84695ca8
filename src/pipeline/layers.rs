//! The AOV pass of a loaded job: which layers its `aovs` ask for, over the integrator's
//! pixel-centre hits (`integrator::aov`). Moved here from the integrator, which knows no job.

use crate::film::{Aov, Film};
use crate::integrator::albedo;
use crate::integrator::aov::{first_hits, layers, stderr_layers, uses_hits, Hit};
use crate::integrator::PixelErrors;
use crate::load::Job;

/// Runs the AOV pass: adds the layers `job.aovs` asks for to `film` and returns the
/// pixel-centre hits the sidecar's boxes come from: `None` when neither a layer nor the
/// scene's `boxes` needs them (then no ray is traced for them).
/// `errors`: what `render_film` returned beside the film (needed for `stderr` and `spp`, and
/// for `alpha` under adaptive sampling; without it those layers assume `settings.spp`
/// everywhere, and `stderr` is left out).
pub fn add_layers(
    job: &Job,
    film: &mut Film,
    errors: Option<&PixelErrors>,
) -> Option<Vec<Option<Hit>>> {
    let s = &job.settings;
    let hits = (job.config.boxes || job.aovs.iter().any(|&a| uses_hits(a)))
        .then(|| first_hits(&job.scene, s.width, s.height));
    let none = Vec::new();
    let h = hits.as_deref().unwrap_or(&none);
    let o = &job.objects;
    let (floats, ids) = layers(
        &job.scene,
        s,
        h,
        &job.aovs,
        &o.label_ids(),
        &o.instance_ids(),
        errors.map(|e| e.spp.as_slice()),
    );
    film.channels.extend(floats);
    film.uint_channels.extend(ids);
    if let (true, Some(e)) = (job.aovs.contains(&Aov::Stderr), errors) {
        film.channels
            .extend(stderr_layers(&e.stderr, &job.channels));
    }
    if job.aovs.contains(&Aov::Albedo) {
        film.channels
            .extend(albedo::layers(&job.scene, h, &job.channels.sensor));
    }
    if let Some(f) = &job.flow {
        film.channels
            .extend(f.layers(&job.scene.camera, h, s.width, &job.aovs));
    }
    hits
}
