//! glTF 2.0 animations (§3.11): translation, rotation and scale channels on nodes, with LINEAR
//! (rotations: slerp), STEP and CUBICSPLINE samplers, times in seconds. One animation is read:
//! the first, or the one the shape names (`Gltf(animation: "Walk")`, or its index, `"1"`).
//! Morph target `weights` channels and skins are not read (a warning says so).
//!
//! The JSON is checked first (`check_json`, in `json`): the gltf crate's reader assumes each
//! sampler's accessors have the right type and count and would panic, or read garbage,
//! otherwise.

use crate::error::InputError;
use crate::motion::{Interp, Motion, Track};
use glam::{Mat4, Quat, Vec3};
use std::collections::HashMap;
use std::path::Path;

mod json;
pub use json::check_json;

/// One animation's tracks, per animated node.
pub struct Clip {
    pub nodes: HashMap<usize, NodeTracks>,
}

/// A node's animated channels (None: the node's own value, held).
#[derive(Default)]
pub struct NodeTracks {
    pub translation: Option<Track<Vec3>>,
    pub rotation: Option<Track<Quat>>,
    pub scale: Option<Track<Vec3>>,
}

impl NodeTracks {
    /// The node's motion: its animated channels, the others held at `node`'s TRS.
    pub fn motion(&self, node: &gltf::Node) -> Motion {
        let (t, r, s) = node.transform().decomposed();
        Motion {
            translation: self
                .translation
                .clone()
                .unwrap_or_else(|| Track::constant(Vec3::from(t))),
            rotation: self
                .rotation
                .clone()
                .unwrap_or_else(|| Track::constant(Quat::from_array(r).normalize())),
            scale: self
                .scale
                .clone()
                .unwrap_or_else(|| Track::constant(Vec3::from(s))),
            parent: None,
        }
    }

    /// The node's local transform at time `t`.
    pub fn local(&self, node: &gltf::Node, t: f32) -> Mat4 {
        self.motion(node).matrix(t)
    }
}

pub(super) fn err(
    path: &Path,
    field: String,
    message: impl Into<String>,
    hint: &str,
) -> InputError {
    InputError::new(path, message).field(field).hint(hint)
}

pub(super) const REEXPORT: &str =
    "re-export the animation (glTF 2.0 §3.11), or check the file with the Khronos glTF validator";

/// The animation `select` names (a name, or an index as text), else the first; None if the
/// file has none. Warnings for what is not read go to `warnings`.
pub fn read(
    model: &super::Model,
    select: Option<&str>,
    warnings: &mut Vec<String>,
) -> Result<Option<Clip>, InputError> {
    let path = &model.path;
    let doc = &model.doc;
    if doc.skins().next().is_some() {
        let w = format!(
            "{}: skins: skinned meshes are not deformed by their joints; they render in their bind pose",
            path.display()
        );
        if !warnings.contains(&w) {
            warnings.push(w);
        }
    }
    let anim = match select {
        None => doc.animations().next(),
        Some(s) => {
            let found = doc.animations().find(|a| a.name() == Some(s)).or_else(|| {
                s.parse::<usize>()
                    .ok()
                    .and_then(|k| doc.animations().nth(k))
            });
            if found.is_none() {
                let names: Vec<String> = doc
                    .animations()
                    .map(|a| match a.name() {
                        Some(n) => format!("{} (\"{n}\")", a.index()),
                        None => a.index().to_string(),
                    })
                    .collect();
                return Err(InputError::new(
                    path,
                    format!("the file has no animation named or numbered \"{s}\" (the shape's `animation`)"),
                )
                .field("animations")
                .hint(if names.is_empty() {
                    "the file has no animations: drop `animation`".to_string()
                } else {
                    format!("its animations are: {}", names.join(", "))
                }));
            }
            found
        }
    };
    let Some(anim) = anim else {
        return Ok(None);
    };
    let data = |b: gltf::Buffer| model.buffers.get(b.index()).map(|d| &d.0[..]);
    let mut clip = Clip {
        nodes: HashMap::new(),
    };
    let at = format!("animations[{}]", anim.index());
    for ch in anim.channels() {
        let sf = format!("{at}.samplers[{}]", ch.sampler().index());
        let reader = ch.reader(data);
        let missing = |what: &str| {
            err(
                path,
                format!("{sf}.{what}"),
                format!("the sampler's {what} accessor has no data"),
                REEXPORT,
            )
        };
        let times: Vec<f32> = reader
            .read_inputs()
            .ok_or_else(|| missing("input"))?
            .collect();
        for (k, w) in times.windows(2).enumerate() {
            if w[0].partial_cmp(&w[1]) != Some(std::cmp::Ordering::Less) {
                return Err(err(
                    path,
                    format!("{sf}.input"),
                    format!(
                        "key times must increase: key {k} is at {} s and key {} at {} s",
                        w[0],
                        k + 1,
                        w[1]
                    ),
                    "give each key a later time than the one before (glTF 2.0 §3.11: strictly increasing); re-export the animation",
                ));
            }
        }
        if let Some(k) = times.iter().position(|t| !t.is_finite()) {
            return Err(err(
                path,
                format!("{sf}.input"),
                format!(
                    "key {k}'s time {} is not a finite number of seconds",
                    times[k]
                ),
                REEXPORT,
            ));
        }
        let interp = match ch.sampler().interpolation() {
            gltf::animation::Interpolation::Linear => Interp::Linear,
            gltf::animation::Interpolation::Step => Interp::Step,
            gltf::animation::Interpolation::CubicSpline => Interp::Cubic,
        };
        let node = ch.target().node().index();
        let outputs = reader.read_outputs().ok_or_else(|| missing("output"))?;
        use gltf::animation::util::ReadOutputs;
        let nonfinite = || {
            err(
                path,
                format!("{sf}.output"),
                "the sampler's output holds a value that is not finite",
                REEXPORT,
            )
        };
        let tracks = clip.nodes.entry(node).or_default();
        match outputs {
            ReadOutputs::Translations(it) => {
                let v: Vec<Vec3> = it.map(Vec3::from).collect();
                if !v.iter().all(|x| x.is_finite()) {
                    return Err(nonfinite());
                }
                tracks.translation = Some(track(times, v, interp));
            }
            ReadOutputs::Scales(it) => {
                let v: Vec<Vec3> = it.map(Vec3::from).collect();
                if !v.iter().all(|x| x.is_finite()) {
                    return Err(nonfinite());
                }
                tracks.scale = Some(track(times, v, interp));
            }
            ReadOutputs::Rotations(r) => {
                let raw: Vec<Quat> = r.into_f32().map(Quat::from_array).collect();
                if !raw.iter().all(|q| q.is_finite()) {
                    return Err(nonfinite());
                }
                // Values are normalised (tangents are not: they are derivatives).
                let mut v = raw;
                let step = if interp == Interp::Cubic { 3 } else { 1 };
                for (k, q) in v.iter_mut().enumerate() {
                    if step == 1 || k % 3 == 1 {
                        if q.length() < 1e-6 {
                            return Err(err(
                                path,
                                format!("{sf}.output"),
                                format!("rotation key {} is the zero quaternion", k / step),
                                REEXPORT,
                            ));
                        }
                        *q = q.normalize();
                    }
                }
                tracks.rotation = Some(track(times, v, interp));
            }
            ReadOutputs::MorphTargetWeights(_) => {
                warnings.push(format!(
                    "{}: {at}: morph target weights (node {node}) are not animated; the mesh keeps its base shape",
                    path.display()
                ));
            }
        }
    }
    clip.nodes
        .retain(|_, t| t.translation.is_some() || t.rotation.is_some() || t.scale.is_some());
    Ok(Some(clip))
}

/// A track from a sampler's times and outputs (CUBICSPLINE: in-tangent, value, out-tangent
/// per key, as the spec lays them out).
fn track<T: crate::motion::keyframes::Key>(
    times: Vec<f32>,
    out: Vec<T>,
    interp: Interp,
) -> Track<T> {
    if interp == Interp::Cubic {
        let values = out.chunks_exact(3).map(|c| c[1]).collect();
        let tangents = out.chunks_exact(3).map(|c| (c[0], c[2])).collect();
        Track {
            times,
            values,
            tangents,
            interp,
        }
    } else {
        Track {
            times,
            values: out,
            tangents: Vec::new(),
            interp,
        }
    }
}

/// `m` seen from a static parent `above`: above · m(t) as one motion, exact when `above` is
/// a rotation, translation and uniform scale (every interpolation is then carried through:
/// translation keys and tangents are mapped affinely and linearly, rotations multiplied on
/// the left, scales scaled). None for a parent that scales unevenly, shears or mirrors (the
/// caller then chains it: `Motion::under`), and for a motion that is already a chain.
pub fn fold(above: Mat4, m: Motion) -> Option<Motion> {
    if m.parent.is_some() {
        return None;
    }
    let (s, r, _) = above.to_scale_rotation_translation();
    let k = s.x;
    let uniform = k > 0.0 && (s - Vec3::splat(k)).abs().max_element() <= 1e-4 * k;
    let back = Mat4::from_scale_rotation_translation(Vec3::splat(k), r, above.w_axis.truncate());
    use crate::load::motion::max_abs;
    let (size, err) = (max_abs(above).max(1.0), max_abs(back - above));
    if !uniform || err > 1e-4 * size {
        return None;
    }
    let Motion {
        mut translation,
        mut rotation,
        mut scale,
        ..
    } = m;
    translation
        .values
        .iter_mut()
        .for_each(|v| *v = above.transform_point3(*v));
    translation
        .tangents
        .iter_mut()
        .for_each(|(a, b)| (*a, *b) = (above.transform_vector3(*a), above.transform_vector3(*b)));
    rotation.values.iter_mut().for_each(|q| *q = r * *q);
    rotation
        .tangents
        .iter_mut()
        .for_each(|(a, b)| (*a, *b) = (r * *a, r * *b));
    scale.values.iter_mut().for_each(|v| *v *= k);
    scale
        .tangents
        .iter_mut()
        .for_each(|(a, b)| (*a, *b) = (*a * k, *b * k));
    Some(Motion::trs(translation, rotation, scale))
}
