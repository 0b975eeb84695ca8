//! Time in the scene: the camera's shutter and the keyframed transforms of the camera and the
//! shapes, checked and turned into `Motion`s. At an instant (no shutter, a zero-length one or
//! `prism render --time T`) every animated `to_world` is replaced by its value then, and the
//! scene builds as a static one; only a shutter that stays open leaves motion to the renderer.

use super::check::check;
use super::geometry::transform;
use crate::config::{AnimationConfig, Interpolation, SceneConfig, ShutterConfig, TransformOp};
use crate::error::InputError;
use crate::motion::keyframes::{catmull_rom, catmull_rom_rotations};
use crate::motion::{Interp, Motion, Shutter, Track};
use glam::{Mat4, Quat, Vec3};
use std::path::Path;

/// What moves while the shutter is open.
pub struct Plan {
    pub shutter: Shutter,
    pub camera: Option<Motion>,
    /// Per entry of `shapes`, its motion if it has one.
    pub shapes: Vec<Option<Motion>>,
    /// Per entry of `emitters`, its motion if it has one (`light_motion`).
    pub lights: Vec<Option<Motion>>,
}

/// Checks the shutter and every animation. At an instant, writes each animated `to_world` as
/// its value then and returns None; with an open shutter, writes each as its value at
/// `open` (the pose the sidecar reports) and returns what moves (None if nothing does).
pub fn prepare(cfg: &mut SceneConfig, file: &Path) -> Result<Option<Plan>, InputError> {
    prepare_moving(cfg, file, None)
}

/// As `prepare`, with `given` the camera's motion from elsewhere (a glTF camera, checked by
/// its loader) in place of `camera.animation`.
pub fn prepare_moving(
    cfg: &mut SceneConfig,
    file: &Path,
    given: Option<&Motion>,
) -> Result<Option<Plan>, InputError> {
    let shutter = match cfg.camera.shutter {
        None => Shutter {
            open: 0.0,
            close: 0.0,
            readout: 0.0,
        },
        Some(s) => shutter(s, file)?,
    };
    let camera = match &cfg.camera.animation {
        None => given.cloned(),
        Some(a) => {
            let m = motion(a, !cfg.camera.to_world.is_empty(), file, "camera")?;
            camera_poses(&m, file)?;
            Some(m)
        }
    };
    let mut shapes = Vec::with_capacity(cfg.shapes.len());
    for (i, sc) in cfg.shapes.iter().enumerate() {
        let field = format!("shapes[{i}]");
        shapes.push(match &sc.animation {
            None => None,
            Some(a) => Some(motion(a, !sc.to_world.is_empty(), file, &field)?),
        });
    }
    // The pose at the instant, or at the shutter's opening.
    let at = |m: &Motion| vec![matrix_op(m.matrix(shutter.open))];
    if let Some(m) = &camera {
        cfg.camera.to_world = at(m);
    }
    for (sc, m) in cfg.shapes.iter_mut().zip(&shapes) {
        if let Some(m) = m {
            sc.to_world = at(m);
        }
    }
    let instant = shutter.open == shutter.close && shutter.readout == 0.0;
    let moving_lights = super::light_motion::any(cfg);
    let lights = super::light_motion::prepare(cfg, file, shutter.open, instant)?;
    // A glTF file may animate its own nodes (`load::gltf::animation`), and lights may move:
    // an open shutter keeps its timing for them.
    let others = cfg
        .shapes
        .iter()
        .any(|s| matches!(s.shape, crate::config::ShapeKind::Gltf { .. }))
        || moving_lights;
    if instant || (camera.is_none() && shapes.iter().all(Option::is_none) && !others) {
        cfg.camera.animation = None;
        cfg.shapes.iter_mut().for_each(|s| s.animation = None);
        return Ok(None);
    }
    Ok(Some(Plan {
        shutter,
        camera,
        shapes,
        lights,
    }))
}

/// The camera's and shapes' poses of `cfg` at many instants, its keys checked once: `prepare`
/// at each instant checks every key again, so a sequence of n frames with a key per frame
/// (`dataset::view`) cost n² (65,536 frames ran for hours: fuzz run 13, case 656123).
pub struct Poses {
    camera: Option<Motion>,
    shapes: Vec<Option<Motion>>,
}

impl Poses {
    /// Checks `cfg` as `prepare` at an instant does, and keeps its motions.
    pub fn new(cfg: &SceneConfig, file: &Path) -> Result<Poses, InputError> {
        let mut first = cfg.clone();
        set_time(&mut first, 0.0);
        prepare(&mut first, file)?;
        let camera = match &cfg.camera.animation {
            None => None,
            Some(a) => Some(motion(a, !cfg.camera.to_world.is_empty(), file, "camera")?),
        };
        let mut shapes = Vec::with_capacity(cfg.shapes.len());
        for (i, sc) in cfg.shapes.iter().enumerate() {
            shapes.push(match &sc.animation {
                None => None,
                Some(a) => Some(motion(
                    a,
                    !sc.to_world.is_empty(),
                    file,
                    &format!("shapes[{i}]"),
                )?),
            });
        }
        Ok(Poses { camera, shapes })
    }

    /// Sets the `to_world` of `at` (`cfg` as `new` took it, or a copy without its animations)
    /// to the poses at `t`, as `prepare` at the instant `t` does.
    pub fn set(&self, at: &mut SceneConfig, t: f32) {
        if let Some(m) = &self.camera {
            at.camera.to_world = vec![matrix_op(m.matrix(t))];
        }
        for (sc, m) in at.shapes.iter_mut().zip(&self.shapes) {
            if let Some(m) = m {
                sc.to_world = vec![matrix_op(m.matrix(t))];
            }
        }
    }
}

/// `prism render --time T`: the scene at the instant T.
pub fn set_time(cfg: &mut SceneConfig, t: f32) {
    cfg.camera.shutter = Some(ShutterConfig {
        open: t,
        close: t,
        readout: 0.0,
    });
}

fn shutter(s: ShutterConfig, file: &Path) -> Result<Shutter, InputError> {
    let f = "camera.shutter";
    check(
        s.open.is_finite(),
        file,
        &format!("{f}.open"),
        format!("open {} is not a finite number of seconds", s.open),
    )?;
    check(
        s.close.is_finite(),
        file,
        &format!("{f}.close"),
        format!("close {} is not a finite number of seconds", s.close),
    )?;
    if s.close < s.open {
        return Err(InputError::new(
            file,
            format!(
                "the shutter closes (close: {}) before it opens (open: {})",
                s.close, s.open
            ),
        )
        .field(format!("{f}.close"))
        .hint("give close ≥ open (close = open renders the instant)"));
    }
    check(
        s.readout.is_finite() && s.readout >= 0.0,
        file,
        &format!("{f}.readout"),
        format!(
            "readout {} must be ≥ 0 seconds per row (0: a global shutter)",
            s.readout
        ),
    )?;
    Ok(Shutter {
        open: s.open,
        close: s.close,
        readout: s.readout,
    })
}

/// An animation's keys as translation, rotation and scale tracks. `owner` is the field of the
/// camera or shape (`camera`, `shapes[2]`); `has_to_world`: it also gives a `to_world`.
pub(super) fn motion(
    a: &AnimationConfig,
    has_to_world: bool,
    file: &Path,
    owner: &str,
) -> Result<Motion, InputError> {
    let f = format!("{owner}.animation");
    if has_to_world {
        return Err(InputError::new(
            file,
            "both to_world and animation are given; the animation's keys set to_world",
        )
        .field(format!("{owner}.to_world"))
        .hint("move the transform into each key's to_world, or drop the animation"));
    }
    check(
        !a.keys.is_empty(),
        file,
        &format!("{f}.keys"),
        "an animation needs at least one key: keys: [(time: 0, to_world: [...])]",
    )?;
    let mut times = Vec::with_capacity(a.keys.len());
    let mut parts = Vec::with_capacity(a.keys.len());
    for (k, key) in a.keys.iter().enumerate() {
        let kf = format!("{f}.keys[{k}]");
        check(
            key.time.is_finite(),
            file,
            &format!("{kf}.time"),
            format!("time {} is not a finite number of seconds", key.time),
        )?;
        if let Some(&prev) = times.last() {
            if key.time == prev {
                return Err(InputError::new(
                    file,
                    format!("keys[{}] and keys[{k}] share the time {prev}", k - 1),
                )
                .field(format!("{kf}.time"))
                .hint("give each key a time of its own (a jump needs Step interpolation, not two keys at one time)"));
            }
            if key.time < prev {
                return Err(InputError::new(
                    file,
                    format!(
                        "keys are out of order: keys[{k}].time {} comes before keys[{}].time {prev}",
                        key.time,
                        k - 1
                    ),
                )
                .field(format!("{kf}.time"))
                .hint("list the keys in increasing time"));
            }
        }
        let m = transform(&key.to_world, file, &format!("{kf}.to_world"))?.m;
        let (s, r, t) = m.to_scale_rotation_translation();
        let back = Mat4::from_scale_rotation_translation(s, r, t);
        let (size, err) = (max_abs(m), max_abs(back - m));
        // 1e-4 of the matrix's largest entry: far above f32 rounding, far below a real shear.
        check(
            err <= 1e-4 * size.max(1.0),
            file,
            &format!("{kf}.to_world"),
            "this key's transform shears (a Scale between rotations); a key must be a \
             translation, a rotation and a scale along the object's own axes",
        )?;
        times.push(key.time);
        parts.push((t, r, s));
    }
    let interp = match a.interpolation {
        Interpolation::Step => Interp::Step,
        Interpolation::Linear => Interp::Linear,
        Interpolation::Cubic => Interp::Cubic,
    };
    let translation: Vec<Vec3> = parts.iter().map(|p| p.0).collect();
    let mut rotation: Vec<Quat> = parts.iter().map(|p| p.1).collect();
    let scale: Vec<Vec3> = parts.iter().map(|p| p.2).collect();
    let cubic = interp == Interp::Cubic;
    let rot_tangents = catmull_rom_rotations(&times, &mut rotation);
    let track = |values: Vec<Vec3>| Track {
        tangents: if cubic {
            catmull_rom(&times, &values)
        } else {
            Vec::new()
        },
        times: times.clone(),
        values,
        interp,
    };
    Ok(Motion {
        translation: track(translation),
        scale: track(scale),
        rotation: Track {
            times: times.clone(),
            values: rotation,
            tangents: if cubic { rot_tangents } else { Vec::new() },
            interp,
        },
        parent: None,
    })
}

/// Every key of a camera's animation must be a pose (rotation, translation, uniform scale).
fn camera_poses(m: &Motion, file: &Path) -> Result<(), InputError> {
    for (k, &t) in m.translation.times.iter().enumerate() {
        let tr = crate::math::Transform::from_matrix(m.matrix(t));
        let why = match tr {
            None => Some("it is singular".to_string()),
            Some(tr) => crate::camera::pose_error(&tr),
        };
        if let Some(why) = why {
            return Err(InputError::new(
                file,
                format!(
                    "this key's to_world is not a rotation, translation and uniform scale: {why}"
                ),
            )
            .field(format!("camera.animation.keys[{k}].to_world"))
            .hint("write each camera key as a rotation and a translation (a uniform scale at most), without shear or mirroring"));
        }
    }
    Ok(())
}

/// A matrix as the config writes it (row-major).
pub(super) fn matrix_op(m: Mat4) -> TransformOp {
    TransformOp::Matrix(m.transpose().to_cols_array_2d())
}

/// Shape `sc` in object space, for a shape moving while the shutter is open (an area light on
/// it moves with it: `light_motion::area`). A glTF model cannot move during an exposure yet.
pub fn object_space(
    sc: &crate::config::ShapeConfig,
    file: &Path,
    field: &str,
) -> Result<crate::config::ShapeConfig, InputError> {
    if matches!(sc.shape, crate::config::ShapeKind::Gltf { .. }) {
        return Err(InputError::new(
            file,
            "a glTF shape cannot move while the shutter is open (only at an instant)",
        )
        .field(format!("{field}.animation"))
        .hint("render instants (prism render --time T, or shutter open = close), or animate RON shapes"));
    }
    let mut obj = sc.clone();
    obj.to_world.clear();
    Ok(obj)
}

/// The scene's motions from the plan: the moving shapes (scene index, motion) and the timing.
pub fn motions(
    plan: Option<Plan>,
    shapes: Vec<(u32, Motion)>,
    cfg: &SceneConfig,
    (_, height): (u32, u32),
    file: &Path,
) -> Result<crate::scene::Motions, InputError> {
    let Some(plan) = plan else {
        return Ok(crate::scene::Motions::default());
    };
    check(
        cfg.integrator.caustics.is_none(),
        file,
        "integrator.caustics",
        "caustic light tracing traces light at one instant; it cannot render an open shutter \
         (drop the caustics, or render an instant: shutter open = close)",
    )?;
    let camera = plan.camera.map(|m| {
        let open_inv = m.matrix(plan.shutter.open).inverse();
        (m, open_inv)
    });
    Ok(crate::scene::Motions {
        shapes,
        timing: Some(crate::scene::SceneTiming {
            timing: crate::motion::Timing {
                shutter: plan.shutter,
                camera,
            },
            span: plan.shutter.span(height),
        }),
    })
}

/// The largest absolute entry of `m`: the scale of a matrix, and of its difference from its
/// scale-rotation-translation rebuild when checking for shear.
pub(crate) fn max_abs(m: Mat4) -> f32 {
    m.abs()
        .to_cols_array()
        .iter()
        .fold(0.0f32, |a, &b| a.max(b))
}
