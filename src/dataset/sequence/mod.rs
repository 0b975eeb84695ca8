//! Video sequences (issue 30 item 4): `sequences` × `frames_per_sequence` frames at `fps`.
//! Frame i is frame k = i mod F of sequence s = i div F, at time t = k / fps. Everything the
//! other variations draw (camera pose, lights, materials, placement, sensor) is drawn once per
//! sequence (their streams are keyed by s: `draw_index`); the render seed stays per frame.
//! `motion` then moves the camera along a trajectory, the listed objects linearly with a spin
//! (`keys`) and the listed lights by a slide and an orbit (`lights`), each drawn per sequence
//! from its own stream, as keyframes at every frame time from
//! −1/fps to F/fps: the frame renders at its instant and its flow layers (`camera.fps` = fps)
//! reach the frames before and after it, the first's and the last's included. A frame needs
//! nothing but (seed, i), so `--frames i` renders it alone, bit for bit as in the full run.

mod check;
mod keys;
mod lights;

pub use check::check;
use keys::{camera_keys, object_keys};

use super::base::Base;
use super::config::Range;
use super::vary::{Rng, Stream};
use crate::config::{AnimationConfig, SceneConfig, ShutterConfig};
use crate::error::InputError;
use serde::{Deserialize, Serialize};
use serde_json::{json, Value};

/// `motion: (camera: Orbit(speed: (10, 30)), objects: [(shapes: ["ball"], speed: (0, 0.3),
/// spin: (-90, 90))], shutter: 0)`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MotionConfig {
    /// How the camera moves through a sequence; left out, it stands still.
    pub camera: Option<Trajectory>,
    /// Shapes that move: each in a straight line over its support, turning about +y.
    pub objects: Vec<ObjectMotion>,
    /// Lights that move: each sliding and orbiting the vertical axis (`lights`).
    pub lights: Vec<LightMotion>,
    /// Exposure as a fraction of the frame interval (a 180° shutter is 0.5): each frame is
    /// blurred over [t, t + shutter/fps]. Default 0: an instant.
    pub shutter: f32,
}

/// A camera trajectory. Orbit, dolly and walk start from the pose the `camera` variation draws
/// for the sequence (its `look_at`: they need its target) and keep looking at that target.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Trajectory {
    /// About the vertical axis through the target, at a speed drawn from `speed` (degrees per
    /// second) in a direction drawn too.
    Orbit { speed: Range },
    /// Along the line of sight at a speed drawn from `speed` (scene units per second; positive
    /// towards the target).
    Dolly { speed: Range },
    /// A smooth random walk in the horizontal plane: a speed drawn from `speed` (units per
    /// second), a heading that turns at a rate drifting within ±`turn` degrees per second.
    Walk { speed: Range, turn: f32 },
    /// The same keys for every sequence, times in seconds from its first frame (interpolated
    /// as a scene's `animation`; flow at the ends needs keys from −1/fps to F/fps).
    Keyframes(Vec<CameraKey>),
}

/// `(time: 0.5, origin: (0, 1, 4), target: (0, 0, 0))`
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraKey {
    pub time: f32,
    pub origin: [f32; 3],
    pub target: [f32; 3],
}

/// `(shapes: ["ball", "box"], speed: (0, 0.3), spin: (-90, 90))`: each shape drawn a
/// horizontal direction, a speed (units per second) and a spin about +y through its centre
/// (degrees per second). A placed shape's speed is lowered where needed so that its footprint
/// stays on the support for the whole sequence.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectMotion {
    pub shapes: Vec<String>,
    #[serde(default)]
    pub speed: Range,
    #[serde(default)]
    pub spin: Range,
}

/// `(targets: ["lamp", "emitters[0]"], speed: (0, 0.3), orbit: (-30, 30))`: each light (a
/// shape with an `emitter`, or `emitters[i]`, as the light variations name them) drawn a
/// horizontal direction and a speed (units per second; point, spot and area lights) and an
/// orbit rate about the vertical axis through the origin (degrees per second).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LightMotion {
    pub targets: Vec<String>,
    #[serde(default)]
    pub speed: Range,
    #[serde(default)]
    pub orbit: Range,
}

/// The streams of the lights' draws start here, past any count of moving objects.
const LIGHT_STREAMS: usize = 1 << 20;

/// The index the variations' streams are keyed by: the sequence of frame `i` (or `i` itself
/// without sequences).
pub fn draw_index(base: &Base, i: u32) -> u32 {
    match base.config.frames_per_sequence {
        0 => i,
        f => i / f,
    }
}

/// Frame `i`'s sequence, its index in it and its time (None without sequences).
pub fn position(base: &Base, i: u32) -> Option<(u32, u32, f32)> {
    let c = &base.config;
    (c.sequences > 0).then(|| {
        let f = c.frames_per_sequence;
        let k = i % f;
        (i / f, k, k as f32 / c.fps)
    })
}

/// Moves frame `i`'s scene (before hidden shapes are dropped: indices are the base scene's):
/// the camera's and the moving shapes' keyframes over the sequence, the frame's instant and
/// `camera.fps`; adds `sequence`, `index`, `time` and what was drawn to `params`.
pub fn animate(
    base: &Base,
    i: u32,
    scene: &mut SceneConfig,
    shown: &[bool],
    params: &mut serde_json::Map<String, Value>,
) -> Result<(), InputError> {
    let Some((s, k, t)) = position(base, i) else {
        return Ok(());
    };
    let c = &base.config;
    let (fps, n) = (c.fps, c.frames_per_sequence as i32);
    let times: Vec<f32> = (-1..=n).map(|j| j as f32 / fps).collect();
    let m = c.motion.clone().unwrap_or_default();
    let mut drawn = serde_json::Map::new();
    if let Some(tr) = &m.camera {
        let mut r = Rng::new(c.seed, s, Stream::Motion(0));
        let (keys, p) = camera_keys(base, tr, &scene.camera.to_world, &times, &mut r)?;
        scene.camera.to_world.clear();
        scene.camera.animation = Some(AnimationConfig {
            interpolation: Default::default(),
            keys,
        });
        drawn.insert("camera".into(), p);
    }
    let mut objects = Vec::new();
    let names = m
        .objects
        .iter()
        .flat_map(|o| o.shapes.iter().map(move |n| (o, n)));
    for (j, (om, name)) in names.enumerate() {
        let Some(&idx) = base.names.get(name) else {
            return Err(InputError::new(
                &base.file,
                format!("no shape of the base scene is named \"{name}\""),
            )
            .field("motion.objects")
            .hint("list shapes by their `name` in the base scene"));
        };
        if !shown[idx] {
            continue;
        }
        let mut r = Rng::new(c.seed, s, Stream::Motion(1 + j));
        let (keys, p) = object_keys(base, idx, om, scene, &times, &mut r)?;
        let sc = &mut scene.shapes[idx];
        sc.to_world.clear();
        sc.animation = Some(AnimationConfig {
            interpolation: Default::default(),
            keys,
        });
        objects.push(json!({"shape": name, "motion": p}));
    }
    if !objects.is_empty() {
        drawn.insert("objects".into(), Value::Array(objects));
    }
    let mut lights = Vec::new();
    let targets = m.lights.iter().enumerate().flat_map(|(k, l)| {
        let field = format!("motion.lights[{k}].targets");
        l.targets.iter().map(move |n| (l, n, field.clone()))
    });
    for (j, (lm, target, field)) in targets.enumerate() {
        let mut r = Rng::new(c.seed, s, Stream::Motion(LIGHT_STREAMS + j));
        let at = (lm, target.as_str(), field.as_str());
        if let Some(p) = lights::animate(base, at, scene, shown, &times, t, &mut r)? {
            lights.push(p);
        }
    }
    if !lights.is_empty() {
        drawn.insert("lights".into(), Value::Array(lights));
    }
    let close = t + m.shutter.max(0.0) / fps;
    scene.camera.shutter = Some(ShutterConfig {
        open: t,
        close,
        readout: 0.0,
    });
    scene.camera.fps = Some(fps);
    params.insert("sequence".into(), json!(s));
    params.insert("index".into(), json!(k));
    params.insert("time".into(), json!(t));
    params.insert("motion".into(), Value::Object(drawn));
    Ok(())
}

/// The preview animation (`animation::write`, `OUT/sequences.png`) of the sequences whose
/// frames the manifest lists whole, each with its preview PNG (`png(i)`); None without
/// sequences or previews.
pub fn previews(
    base: &Base,
    listed: &std::collections::BTreeSet<u32>,
    png: impl Fn(u32) -> std::path::PathBuf,
    root: &std::path::Path,
) -> Result<Option<std::path::PathBuf>, crate::error::Error> {
    let c = &base.config;
    if c.sequences == 0 {
        return Ok(None);
    }
    let f = c.frames_per_sequence;
    let whole: Vec<Vec<std::path::PathBuf>> = (0..c.sequences)
        .map(|s| {
            (s * f..(s + 1) * f)
                .map(|i| (listed.contains(&i), png(i)))
                .collect::<Vec<_>>()
        })
        .filter(|seq| seq.iter().all(|(l, p)| *l && p.is_file()))
        .map(|seq| seq.into_iter().map(|(_, p)| p).collect())
        .collect();
    super::animation::write(&whole, c.fps, &root.join("sequences.png"))
}
