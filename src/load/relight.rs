//! A built job given a new config of the same geometry: everything but the shapes and the
//! acceleration structure is built again from the config (camera, materials, emitters, film,
//! sensor, the objects' names), so changing a material, light, camera or sensor reads no mesh
//! and builds no BVH. The dataset's frames (`dataset::frame`) and the Python module's
//! `scene.params` use it.

use super::Job;
use crate::config::{SceneConfig, ShapeKind, SpectrumConfig};
use crate::error::Error;
use std::path::{Path, PathBuf};

/// What decides a scene's geometry: its shapes without their materials and emitted spectra
/// (whether a shape emits stays: area lights are built from their shapes), and the accelerator.
/// Two configs with the same key may share one built geometry.
pub fn geometry_key(cfg: &SceneConfig) -> String {
    let shapes: Vec<_> = cfg
        .shapes
        .iter()
        .map(|s| {
            let mut s = s.clone();
            s.material = None;
            if let Some(e) = &mut s.emitter {
                e.radiance = SpectrumConfig::Constant(0.0);
            }
            s
        })
        .collect();
    // Moving shapes are built at the frame's time; the flow layers' scene also holds the
    // camera's motion and the frame rate.
    let moving = cfg.shapes.iter().any(|s| s.animation.is_some());
    let flow = cfg.aovs.iter().any(|a| {
        crate::film::Aov::parse(a.trim())
            .and_then(|a| a.flow_dir())
            .is_some()
    });
    if moving || flow {
        let time = (
            &cfg.camera.shutter,
            flow.then_some((&cfg.camera, &cfg.aovs)),
        );
        return serde_json::to_string(&(shapes, cfg.accel, time)).expect("configs serialise");
    }
    serde_json::to_string(&(shapes, cfg.accel)).expect("configs serialise")
}

/// Rebuilds `job` for `cfg`, whose `geometry_key` must equal that of `job.config`: the shapes
/// and accelerator stay, the rest is `cfg`'s. On an error `job` is left as it was.
pub fn relight(job: &mut Job, cfg: SceneConfig, file: &Path) -> Result<(), Error> {
    debug_assert_eq!(geometry_key(&cfg), geometry_key(&job.config));
    // Non-emitting meshes stand in as unit spheres: their geometry is the built one.
    let mut light = cfg.clone();
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
    let new = super::build(light, file)?;
    let (sc, n) = (&mut job.scene, new.scene);
    sc.camera = n.camera;
    sc.shape_material = n.shape_material;
    sc.shape_emitter = n.shape_emitter;
    sc.materials = n.materials;
    sc.emitters = n.emitters;
    sc.environment = n.environment;
    job.settings = new.settings;
    job.channels = new.channels;
    // The config the job says it was built from is `cfg`, meshes and all (the sidecar hashes
    // the files it names; a rebuild starts from it).
    job.config = cfg;
    job.aovs = new.aovs;
    // The inputs, as a fresh build records them: the new config's files and the built meshes
    // it stands in for (the sidecar hashes them).
    let mut inputs: Vec<PathBuf> = job
        .inputs
        .iter()
        .filter(|p| meshes.contains(&crate::io::paths::normal(p)))
        .cloned()
        .collect();
    inputs.extend(new.inputs);
    job.inputs = inputs;
    // Names, labels and materials are the new config's; where the objects are, the built
    // geometry's (the stand-in spheres are nowhere).
    let mut objects = new.objects;
    for (n, o) in objects.list.iter_mut().zip(&job.objects.list) {
        (n.to_world, n.bounds) = (o.to_world, o.bounds);
    }
    job.objects = objects;
    Ok(())
}
