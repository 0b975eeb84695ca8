//! Video sequences (issue 30 item 4): `sequences` × `frames_per_sequence` frames at `fps`.
//! Frame i is frame k = i mod F of sequence s = i div F, at time t = k / fps. Everything the
//! other variations draw (camera pose, lights, materials, placement, sensor) is drawn once per
//! sequence (their streams are keyed by s: `draw_index`); the render seed stays per frame.
//! `motion` then moves the camera along a trajectory and the listed objects linearly with a
//! spin, both drawn per sequence from their own stream, as keyframes at every frame time from
//! −1/fps to F/fps: the frame renders at its instant and its flow layers (`camera.fps` = fps)
//! reach the frames before and after it, the first's and the last's included. A frame needs
//! nothing but (seed, i), so `--frames i` renders it alone, bit for bit as in the full run.

use super::base::Base;
use super::config::Range;
use super::vary::{Rng, Stream};
use crate::config::{AnimationConfig, KeyConfig, SceneConfig, ShutterConfig, TransformOp};
use crate::error::InputError;
use glam::{Mat4, Vec3};
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

/// The camera's keys at `times` along trajectory `tr`, from the frame's drawn pose `ops`
/// (ending in a LookAt, after its roll), and what was drawn.
fn camera_keys(
    base: &Base,
    tr: &Trajectory,
    ops: &[TransformOp],
    times: &[f32],
    r: &mut Rng,
) -> Result<(Vec<KeyConfig>, Value), InputError> {
    let look = ops
        .iter()
        .rposition(|o| matches!(o, TransformOp::LookAt { .. }));
    let key = |time: f32, origin: Vec3, target: Vec3, up: [f32; 3]| {
        let mut to_world = ops[..look.unwrap_or(0)].to_vec();
        to_world.push(TransformOp::LookAt {
            origin: origin.to_array(),
            target: target.to_array(),
            up,
        });
        KeyConfig { time, to_world }
    };
    if let Trajectory::Keyframes(keys) = tr {
        let up = base
            .config
            .camera
            .as_ref()
            .map_or([0.0, 1.0, 0.0], |c| c.up);
        let out = keys
            .iter()
            .map(|k| key(k.time, k.origin.into(), k.target.into(), up))
            .collect();
        return Ok((out, json!({"trajectory": "keyframes"})));
    }
    let Some(TransformOp::LookAt { origin, target, up }) = look.map(|l| ops[l].clone()) else {
        return Err(InputError::new(
            &base.file,
            "the camera trajectory starts from a look-at pose, and the frame's camera has none",
        )
        .field("motion.camera")
        .hint("give the dataset a camera look_at (Shell or Poses), or the base scene's camera a LookAt"));
    };
    let (o, tg) = (Vec3::from(origin), Vec3::from(target));
    let span = times[times.len() - 1];
    let (path, p): (Vec<Vec3>, Value) = match tr {
        Trajectory::Orbit { speed } => {
            let sign = if r.unit() < 0.5 { -1.0 } else { 1.0 };
            let w = sign * r.range(*speed);
            let rel = o - tg;
            let at =
                |t: f32| tg + Mat4::from_rotation_y((w * t).to_radians()).transform_vector3(rel);
            (
                times.iter().map(|&t| at(t)).collect(),
                json!({"trajectory": "orbit", "degrees_per_second": w}),
            )
        }
        Trajectory::Dolly { speed } => {
            let dist = (tg - o).length();
            let drawn = r.range(*speed);
            // Never closer than a fifth of the start distance (nor through the target).
            let v = drawn.min(0.8 * dist / span.max(1e-6));
            let d = (tg - o) / dist;
            (
                times.iter().map(|&t| o + d * v * t).collect(),
                json!({"trajectory": "dolly", "speed": v, "drawn_speed": drawn}),
            )
        }
        Trajectory::Walk { speed, turn } => {
            let v = r.range(*speed);
            let mut heading = r.range((0.0, 360.0)).to_radians();
            let mut rate = r.symmetric(*turn);
            let dt = times[1] - times[0];
            let step = |h: f32| Vec3::new(h.sin(), 0.0, h.cos()) * v * dt;
            // Frame −1 lies one step behind the start, along the first heading.
            let mut pos = o - step(heading);
            let mut path = Vec::with_capacity(times.len());
            for _ in times {
                path.push(pos);
                // The turn rate drifts by at most half its bound per frame, within the bound.
                rate = (rate + 0.5 * r.symmetric(*turn)).clamp(-turn, *turn);
                heading += (rate * dt).to_radians();
                pos += step(heading);
            }
            (
                path,
                json!({"trajectory": "walk", "speed": v, "max_turn_degrees_per_second": turn}),
            )
        }
        Trajectory::Keyframes(_) => unreachable!("returned above"),
    };
    let keys = times
        .iter()
        .zip(path)
        .map(|(&t, o)| key(t, o, tg, up))
        .collect();
    Ok((keys, p))
}

/// Shape `idx`'s keys at `times`: its drawn pose (`scene`'s to_world, placement included)
/// carried along a line and turned about +y through its centre; what was drawn.
fn object_keys(
    base: &Base,
    idx: usize,
    om: &ObjectMotion,
    scene: &SceneConfig,
    times: &[f32],
    r: &mut Rng,
) -> Result<(Vec<KeyConfig>, Value), InputError> {
    let ops = &scene.shapes[idx].to_world;
    // What the frame added to the base scene's transform (the placement): the base bounds
    // are the shape's world box before it.
    let added = &ops[base.scene.shapes[idx].to_world.len().min(ops.len())..];
    let field = format!(
        "motion.objects: \"{}\"",
        scene.shapes[idx].name.as_deref().unwrap_or("")
    );
    let p = crate::load::transform(added, &base.file, &field)?.m;
    let (lo, hi) = base.bounds[idx];
    let centre = p.transform_point3(0.5 * (lo + hi));
    let scale = p.x_axis.truncate().length();
    let radius = 0.5 * glam::Vec2::new(hi.x - lo.x, hi.z - lo.z).length() * scale;
    let angle = r.range((0.0, 360.0)).to_radians();
    let dir = Vec3::new(angle.cos(), 0.0, angle.sin());
    let drawn = r.range(om.speed);
    let spin = r.range(om.spin);
    let mut v = drawn;
    // On a support: slow down until the footprint stays on its top face at every key.
    let support = base
        .config
        .objects
        .place
        .as_ref()
        .filter(|pl| pl.shapes.iter().any(|n| base.names.get(n) == Some(&idx)));
    if let Some(pl) = support {
        let (slo, shi) = base.bounds[base.names[&pl.support]];
        for &t in [times[0], times[times.len() - 1]].iter() {
            for (c, d, a, b) in [
                (centre.x, dir.x, slo.x + radius, shi.x - radius),
                (centre.z, dir.z, slo.z + radius, shi.z - radius),
            ] {
                let m = d * t;
                if m > 0.0 {
                    v = v.min(((b - c) / m).max(0.0));
                } else if m < 0.0 {
                    v = v.min(((a - c) / m).max(0.0));
                }
            }
        }
    }
    let keys = times
        .iter()
        .map(|&t| {
            let mut to_world = ops.clone();
            to_world.push(TransformOp::Translate((-centre).to_array()));
            to_world.push(TransformOp::Rotate {
                axis: [0.0, 1.0, 0.0],
                angle: spin * t,
            });
            to_world.push(TransformOp::Translate((centre + dir * v * t).to_array()));
            KeyConfig { time: t, to_world }
        })
        .collect();
    let p = json!({
        "direction": dir.to_array(), "speed": v, "drawn_speed": drawn,
        "spin_degrees_per_second": spin, "centre_at_0": centre.to_array(),
    });
    Ok((keys, p))
}

/// The sequence fields' own checks; sets `frames` to sequences × frames_per_sequence.
pub fn check(c: &mut super::DatasetConfig, file: &std::path::Path) -> Result<(), InputError> {
    let err = |field: &str, message: String, hint: &str| {
        Err(InputError::new(file, message).field(field).hint(hint))
    };
    if c.sequences == 0 {
        if c.frames_per_sequence != 0 || c.fps != 0.0 || c.motion.is_some() {
            return err(
                "sequences",
                "frames_per_sequence, fps and motion describe video sequences, and sequences is not given".into(),
                "give sequences: N (how many), or drop frames_per_sequence, fps and motion",
            );
        }
        return Ok(());
    }
    if c.frames_per_sequence == 0 {
        return err(
            "frames_per_sequence",
            "sequences need frames_per_sequence ≥ 1".into(),
            "e.g. frames_per_sequence: 8",
        );
    }
    if !(c.fps.is_finite() && c.fps > 0.0 && c.fps <= 1e6) {
        return err(
            "fps",
            format!(
                "fps {} must be a positive number of frames per second",
                c.fps
            ),
            "e.g. fps: 24",
        );
    }
    let total = c.sequences as u64 * c.frames_per_sequence as u64;
    if total > super::config::MAX_FRAMES as u64 {
        return err(
            "sequences",
            format!(
                "{} sequences of {} frames make {total} frames, more than {}",
                c.sequences,
                c.frames_per_sequence,
                super::config::MAX_FRAMES
            ),
            "split a larger dataset into several configs with different seeds",
        );
    }
    if c.frames != 0 && c.frames as u64 != total {
        return err(
            "frames",
            format!(
                "frames: {} differs from sequences × frames_per_sequence = {total}",
                c.frames
            ),
            "leave frames out with sequences (it is their product)",
        );
    }
    c.frames = total as u32;
    let m = c.motion.clone().unwrap_or_default();
    if !(m.shutter.is_finite() && (0.0..=1.0).contains(&m.shutter)) {
        return err(
            "motion.shutter",
            format!(
                "shutter {} must be a fraction of the frame interval in [0, 1]",
                m.shutter
            ),
            "e.g. shutter: 0.5 (a 180° shutter), 0 for instants",
        );
    }
    let ranges = m
        .objects
        .iter()
        .enumerate()
        .flat_map(|(k, o)| {
            [
                (format!("motion.objects[{k}].speed"), o.speed),
                (format!("motion.objects[{k}].spin"), o.spin),
            ]
        })
        .chain(match &m.camera {
            Some(
                Trajectory::Orbit { speed }
                | Trajectory::Dolly { speed }
                | Trajectory::Walk { speed, .. },
            ) => Some(("motion.camera.speed".to_string(), *speed)),
            _ => None,
        });
    for (field, (lo, hi)) in ranges {
        if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
            return err(
                &field,
                format!("the range ({lo}, {hi}) must be finite and increasing"),
                "give (lo, hi) with lo ≤ hi",
            );
        }
    }
    if let Some(Trajectory::Walk { turn, .. }) = &m.camera {
        if !(turn.is_finite() && *turn >= 0.0) {
            return err(
                "motion.camera.turn",
                format!("turn {turn} must be ≥ 0 degrees per second"),
                "e.g. turn: 30",
            );
        }
    }
    if let Some(Trajectory::Keyframes(keys)) = &m.camera {
        if keys.is_empty() {
            return err(
                "motion.camera",
                "Keyframes needs at least one key".into(),
                "e.g. Keyframes([(time: 0, origin: (0, 1, 4), target: (0, 0, 0))])",
            );
        }
    }
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
