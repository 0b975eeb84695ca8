//! The flow layers' setup (`integrator::flow`): the frame interval from `camera.fps`, the
//! frame's time, and the scene built again with its shutter open over [t − 1/fps, t + 1/fps],
//! where every moving shape and the camera can be posed at either neighbouring frame and the
//! occlusion rays are traced. Its materials and lights are left out (flow needs geometry only,
//! and an area light may then move). Refused, with the fix: flow without `fps`, in a scene
//! where nothing moves, or towards a frame beyond every animation's keys.

use crate::config::{SceneConfig, ShutterConfig};
use crate::error::InputError;
use crate::film::{Aov, Dir};
use crate::integrator::flow::FlowScene;
use crate::math::Transform;
use crate::motion::Motion;
use std::path::Path;

/// The flow scene when `cfg.aovs` asks for a flow layer (None otherwise). Runs before the
/// frame's own build, on the config as written (with its animations).
/// `camera`: the camera's motion where the config's animation does not give it (a glTF
/// camera, `build::build_moving`).
pub fn setup(
    cfg: &SceneConfig,
    file: &Path,
    camera: Option<&Motion>,
) -> Result<Option<FlowScene>, InputError> {
    let asked: Vec<(usize, Aov)> = cfg
        .aovs
        .iter()
        .enumerate()
        .filter_map(|(i, n)| Some((i, Aov::parse(n.trim()).filter(|a| a.flow_dir().is_some())?)))
        .collect();
    let Some(&(first, aov)) = asked.first() else {
        return Ok(None);
    };
    // The shutter's and the animations' own checks speak first.
    super::motion::prepare_moving(&mut cfg.clone(), file, camera)?;
    let fps = match cfg.camera.fps {
        None => {
            return Err(InputError::new(
                file,
                format!("the AOV \"{}\" follows each pixel's point to the next or previous frame, and the scene gives no frame rate", aov.name()),
            )
            .field("camera.fps")
            .hint("give the frames per second, e.g. camera: (fps: 30, ...) or prism render --fps 30 (the flow spans 1/fps)"))
        }
        Some(f) if !(f.is_finite() && f > 0.0 && f <= 1e6) => {
            return Err(InputError::new(
                file,
                format!("fps {f} must be a positive number of frames per second (at most 1e6)"),
            )
            .field("camera.fps")
            .hint("e.g. fps: 30"))
        }
        Some(f) => f,
    };
    let step = 1.0 / fps;
    let time = cfg.camera.shutter.map_or(0.0, |s| s.open);
    let mut c = cfg.clone();
    c.camera.shutter = Some(ShutterConfig {
        open: time - step,
        close: time + step,
        readout: 0.0,
    });
    c.aovs.clear();
    c.boxes = false;
    c.integrator.caustics = None;
    c.materials.clear();
    c.emitters.clear();
    for s in &mut c.shapes {
        s.material = None;
        s.emitter = None;
    }
    let span = format!("[{}, {}] s", time - step, time + step);
    let job = super::build::build_moving(c, file, camera).map_err(|mut e| {
        e.message = format!(
            "{} (building the flow layers' motion over {span})",
            e.message
        );
        e
    })?;
    let scene = job.scene;
    let camera = scene
        .timing
        .as_ref()
        .and_then(|t| t.camera.as_ref())
        .map(|(m, _)| m);
    let shapes: Vec<&Motion> = (0..scene.shapes.len() as u32)
        .filter_map(|s| scene.shape_motion(s))
        .collect();
    if camera.is_none() && shapes.is_empty() {
        return Err(InputError::new(
            file,
            format!("the AOV \"{}\" follows motion, and nothing in the scene moves (neither the camera nor any shape is animated)", aov.name()),
        )
        .field(format!("aovs[{first}]"))
        .hint("animate the camera or a shape (camera.animation, shapes[i].animation), or remove the flow layers; a still scene's flow is 0 everywhere"));
    }
    // The keys' span over every animation: a neighbouring frame outside it has no motion.
    // (A chained motion's span is its every track's: `Motion::key_span`.)
    let (lo, hi) = camera
        .into_iter()
        .chain(shapes)
        .filter_map(Motion::key_span)
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), (a, b)| {
            (lo.min(a), hi.max(b))
        });
    for &(i, a) in &asked {
        let (dir, t2) = match a.flow_dir() {
            Some(Dir::Forward) => ("next", time + step),
            _ => ("previous", time - step),
        };
        if t2 > hi || t2 < lo {
            return Err(InputError::new(
                file,
                format!("there is no {dir} frame: the AOV \"{}\" looks at t = {t2} s, and every animation's keys lie within [{lo}, {hi}] s", a.name()),
            )
            .field(format!("aovs[{i}]"))
            .hint(format!("render a time whose {dir} frame (1/fps = {step} s away) lies within the keys, add keys that reach it, or drop \"{}\"", a.name())));
        }
    }
    let at = |t: f32| -> Result<crate::camera::Camera, InputError> {
        let Some(m) = camera else {
            return Ok(scene.camera.clone());
        };
        let tr = Transform::from_matrix(m.matrix(t));
        let why = match &tr {
            None => Some("it is singular".to_string()),
            Some(tr) => crate::camera::pose_error(tr),
        };
        match (tr, why) {
            (Some(tr), None) => Ok(scene.camera.with_to_world(tr)),
            (_, why) => Err(InputError::new(
                file,
                format!("the camera's pose at t = {t} s (a flow layer's neighbouring frame) is not a rotation, translation and uniform scale: {}", why.unwrap_or_default()),
            )
            .field("camera.animation")
            .hint("give keys whose interpolation stays a pose there (Linear, or Cubic keys without overshooting scale)")),
        }
    };
    let (forward, backward) = (at(time + step)?, at(time - step)?);
    Ok(Some(FlowScene {
        scene,
        time,
        step,
        forward,
        backward,
    }))
}
