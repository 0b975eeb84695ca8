//! Lights moving along a sequence (`motion.lights`): each listed light is drawn, once per
//! sequence from its own stream, a horizontal direction and a speed (units per second) and an
//! orbit rate about the vertical axis through the world origin (degrees per second). At time t
//! its pose is its drawn pose (the frame's `to_world`, or a point light's position, a
//! directional light's direction) carried by Translate(direction · speed · t) then
//! Rotate(+y, rate · t), written as keys at every frame time as the objects' are. A directional
//! light and an environment map only turn (a translation moves nothing at infinity, and an
//! environment map's keys may only rotate it); a constant environment cannot move.

use super::LightMotion;
use crate::config::TransformOp;
use crate::config::{AnimationConfig, EmitterConfig, KeyConfig, Placement, SceneConfig};
use crate::dataset::base::{Base, LightRef};
use crate::dataset::vary::Rng;
use crate::error::InputError;
use crate::math::portable;
use glam::{Mat4, Vec3};
use serde_json::{json, Value};

/// Moves light `target` of `scene` (listed in `field`) by `lm` with draws from `r`, keyed at
/// `times`; returns what was drawn and its pose at `t`, or None for a hidden area light.
pub(super) fn animate(
    base: &Base,
    (lm, target, field): (&LightMotion, &str, &str),
    scene: &mut SceneConfig,
    shown: &[bool],
    times: &[f32],
    t: f32,
    r: &mut Rng,
) -> Result<Option<Value>, InputError> {
    let angle = r.range((0.0, 360.0)).to_radians();
    let dir = Vec3::new(portable::cos(angle), 0.0, portable::sin(angle));
    let speed = r.range(lm.speed);
    let orbit = r.range(lm.orbit);
    let busy = |what: &str| {
        Err(InputError::new(&base.file, format!("light \"{target}\" {what}"))
            .field(field.to_string())
            .hint("list each light once, and not also in motion.objects or with an animation of its own"))
    };
    let (ops, translate, point) = match base.light(target, field)? {
        LightRef::Shape(i) => {
            if !shown[i] {
                return Ok(None);
            }
            let sc = &mut scene.shapes[i];
            if sc.animation.is_some() {
                return busy("already moves (motion.objects, another entry, or its own animation)");
            }
            let ops = std::mem::take(&mut sc.to_world);
            let keys = keys(&ops, times, dir * speed, orbit, true);
            sc.animation = Some(AnimationConfig {
                interpolation: Default::default(),
                keys,
            });
            (ops, true, None)
        }
        LightRef::Emitter(e) => {
            let em = &mut scene.emitters[e];
            if matches!(em, EmitterConfig::Constant { .. }) {
                return Err(InputError::new(
                    &base.file,
                    format!("light \"{target}\" is a constant environment, which cannot move"),
                )
                .field(field.to_string())
                .hint("list point, spot, directional, environment-map or area lights only"));
            }
            // A translation moves nothing at infinity (and an environment map may only turn).
            let at_infinity = matches!(
                em,
                EmitterConfig::Directional { .. } | EmitterConfig::Envmap { .. }
            );
            if em.animation().is_some() {
                return busy("already has an animation in the base scene");
            }
            let translate = !at_infinity;
            let (ops, point) = match em.placement_mut() {
                Placement::ToWorld(w) => (std::mem::take(w), None),
                Placement::Position(p) => (Vec::new(), Some((Vec3::from(*p), true))),
                Placement::Direction(d) => (Vec::new(), Some((Vec3::from(*d), false))),
                Placement::Fixed => unreachable!("constant environments are refused above"),
            };
            let keys = keys(&ops, times, dir * speed, orbit, translate);
            if let Some(a) = em.animation_mut() {
                *a = Some(AnimationConfig {
                    interpolation: Default::default(),
                    keys,
                });
            }
            (ops, translate, point)
        }
    };
    let at = crate::load::transform(
        &pose(&ops, dir * speed, orbit, translate, t),
        &base.file,
        field,
    )?
    .m;
    let rows: Vec<[f32; 4]> = (0..4).map(|i| at.row(i).to_array()).collect();
    let mut p = json!({
        "target": target, "direction": dir.to_array(),
        "speed": if translate { speed } else { 0.0 }, "orbit_degrees_per_second": orbit,
        "to_world": rows,
    });
    match point {
        Some((q, true)) => p["position"] = json!(at.transform_point3(q).to_array()),
        Some((d, false)) => p["light_direction"] = json!(turn(&at, d).to_array()),
        None => {}
    }
    Ok(Some(p))
}

/// The keys at `times` (one per frame time, as the objects').
fn keys(
    ops: &[TransformOp],
    times: &[f32],
    v: Vec3,
    orbit: f32,
    translate: bool,
) -> Vec<KeyConfig> {
    times
        .iter()
        .map(|&t| KeyConfig {
            time: t,
            to_world: pose(ops, v, orbit, translate, t),
        })
        .collect()
}

/// The light's `to_world` at time `t`: its drawn one, then the slide, then the orbit.
fn pose(ops: &[TransformOp], v: Vec3, orbit: f32, translate: bool, t: f32) -> Vec<TransformOp> {
    let mut out = ops.to_vec();
    if translate {
        out.push(TransformOp::Translate((v * t).to_array()));
    }
    out.push(TransformOp::Rotate {
        axis: [0.0, 1.0, 0.0],
        angle: orbit * t,
    });
    out
}

/// A directional light's direction turned by `m` (unit).
fn turn(m: &Mat4, d: Vec3) -> Vec3 {
    m.transform_vector3(d).normalize_or(d)
}
