//! Objects stood on a support surface without overlap: each shape's footprint is the circle
//! around its bounding box in the xz-plane (so any yaw keeps it), scaled; positions are drawn
//! uniformly where the circle stays on the support's top face, and drawn again while it comes
//! within `gap` of a shape already placed.

use super::apply;
use super::base::Base;
use super::config::Placement;
use super::vary::{Rng, Stream};
use crate::config::{SceneConfig, TransformOp};
use crate::error::InputError;
use glam::{Vec2, Vec3};
use serde_json::{json, Value};

/// Places the shown shapes of `p` in `scene` (appending to their `to_world`) and updates
/// `bounds` to conservative boxes around them; returns what was drawn.
pub fn place(
    base: &Base,
    p: &Placement,
    frame: u32,
    shown: &[bool],
    scene: &mut SceneConfig,
    bounds: &mut [(Vec3, Vec3)],
) -> Result<Value, InputError> {
    let mut r = Rng::new(base.config.seed, frame, Stream::Place);
    let (slo, shi) = base.bounds[base.names[&p.support]];
    let top = shi.y;
    let mut placed: Vec<(Vec2, f32)> = Vec::new();
    let mut out = Vec::new();
    for name in &p.shapes {
        let k = base.names[name];
        if !shown[k] {
            continue;
        }
        let (lo, hi) = base.bounds[k];
        let radius = 0.5 * Vec2::new(hi.x - lo.x, hi.z - lo.z).length();
        let mut done = None;
        for attempt in 1..=p.max_attempts {
            let s = p.scale.map_or(1.0, |x| r.range(x));
            let yaw = p.yaw.map_or(0.0, |x| r.range(x));
            let rad = radius * s;
            let (x0, x1) = (slo.x + rad, shi.x - rad);
            let (z0, z1) = (slo.z + rad, shi.z - rad);
            if x0 > x1 || z0 > z1 {
                continue;
            }
            let at = Vec2::new(r.range((x0, x1)), r.range((z0, z1)));
            if placed
                .iter()
                .all(|(q, rq)| q.distance(at) >= rq + rad + p.gap)
            {
                done = Some((at, s, yaw, rad, attempt));
                break;
            }
        }
        let Some((at, s, yaw, rad, attempt)) = done else {
            return Err(InputError::new(
                &base.file,
                format!(
                    "frame {frame}: \"{name}\" found no free place on \"{}\" in {} attempts",
                    p.support, p.max_attempts
                ),
            )
            .field("objects.place")
            .hint("place fewer or smaller shapes, lower `gap`, use a larger support, or raise max_attempts"));
        };
        placed.push((at, rad));
        // Base centre to the origin, scale, turn, then onto the support at `at`.
        let c = Vec3::new(0.5 * (lo.x + hi.x), lo.y, 0.5 * (lo.z + hi.z));
        let ops = &mut scene.shapes[k].to_world;
        ops.push(TransformOp::Translate((-c).to_array()));
        ops.push(TransformOp::Scale([s, s, s]));
        ops.push(apply::yaw(yaw));
        ops.push(TransformOp::Translate([at.x, top, at.y]));
        let h = (hi.y - lo.y) * s;
        bounds[k] = (
            Vec3::new(at.x - rad, top, at.y - rad),
            Vec3::new(at.x + rad, top + h, at.y + rad),
        );
        out.push(json!({
            "shape": name, "position": [at.x, top, at.y], "yaw": yaw, "scale": s, "attempts": attempt,
        }));
    }
    Ok(Value::Array(out))
}
