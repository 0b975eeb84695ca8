//! Moving lights in the scene file: a point, spot or directional light or an environment map
//! with an `animation` (keys of its `to_world`, as a shape's; a point light's `position` and a
//! directional light's `direction` are given in that frame). At an instant each light is
//! written as its pose then and builds as a static light; with an open shutter it keeps its
//! own frame and its motion (`emitter::MovingLight`). Area lights move with their shape: on a
//! shape moving while the shutter is open, the light is sampled through the shape's motion
//! (`area`, `emitter::MovingArea`).

use crate::config::{EmitterConfig, Placement, SceneConfig, ShapeConfig};
use crate::emitter::{AreaEmitter, Emitter, MovingArea, MovingLight};
use crate::error::InputError;
use crate::motion::Motion;
use crate::shape::Shape;
use glam::Vec3;
use std::path::Path;

/// True if any light of `cfg` has an animation.
pub fn any(cfg: &SceneConfig) -> bool {
    cfg.emitters.iter().any(|e| e.animation().is_some())
}

/// Checks every light's animation. At an instant (`instant`, time `t`) writes each moving
/// light as its pose at `t` and returns no motions; with an open shutter returns each light's
/// motion (None for a still one), the lights left in their own frames.
pub fn prepare(
    cfg: &mut SceneConfig,
    file: &Path,
    t: f32,
    instant: bool,
) -> Result<Vec<Option<Motion>>, InputError> {
    let mut out = Vec::with_capacity(cfg.emitters.len());
    for (i, e) in cfg.emitters.iter().enumerate() {
        let field = format!("emitters[{i}]");
        let Some(a) = e.animation() else {
            out.push(None);
            continue;
        };
        let m = super::motion::motion(a, e.has_to_world(), file, &field)?;
        if matches!(e, EmitterConfig::Envmap { .. }) {
            rotation_only(&m, file, &field)?;
        }
        out.push(Some(m));
    }
    if !instant {
        return Ok(out);
    }
    for (e, m) in cfg.emitters.iter_mut().zip(&out) {
        let Some(m) = m else { continue };
        let at = m.matrix(t);
        match e.placement_mut() {
            Placement::Position(p) => *p = at.transform_point3(Vec3::from(*p)).into(),
            Placement::Direction(d) => *d = at.transform_vector3(Vec3::from(*d)).into(),
            Placement::ToWorld(w) => *w = vec![super::motion::matrix_op(at)],
            Placement::Fixed => {}
        }
        if let Some(a) = e.animation_mut() {
            *a = None;
        }
    }
    Ok(Vec::new())
}

/// An environment map's keys may only turn it.
fn rotation_only(m: &Motion, file: &Path, field: &str) -> Result<(), InputError> {
    let scaled = m
        .scale
        .values
        .iter()
        .position(|s| (*s - Vec3::ONE).abs().max_element() > 1e-4);
    let moved = m.translation.values.iter().position(|t| *t != Vec3::ZERO);
    if let Some(k) = scaled.or(moved) {
        return Err(InputError::new(
            file,
            "an environment map's keys may only rotate it (no scale or translation)",
        )
        .field(format!("{field}.animation.keys[{k}].to_world"))
        .hint("give each key Rotate steps only"));
    }
    Ok(())
}

/// Emitter `e` moving by `m` (None: `e` itself); `open` is the shutter's opening.
pub fn wrap(e: Emitter, m: Option<Motion>, open: f32) -> Emitter {
    match m {
        None => e,
        Some(motion) => Emitter::Moving(Box::new(MovingLight {
            light: e,
            motion,
            open,
        })),
    }
}

/// The area light of shape `sc` (None if it emits nothing), built on `shape` (object space,
/// scene index `index`) moving by `motion`; `at` is the scene file, the shape's field and the
/// render's wavelength range.
pub fn area(
    sc: &ShapeConfig,
    (shape, index): (&Shape, u32),
    motion: &Motion,
    (file, field, range): (&Path, &str, (f32, f32)),
    warnings: &mut Vec<String>,
) -> Result<Option<Emitter>, InputError> {
    let Some(e) = &sc.emitter else {
        return Ok(None);
    };
    let f = format!("{field}.emitter.radiance");
    let radiance = super::emission::area_radiance(&e.radiance, file, &f, range, warnings)?;
    super::emission::check_shape(&radiance, shape, file, &f)?;
    Ok(Some(Emitter::MovingArea(Box::new(MovingArea {
        area: AreaEmitter::with_radiance(index, shape, radiance),
        motion: motion.clone(),
        shape: shape.clone(),
    }))))
}
