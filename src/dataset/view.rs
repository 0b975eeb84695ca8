//! `camera.keep_in_view`: whether every corner of each watched shape's world box projects
//! inside the image, at the drawn pose (`in_view`) and, in a video dataset, at every frame of
//! the sequence (`throughout`): the camera on its trajectory and each shape at its pose then,
//! so that a shape drawn to move, or a camera that moves, cannot carry it out of the frame.

use super::base::Base;
use crate::camera::Camera;
use crate::config::{CameraConfig, SceneConfig};
use crate::error::InputError;
use glam::{Mat4, Vec3};
use std::path::Path;

/// Whether every corner of each watched shape's bounds projects inside the image.
pub fn in_view(
    cam: &CameraConfig,
    scene: &SceneConfig,
    file: &Path,
    watched: &[usize],
    bounds: &[(Vec3, Vec3)],
) -> Result<bool, InputError> {
    if watched.is_empty() {
        return Ok(true);
    }
    let camera = camera(cam, scene, file)?;
    Ok(watched
        .iter()
        .all(|&k| corners(bounds[k]).all(|p| camera.project(p, 0.0).is_some())))
}

/// Whether the watched shapes stay in view at every frame of frame `i`'s sequence: `scene`
/// holds the drawn camera pose and the shapes' placed poses, whose world boxes are `bounds`.
/// Each frame's instant is tested, and its shutter's close when the frames are blurred. The
/// test depends on the sequence only (not on `i`'s place in it), so every frame of a
/// sequence keeps the same pose and a frame rendered alone matches the full run.
pub fn throughout(
    base: &Base,
    i: u32,
    scene: &SceneConfig,
    shown: &[bool],
    watched: &[usize],
    bounds: &[(Vec3, Vec3)],
) -> Result<bool, InputError> {
    let c = &base.config;
    if c.sequences == 0 || watched.is_empty() {
        return Ok(true);
    }
    // The answer depends on the sequence and the drawn poses only (not on `i`'s place).
    let key = {
        use std::hash::{Hash, Hasher};
        let mut h = std::collections::hash_map::DefaultHasher::new();
        let seq = super::sequence::draw_index(base, i);
        format!("{seq} {scene:?} {shown:?} {watched:?} {bounds:?}").hash(&mut h);
        h.finish()
    };
    let known = |b: &Base| {
        b.views
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .get(&key)
            .copied()
    };
    if let Some(ok) = known(base) {
        return Ok(ok);
    }
    let ok = sweep(base, i, scene, shown, watched, bounds)?;
    base.views
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .insert(key, ok);
    Ok(ok)
}

/// `throughout` without the memo: every frame's instant of the sequence.
fn sweep(
    base: &Base,
    i: u32,
    scene: &SceneConfig,
    shown: &[bool],
    watched: &[usize],
    bounds: &[(Vec3, Vec3)],
) -> Result<bool, InputError> {
    let c = &base.config;
    let mut moved = scene.clone();
    let mut drawn = serde_json::Map::new();
    super::sequence::animate(base, i, &mut moved, shown, &mut drawn)?;
    // Only the camera and the watched shapes: their poses at an instant.
    let poses = SceneConfig {
        camera: moved.camera.clone(),
        film: moved.film.clone(),
        shapes: watched.iter().map(|&k| moved.shapes[k].clone()).collect(),
        ..Default::default()
    };
    // The placed pose each watched box was measured at, undone before the pose at t.
    let mut placed = Vec::with_capacity(watched.len());
    for &k in watched {
        let field = format!("shapes[{k}]");
        let m = crate::load::transform(&scene.shapes[k].to_world, &base.scene_file, &field)?.m;
        placed.push(m.inverse());
    }
    let shutter = c.motion.as_ref().map_or(0.0, |m| m.shutter.max(0.0)) / c.fps;
    let times = (0..c.frames_per_sequence).flat_map(|k| {
        let t = k as f32 / c.fps;
        [Some(t), (shutter > 0.0).then_some(t + shutter)]
    });
    // The motions checked once, then posed per instant without their keys (linear in the
    // frames: a copy of the keys per instant was quadratic).
    let motions = crate::load::motion::Poses::new(&poses, &base.scene_file)?;
    let mut at = poses.clone();
    at.camera.animation = None;
    at.shapes.iter_mut().for_each(|s| s.animation = None);
    for t in times.flatten() {
        motions.set(&mut at, t);
        let camera = camera(&at.camera, &at, &base.scene_file)?;
        for (j, &k) in watched.iter().enumerate() {
            let m = match poses.shapes[j].animation {
                Some(_) => {
                    let field = format!("shapes[{k}]");
                    let now =
                        crate::load::transform(&at.shapes[j].to_world, &base.scene_file, &field)?;
                    now.m * placed[j]
                }
                None => Mat4::IDENTITY,
            };
            let inside = corners(bounds[k]).all(|p| {
                let q = m.transform_point3(p);
                camera.project(q, 0.0).is_some()
            });
            if !inside {
                return Ok(false);
            }
        }
    }
    Ok(true)
}

/// The pinhole (or other) camera `cam` of `scene`'s film.
fn camera(cam: &CameraConfig, scene: &SceneConfig, file: &Path) -> Result<Camera, InputError> {
    let t = crate::load::transform(&cam.to_world, file, "camera")?;
    let f = &scene.film;
    Ok(match &cam.intrinsics {
        Some(k) => Camera::Pinhole(crate::camera::Pinhole::with_intrinsics(
            t,
            crate::camera::Intrinsics::from_k(k.fx, k.fy, k.cx, k.cy, f.width, f.height),
            cam.near_clip,
            cam.far_clip,
        )),
        None => Camera::new(
            t,
            cam.fov,
            cam.fov_axis,
            cam.near_clip,
            cam.far_clip,
            f.width,
            f.height,
        ),
    })
}

/// The eight corners of the box (lo, hi).
fn corners((lo, hi): (Vec3, Vec3)) -> impl Iterator<Item = Vec3> {
    (0..8).map(move |c| {
        Vec3::new(
            if c & 1 == 0 { lo.x } else { hi.x },
            if c & 2 == 0 { lo.y } else { hi.y },
            if c & 4 == 0 { lo.z } else { hi.z },
        )
    })
}
