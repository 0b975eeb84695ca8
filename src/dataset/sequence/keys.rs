//! The keys a sequence moves the camera and the objects by (`super::animate`): the camera
//! along its trajectory from the frame's drawn pose, each object along a line over its
//! support while it spins.

use super::{ObjectMotion, Trajectory};
use crate::config::{KeyConfig, SceneConfig, TransformOp};
use crate::dataset::base::Base;
use crate::dataset::vary::Rng;
use crate::error::InputError;
use crate::math::{portable, rotation};
use glam::Vec3;
use serde_json::{json, Value};

/// The camera's keys at `times` along trajectory `tr`, from the frame's drawn pose `ops`
/// (ending in a LookAt, after its roll), and what was drawn.
pub(super) fn camera_keys(
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
            let at = |t: f32| {
                tg + rotation::axis_angle(Vec3::Y, (w * t).to_radians()).transform_vector3(rel)
            };
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
            let step = |h: f32| Vec3::new(portable::sin(h), 0.0, portable::cos(h)) * v * dt;
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
pub(super) fn object_keys(
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
    let dir = Vec3::new(portable::cos(angle), 0.0, portable::sin(angle));
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
