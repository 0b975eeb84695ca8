//! The camera of a glTF file rendered directly (`prism render model.gltf`) when its node, or
//! a node above it, is animated: posed at the render's instant, or, with an open shutter (and
//! for the flow layers, whose scene spans the neighbouring frames), given the node chain's
//! `Motion`, which the build hands to `motion::Timing` (`load::motion::prepare`), so that it
//! moves per ray as a RON camera does, rolling shutter included (no second moving camera).
//!
//! The motion is exact, not a resampling: it is the chain the walk poses meshes with
//! (`Motion::under`), parent(t) · static nodes · node(t) · … · static nodes · half-turn, so
//! nested animated nodes, a camera offset from a turning node (an arc), CUBICSPLINE channels
//! and STEP mixed with LINEAR all move as the file says. Refused with an open shutter, naming
//! the file, the node and the fix: a pose that is not a rotation, translation and uniform
//! scale at some instant (a parent or scale key that scales unevenly, shears or mirrors: no
//! R, t and K describe it, as `camera::pose_error` says for RON cameras).

use super::animation::Clip;
use super::Model;
use crate::camera::pose_error;
use crate::config::{CameraConfig, SceneConfig};
use crate::error::InputError;
use crate::math::Transform;
use crate::motion::Motion;
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
) -> Result<Option<Motion>, InputError> {
    if cfg.camera.to_world != before.to_world || cfg.camera.animation.is_some() {
        return Ok(None);
    }
    let Some(chain) = camera_chain(model) else {
        return Ok(None);
    };
    let Some(clip) = super::animation::read(model, None, &mut Vec::new())? else {
        return Ok(None);
    };
    if !chain.iter().any(|n| clip.nodes.contains_key(&n.index())) {
        return Ok(None);
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
        return Ok(None);
    }
    let cam = &chain[chain.len() - 1];
    let motion = chain_motion(&chain, &clip);
    // Every pose the camera takes: every key of every track of the chain and 64 instants
    // between neighbouring keys (`Motion::samples`); outside the keys it holds the ends'.
    let (lo, hi) = motion.key_span().unwrap_or((time, time));
    for t in motion.samples(lo, hi) {
        let world = motion.matrix(t);
        let why =
            Transform::from_matrix(world).map_or(Some("it is singular".into()), |t| pose_error(&t));
        if let Some(why) = why {
            return Err(InputError::new(
                &model.path,
                format!(
                    "the camera on node {} cannot move while the shutter is open: its pose at \
                     {t} s is not a rotation, translation and uniform scale ({why})",
                    node_name(cam)
                ),
            )
            .field(format!("nodes[{}].camera", cam.index()))
            .hint(
                "give the camera's node and the nodes above it uniform scales (and scale keys), \
                 without shear or mirroring; or render instants (prism render --time T, or \
                 shutter open = close)",
            ));
        }
    }
    cfg.camera.to_world = vec![super::lights::matrix_op(motion.matrix(time))];
    Ok(Some(motion))
}

/// The camera's world transform as a motion: each animated node of its branch carried by the
/// one above through the static nodes between (`Motion::under`; the topmost folded into the
/// static nodes above it where they allow, as the walk folds meshes), and the static nodes
/// below the last, with glTF's camera half-turn, as a still motion under it. Exact at every
/// time for every interpolation the importer reads: it is the product the walk poses.
fn chain_motion(chain: &[gltf::Node], clip: &Clip) -> Motion {
    let mut motion: Option<Motion> = None;
    let mut between = Mat4::IDENTITY;
    for n in chain {
        let Some(tracks) = clip.nodes.get(&n.index()) else {
            between *= Mat4::from_cols_array_2d(&n.transform().matrix());
            continue;
        };
        let own = tracks.motion(n);
        motion = Some(match motion.take() {
            Some(m) => own.under(m, between),
            None => super::animation::fold(between, own.clone())
                .unwrap_or_else(|| own.under(Motion::still(), between)),
        });
        between = Mat4::IDENTITY;
    }
    let top = motion.unwrap_or_else(Motion::still);
    Motion::still().under(top, between * flip())
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
