//! The AOV pass of a loaded job: which layers its `aovs` ask for, over the integrator's
//! pixel-centre hits (`integrator::aov`). Moved here from the integrator, which knows no job.

use crate::film::{Aov, Film};
use crate::integrator::albedo;
use crate::integrator::aov::{first_hits, layers, uses_hits, Hit};
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
    let sensor = &job.channels.sensor;
    if let (true, Some(e)) = (job.aovs.contains(&Aov::Stderr), errors) {
        // Every sensor's: the extras' slots have their standard errors too.
        film.channels.extend(sensor.stderr_channels(&e.stderr));
    }
    if job.aovs.contains(&Aov::Albedo) {
        film.channels
            .extend(albedo::layers(&job.scene, h, sensor, true));
        // An extra sensor's bands (R/G/B is the main sensor's: it does not depend on one).
        for x in sensor
            .extras()
            .iter()
            .filter(|x| x.sensor.bands().is_some())
        {
            let own = albedo::layers(&job.scene, h, &x.sensor, false);
            film.channels.extend(x.prefixed(own));
        }
    }
    if let Some(f) = &job.flow {
        film.channels
            .extend(f.layers(&job.scene.camera, h, s.width, &job.aovs));
    }
    hits
}
