//! Frame i → its scene and its sampled parameters, from (dataset seed, i) alone.

use super::apply::{self, EmitterSlot};
use super::base::{Base, LightRef};
use super::config::{LookAtVariation, ReflectanceSource};
use super::library;
use super::vary::{shell_point, Rng, Stream};
use super::view;
use crate::config::sensor::{SensorField, SensorFile};
use crate::config::{SceneConfig, SpectrumConfig, TransformOp};
use crate::error::InputError;
use crate::math::portable;
use crate::spectrum::Curve;
use glam::Vec3;
use serde_json::{json, Value};
use std::path::Path;

/// One frame, resolved.
pub struct FramePlan {
    pub index: u32,
    /// The render seed (`sampler.seed` of `scene`).
    pub seed: u64,
    /// The scene to render (relative paths still relative to the base scene file).
    pub scene: SceneConfig,
    /// What was drawn, for the frame's JSON.
    pub params: Value,
    /// The factor 2^e of the sensor variation's exposure e on the sensor's channels (1: none).
    pub exposure_scale: f32,
}

/// Plans frame `i` of `base`.
pub fn plan(base: &Base, i: u32) -> Result<FramePlan, InputError> {
    let c = &base.config;
    let mut scene = base.scene.clone();
    let mut params = serde_json::Map::new();
    let seed = Rng::new(c.seed, i, Stream::Render).next_u64();
    // The variations' draws: per sequence in a video dataset, else per frame.
    let d = super::sequence::draw_index(base, i);
    scene.sampler.seed = seed;
    if let Some(spp) = &c.outputs.spp {
        scene.sampler.spp = *spp;
    }
    if let Some((w, h)) = c.outputs.resolution {
        scene.film.width = w;
        scene.film.height = h;
    }
    params.insert("frame".into(), json!(i));
    params.insert("render_seed".into(), json!(seed));
    params.insert("spp".into(), json!(scene.sampler.spp));

    // Objects first: the camera keeps the placed ones in view.
    let mut shown = vec![true; scene.shapes.len()];
    let mut subsets = Vec::new();
    for (k, s) in c.objects.subsets.iter().enumerate() {
        let mut r = Rng::new(c.seed, d, Stream::Subset(k));
        let n = r.int(s.shown.0, s.shown.1) as usize;
        let pick = r.subset(s.shapes.len(), n);
        for (j, name) in s.shapes.iter().enumerate() {
            shown[base.names[name]] = pick.contains(&j);
        }
        subsets.push(json!(pick
            .iter()
            .map(|&j| &s.shapes[j])
            .collect::<Vec<_>>()));
    }
    if !subsets.is_empty() {
        params.insert("shown".into(), Value::Array(subsets));
    }
    let mut bounds = base.bounds.clone();
    // Asset-folder meshes: which show, placed with the listed shapes.
    let assets = super::asset_folder::draw(base, d, &mut shown);
    let place = match &assets {
        Some((p, drawn)) => {
            params.insert("assets".into(), drawn.clone());
            Some(p)
        }
        None => c.objects.place.as_ref(),
    };
    if let Some(p) = place {
        let placed = super::place::place(base, p, d, &shown, &mut scene, &mut bounds)?;
        params.insert("placement".into(), placed);
    }

    // K and distortion first: the pose's keep_in_view test projects through K.
    let intrinsics = super::intrinsics::draw(base, d, &mut scene.camera);
    if let Some(k) = intrinsics {
        params.insert("intrinsics".into(), k);
    }
    if let Some(cam) = &c.camera {
        let mut r = Rng::new(c.seed, d, Stream::Camera);
        let watched: Vec<usize> = cam
            .keep_in_view
            .iter()
            .map(|n| base.names[n])
            .filter(|&k| shown[k])
            .collect();
        let mut found = None;
        for attempt in 1..=cam.max_attempts {
            let (origin, target) = match &cam.look_at {
                Some(LookAtVariation::Shell {
                    target,
                    radius,
                    elevation,
                    azimuth,
                }) => {
                    let t = Vec3::from(*target);
                    let o =
                        shell_point(t, r.range(*radius), r.range(*elevation), r.range(*azimuth));
                    (Some(o.to_array()), Some(*target))
                }
                Some(LookAtVariation::Poses(p)) => {
                    let pose = &p[r.index(p.len())];
                    (Some(pose.origin), Some(pose.target))
                }
                None => (None, None),
            };
            let fov = cam.fov.map_or(scene.camera.fov, |f| r.range(f));
            let roll = if cam.roll > 0.0 {
                r.symmetric(cam.roll)
            } else {
                0.0
            };
            let mut ops = Vec::new();
            if roll != 0.0 {
                ops.push(TransformOp::Rotate {
                    axis: [0.0, 0.0, 1.0],
                    angle: roll,
                });
            }
            match (origin, target) {
                (Some(origin), Some(target)) => ops.push(TransformOp::LookAt {
                    origin,
                    target,
                    up: cam.up,
                }),
                _ => ops.extend(scene.camera.to_world.iter().cloned()),
            }
            let mut cfg = scene.camera.clone();
            cfg.fov = fov;
            cfg.to_world = ops;
            let mut posed = None;
            // A drawn pose or trajectory the scene refuses is the dataset's error, named by
            // its field (`camera`, `motion.camera`), not the scene's.
            let drawn = |e| super::check_frames::refused(base, i, &scene, e, false);
            let file = &base.scene_file;
            if view::in_view(&cfg, &scene, file, &watched, &bounds).map_err(drawn)? {
                // In a sequence, also at every frame's pose of the camera and the shapes.
                let mut trial = scene.clone();
                trial.camera = cfg.clone();
                let ok =
                    view::throughout(base, i, &trial, &shown, &watched, &bounds).map_err(drawn)?;
                posed = ok.then_some(cfg);
            }
            if let Some(cfg) = posed {
                found = Some((
                    cfg,
                    json!({
                        "origin": origin, "target": target, "up": cam.up,
                        "fov": fov, "roll": roll, "attempts": attempt,
                    }),
                ));
                break;
            }
        }
        let Some((cfg, p)) = found else {
            return Err(InputError::new(
                &base.file,
                format!(
                    "frame {i}: no camera pose in {} attempts keeps every shape of keep_in_view wholly in the image{}",
                    cam.max_attempts,
                    if c.sequences > 0 { " at every frame of its sequence" } else { "" }
                ),
            )
            .field("camera.keep_in_view")
            .hint("widen the fov, move the shell farther out, narrow its angles, or raise max_attempts (in a sequence, or slow motion.camera and motion.objects)"));
        };
        scene.camera = cfg;
        params.insert("camera".into(), p);
    }

    let mut lights = Vec::new();
    for (k, l) in c.lights.iter().enumerate() {
        let mut r = Rng::new(c.seed, d, Stream::Light(k));
        let intensity = l.intensity.map(|x| r.range(x));
        let temperature = l.temperature.map(|x| r.range(x));
        // Drawn last from the light's stream: configs without it draw as before.
        // Uniformly over the named illuminants, then the files.
        let files = base
            .illuminant_files
            .get(k)
            .map_or(&[][..], |f| f.as_slice());
        let count = l.illuminants.len() + files.len();
        let drawn = (count > 0).then(|| r.index(count));
        let file = drawn.and_then(|j| files.get(j.wrapping_sub(l.illuminants.len())));
        let illuminant = drawn.map(|j| match file {
            Some(f) => f.name.clone(),
            None => l.illuminants[j].clone(),
        });
        let new = |old: &SpectrumConfig| match (temperature, &illuminant) {
            (_, Some(_)) if file.is_some() => {
                file.expect("drawn").spectrum(intensity.unwrap_or(1.0))
            }
            // A named illuminant is of unit luminance already.
            (_, Some(n)) => SpectrumConfig::Scaled(
                intensity.unwrap_or(1.0),
                Box::new(SpectrumConfig::Named(n.clone())),
            ),
            // A blackbody of unit luminance, like the named illuminants, times the intensity.
            (Some(t), None) => {
                let y = Curve::blackbody(t).luminance();
                SpectrumConfig::Scaled(
                    intensity.unwrap_or(1.0) / y,
                    Box::new(SpectrumConfig::Blackbody(t)),
                )
            }
            (None, None) => SpectrumConfig::Scaled(intensity.unwrap_or(1.0), Box::new(old.clone())),
        };
        match base.light(&l.target, "lights")? {
            LightRef::Shape(s) => {
                let e = scene.shapes[s].emitter.as_mut().expect("checked at load");
                e.radiance = new(&e.radiance);
            }
            LightRef::Emitter(e) => match apply::emitter_slot(&mut scene.emitters[e]) {
                EmitterSlot::Spectrum(s) => *s = new(s),
                EmitterSlot::Scale(s) => *s *= intensity.unwrap_or(1.0),
            },
        }
        let mut p = json!({"target": l.target, "intensity": intensity, "temperature": temperature});
        if let Some(n) = &illuminant {
            p["illuminant"] = json!(n);
        }
        lights.push(p);
    }
    if !lights.is_empty() {
        params.insert("lights".into(), Value::Array(lights));
    }

    if let Some(e) = &c.envmap {
        let mut r = Rng::new(c.seed, d, Stream::Envmap);
        let file = (!e.files.is_empty()).then(|| &e.files[r.index(e.files.len())]);
        let angle = if e.rotate { r.range((0.0, 360.0)) } else { 0.0 };
        let Ok(LightRef::Emitter(k)) = base.light(&e.target, "envmap.target") else {
            unreachable!("checked at load")
        };
        if let crate::config::EmitterConfig::Envmap {
            filename, to_world, ..
        } = &mut scene.emitters[k]
        {
            if let Some(f) = file {
                let dir = base.file.parent().unwrap_or(Path::new("."));
                *filename = absolute(&dir.join(f));
            }
            if e.rotate {
                to_world.push(apply::yaw(angle));
            }
        }
        params.insert("envmap".into(), json!({"file": file, "rotation": angle}));
    }

    let mut mats = Vec::new();
    for (k, m) in c.materials.iter().enumerate() {
        let mut r = Rng::new(c.seed, d, Stream::Material(k));
        let range = scene.spectral.range;
        let mat = scene.materials.get_mut(&m.target).expect("checked at load");
        let mut entry = None;
        if let Some(src) = &m.reflectance {
            let (set, only) = match src {
                ReflectanceSource::Library(s) => (s, None),
                ReflectanceSource::Patches(s, p) => (s, Some(p)),
            };
            let t = library::set(set).expect("checked at load");
            let col = match only {
                None => r.index(t.columns.len()),
                Some(p) => {
                    let name = &p[r.index(p.len())];
                    t.columns
                        .iter()
                        .position(|c| c == name)
                        .expect("checked at load")
                }
            };
            *apply::reflectance_slot(mat).expect("checked at load") =
                library::spectrum(&t, col, range);
            entry = Some(format!("{set}/{}", t.columns[col]));
        }
        let roughness = m.roughness.map(|x| r.range(x));
        if let Some(a) = roughness {
            apply::set_roughness(mat, a);
        }
        let ior = m.ior.map(|x| r.range(x));
        if let Some(n) = ior {
            apply::set_ior(mat, n);
        }
        mats.push(
            json!({"target": m.target, "reflectance": entry, "roughness": roughness, "ior": ior}),
        );
    }
    if !mats.is_empty() {
        params.insert("materials".into(), Value::Array(mats));
    }
    if let Some(t) = super::textures::draw(base, d, &mut scene) {
        params.insert("textures".into(), t);
    }

    let mut swaps = Vec::new();
    for (k, s) in c.swaps.iter().enumerate() {
        let mut r = Rng::new(c.seed, d, Stream::Swap(k));
        let m = &s.materials[r.index(s.materials.len())];
        scene.shapes[base.names[&s.shape]].material = Some(m.clone());
        swaps.push(json!({"shape": s.shape, "material": m}));
    }
    if !swaps.is_empty() {
        params.insert("swaps".into(), Value::Array(swaps));
    }

    let mut exposure_scale = 1.0;
    if let Some(v) = &c.sensor {
        let mut r = Rng::new(c.seed, d, Stream::Sensor);
        let file = v.files.as_ref().map(|f| &f[r.index(f.len())]);
        if let Some(f) = file {
            let dir = base.file.parent().unwrap_or(Path::new("."));
            scene.sensor = Some(SensorField::File(SensorFile::File(absolute(&dir.join(f)))));
            // The chosen sensor replaces the scene's (`outputs` is the older way to say one).
            scene.outputs = Default::default();
        }
        let stops = v.exposure.map(|x| r.range(x));
        if let Some(e) = stops {
            exposure_scale = portable::exp2(e);
        }
        params.insert("sensor".into(), json!({"file": file, "exposure": stops}));
    }

    // Ids fixed by the base scene, so a hidden shape keeps its id and its class keeps its own.
    for (s, id) in scene.shapes.iter_mut().zip(&base.ids) {
        s.id = *id;
    }
    scene.labels = base.labels.clone();
    super::sequence::animate(base, i, &mut scene, &shown, &mut params)?;
    // Hidden shapes go last: every index above refers to the base scene's shapes.
    let mut k = 0;
    scene.shapes.retain(|_| {
        k += 1;
        shown[k - 1]
    });
    Ok(FramePlan {
        index: i,
        seed,
        scene,
        params: Value::Object(params),
        exposure_scale,
    })
}

/// `p` as an absolute path string (so the frame's scene finds it from anywhere).
pub fn absolute(p: &Path) -> String {
    std::path::absolute(p)
        .unwrap_or_else(|_| p.to_path_buf())
        .to_string_lossy()
        .into_owned()
}
