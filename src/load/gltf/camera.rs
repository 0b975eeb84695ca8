//! The camera of a glTF file rendered directly (`prism render model.gltf`) when its node, or
//! one node above it, is animated: posed at the render's instant, or, with an open shutter (and
//! for the flow layers, whose scene spans the neighbouring frames), written as the camera's RON
//! `animation`, so that it moves per ray through the same `motion::Timing` as a RON camera,
//! rolling shutter included (no second moving camera).
//!
//! The keys are exact, not a resampling. The camera's world transform is
//! above · node(t) · below, with `above` (the static parents) and `below` (the static nodes
//! down to the camera, and glTF's camera half-turn) rotations, translations and uniform
//! scales. Such factors commute with slerp and with straight (or held) translation and scale,
//! so keys at every key time of the node's channels, interpolated as the channels are, give
//! the world transform at every time. Refused with an open shutter, naming the file, the node
//! and the fix (each is posed exactly at an instant): a camera under two animated nodes (nested
//! motion), a camera offset from a node that turns (it sweeps an arc, which no straight
//! translation between keys follows), CUBICSPLINE channels (RON's `Cubic` keys take
//! Catmull-Rom tangents, not the file's) and STEP mixed with LINEAR. Where the node turns
//! by more than 90° between keys, keys are added on the way (`split_turns`).

use super::animation::NodeTracks;
use super::Model;
use crate::camera::pose_error;
use crate::config::{AnimationConfig, CameraConfig, Interpolation, KeyConfig, SceneConfig};
use crate::error::InputError;
use crate::math::Transform;
use crate::motion::Interp;
use glam::{Mat4, Vec4};

/// glTF cameras look along −z with +x right; prism's along +z with +x left: a half-turn about y.
pub(super) fn flip() -> Mat4 {
    Mat4::from_diagonal(Vec4::new(-1.0, 1.0, -1.0, 1.0))
}

/// Moves `cfg.camera` with the file's animation (its first, as the model's `Gltf` shape reads
/// it), after the command line's edits: `before` is the camera `scene_for` wrote; a camera the
/// edits replaced is left alone.
pub fn animate(
    model: &Model,
    before: &CameraConfig,
    cfg: &mut SceneConfig,
) -> Result<(), InputError> {
    if cfg.camera.to_world != before.to_world || cfg.camera.animation.is_some() {
        return Ok(());
    }
    let Some(chain) = camera_chain(model) else {
        return Ok(());
    };
    let Some(clip) = super::animation::read(model, None, &mut Vec::new())? else {
        return Ok(());
    };
    let animated: Vec<usize> = (0..chain.len())
        .filter(|&i| clip.nodes.contains_key(&chain[i].index()))
        .collect();
    if animated.is_empty() {
        return Ok(());
    }
    let local = |n: &gltf::Node, t: f32| match clip.nodes.get(&n.index()) {
        Some(tr) => tr.local(n, t),
        None => Mat4::from_cols_array_2d(&n.transform().matrix()),
    };
    let shutter = cfg.camera.shutter;
    let time = shutter.map_or(0.0, |s| s.open);
    let instant = shutter.is_none_or(|s| s.open == s.close && s.readout == 0.0);
    let flow = cfg
        .aovs
        .iter()
        .any(|a| crate::film::Aov::parse(a.trim()).is_some_and(|a| a.flow_dir().is_some()));
    if instant && !flow {
        let world = chain.iter().fold(Mat4::IDENTITY, |m, n| m * local(n, time)) * flip();
        cfg.camera.to_world = vec![super::lights::matrix_op(world)];
        return Ok(());
    }
    let cam = &chain[chain.len() - 1];
    let refuse = |why: String, hint: &str| {
        InputError::new(
            &model.path,
            format!(
                "the camera on node {} cannot move while the shutter is open: {why}",
                node_name(cam)
            ),
        )
        .field(format!("nodes[{}].camera", cam.index()))
        .hint(format!(
            "{hint}; or render instants (prism render --time T, or shutter open = close)"
        ))
    };
    if animated.len() > 1 {
        let names: Vec<String> = animated.iter().map(|&i| node_name(&chain[i])).collect();
        return Err(refuse(
            format!(
                "it moves with {} animated nodes ({}): nested motion",
                names.len(),
                names.join(", ")
            ),
            "animate one node of the camera's branch (bake the others' motion into it)",
        ));
    }
    let a = animated[0];
    let node = &chain[a];
    let tracks = &clip.nodes[&node.index()];
    let above = chain[..a]
        .iter()
        .fold(Mat4::IDENTITY, |m, n| m * local(n, 0.0));
    let below = chain[a + 1..]
        .iter()
        .fold(Mat4::IDENTITY, |m, n| m * local(n, 0.0))
        * flip();
    for (m, what) in [
        (above, "its parents"),
        (below, "the nodes between it and the animated node"),
    ] {
        let why = Transform::from_matrix(m).map_or(Some("a zero scale".into()), |t| pose_error(&t));
        if let Some(why) = why {
            return Err(refuse(
                format!("{what} are not a rotation, translation and uniform scale ({why})"),
                "give the camera's parents uniform scales, without shear or mirroring",
            ));
        }
    }
    let interp = interpolation(tracks).map_err(|why| {
        refuse(
            format!("{why} on node {}", node_name(node)),
            "re-export the camera's animation with LINEAR (or STEP) channels",
        )
    })?;
    let turns = tracks
        .rotation
        .as_ref()
        .is_some_and(|r| r.values.windows(2).any(|w| w[0] != w[1]));
    let offset = below.w_axis.truncate().length();
    if turns && offset > 1e-6 * below.x_axis.truncate().length() {
        return Err(refuse(
            format!(
                "it is {offset} units from the animated node {}, which turns, so it sweeps an arc",
                node_name(node)
            ),
            "animate the camera's own node (or put the camera at its animated parent's origin)",
        ));
    }
    // Every key time of a channel that moves; a channel of one key holds its value.
    let mut times: Vec<f32> = [
        tracks.translation.as_ref().map(|t| &t.times),
        tracks.rotation.as_ref().map(|t| &t.times),
        tracks.scale.as_ref().map(|t| &t.times),
    ]
    .into_iter()
    .flatten()
    .filter(|ts| ts.len() > 1)
    .flatten()
    .copied()
    .collect();
    times.sort_by(f32::total_cmp);
    times.dedup();
    let Some(interpolation) = interp.filter(|_| !times.is_empty()) else {
        let world = above * local(node, time) * below;
        cfg.camera.to_world = vec![super::lights::matrix_op(world)];
        return Ok(());
    };
    if interpolation == Interpolation::Linear {
        if let Some(r) = &tracks.rotation {
            split_turns(&mut times, |t| r.at(t));
        }
    }
    let mut keys = Vec::with_capacity(times.len());
    for &t in &times {
        let world = above * tracks.local(node, t) * below;
        let why =
            Transform::from_matrix(world).map_or(Some("it is singular".into()), |t| pose_error(&t));
        if let Some(why) = why {
            return Err(refuse(
                format!("its pose at the key time {t} s is not a rotation, translation and uniform scale ({why})"),
                "give the animated node uniform scale keys, without mirroring",
            ));
        }
        keys.push(KeyConfig {
            time: t,
            to_world: vec![super::lights::matrix_op(world)],
        });
    }
    cfg.camera.to_world = Vec::new();
    cfg.camera.animation = Some(AnimationConfig {
        interpolation,
        keys,
    });
    Ok(())
}

/// Keys a half-turn apart leave the way the camera turns to the decomposition of their
/// matrices (q and −q are one rotation): keys are added at interval midpoints until
/// neighbours are at most 90° apart (|q·q′| ≥ cos 45°). A midpoint lies on the slerp's arc
/// and on the straight translation and scale, so the added keys change no pose.
fn split_turns(times: &mut Vec<f32>, rotation: impl Fn(f32) -> glam::Quat) {
    let mut k = 0;
    // Each split halves an interval's turn: a few per half-turn; the cap keeps it finite.
    while k + 1 < times.len() && times.len() < 1 << 16 {
        let (a, b) = (times[k], times[k + 1]);
        let mid = 0.5 * (a + b);
        let far = rotation(a).dot(rotation(b)).abs() < std::f32::consts::FRAC_1_SQRT_2;
        if far && mid > a && mid < b {
            times.insert(k + 1, mid);
        } else {
            k += 1;
        }
    }
}

/// The interpolation of the node's moving channels (None: none moves), or why RON keys cannot
/// follow them exactly.
fn interpolation(tracks: &NodeTracks) -> Result<Option<Interpolation>, String> {
    let interps = [
        tracks
            .translation
            .as_ref()
            .map(|t| (t.times.len(), t.interp)),
        tracks.rotation.as_ref().map(|t| (t.times.len(), t.interp)),
        tracks.scale.as_ref().map(|t| (t.times.len(), t.interp)),
    ];
    let mut found = None;
    for (_, interp) in interps.into_iter().flatten().filter(|(n, _)| *n > 1) {
        let this = match interp {
            Interp::Linear => Interpolation::Linear,
            Interp::Step => Interpolation::Step,
            Interp::Cubic => return Err("its animation has a CUBICSPLINE channel".into()),
        };
        if found.is_some_and(|f| f != this) {
            return Err("its animation mixes STEP and LINEAR channels".into());
        }
        found = Some(this);
    }
    Ok(found)
}

/// `"Name" (nodes[i])`, or `nodes[i]` for a node without a name.
fn node_name(n: &gltf::Node) -> String {
    match n.name() {
        Some(name) => format!("\"{name}\" (nodes[{}])", n.index()),
        None => format!("nodes[{}]", n.index()),
    }
}

/// The nodes from a root of the default scene down to the first camera node, in the walk's
/// order (depth first, children in order: the camera `scene_for` chose); None without one.
fn camera_chain(model: &Model) -> Option<Vec<gltf::Node<'_>>> {
    let doc = &model.doc;
    let scene = doc.default_scene().or_else(|| doc.scenes().next())?;
    let mut parent: Vec<Option<usize>> = vec![None; doc.nodes().len()];
    for n in doc.nodes() {
        for c in n.children() {
            parent[c.index()] = Some(n.index());
        }
    }
    // The load has refused cycles already; `seen` keeps this walk finite regardless.
    let mut seen = vec![false; doc.nodes().len()];
    let mut stack: Vec<gltf::Node> = scene.nodes().collect();
    stack.reverse();
    while let Some(n) = stack.pop() {
        if std::mem::replace(&mut seen[n.index()], true) {
            continue;
        }
        if n.camera().is_some() {
            let mut chain = vec![n.clone()];
            let mut at = n.index();
            while let Some(p) = parent[at].filter(|_| chain.len() <= seen.len()) {
                chain.push(doc.nodes().nth(p)?);
                at = p;
            }
            chain.reverse();
            return Some(chain);
        }
        stack.extend(n.children().collect::<Vec<_>>().into_iter().rev());
    }
    None
}
