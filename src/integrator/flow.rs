//! Optical flow, scene flow and occlusion of the pixel-centre hits (issue 30; conventions in
//! `film::aov` and docs/sidecar.md, "Flow").
//!
//! Each pixel's first hit at the frame time t (the AOV pass's) is followed exactly to the
//! neighbouring frame t' = t ± step: the transform of the shape it lies on, taken at t' and
//! applied to the object-space hit point (p' = M(t')·M(t)⁻¹·p, in f64), and projected by the
//! camera at t' through its model and distortion. Nothing is matched between images and
//! nothing is sampled: the flow is the motion of that one surface point. Whether the point is
//! seen at t' is asked of `FlowScene::scene`, the scene with its shutter open over
//! [t − step, t + step], where every shape can be posed at either neighbouring frame.

use super::aov::Hit;
use crate::camera::{Camera, Distortion};
use crate::film::{Aov, Channel, Dir};
use crate::scene::Scene;
use glam::{DMat3, DMat4, DVec2, DVec3};
use rayon::prelude::*;

/// What the flow layers need beyond the frame's own scene (built by `load::flow`).
pub struct FlowScene {
    /// The scene over [time − step, time + step] (materials and lights left out): the moving
    /// shapes' motions and the occluders at either neighbouring frame.
    pub scene: Scene,
    /// The frame's time (the shutter's opening) and the frame interval, seconds.
    pub time: f32,
    pub step: f32,
    /// The camera at time + step and at time − step.
    pub forward: Camera,
    pub backward: Camera,
}

/// Where a pixel's surface point goes at the neighbouring frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Track {
    /// Image motion in pixels, OpenCV's axes (x right, y down).
    pub flow: [f32; 2],
    /// World displacement p(t') − p(t).
    pub world: [f32; 3],
    /// OpenCV camera-frame displacement, each time's own camera: C(t')·p(t') − C(t)·p(t).
    pub camera: [f32; 3],
    /// 1 where the point is hidden at t', leaves the image, or there is no surface.
    pub occluded: f32,
}

/// A camera as OpenCV states it, in f64: x_cam = R·x_world + t, K, distortion.
struct View {
    r: DMat3,
    t: DVec3,
    /// fx, fy, cx, cy (OpenCV's pixels, centres at integers).
    k: [f64; 4],
    dist: Option<Distortion>,
    ortho: bool,
    /// Clip depths in world units along the optical axis.
    near: f64,
    far: f64,
    size: DVec2,
    /// The camera centre (perspective) and its forward axis, world frame.
    centre: DVec3,
    forward: DVec3,
}

impl View {
    fn new(c: &Camera) -> View {
        let (r, t) = c.world_to_opencv();
        let m = c.to_world().m.as_dmat4();
        // A uniform scale in `to_world` scales the clip distances with the rays.
        let scale = m.x_axis.truncate().length();
        let k = c.intrinsics();
        View {
            r,
            t,
            k: k.k_opencv(),
            dist: c.distortion().copied(),
            ortho: matches!(c, Camera::Orthographic(_)),
            near: c.near_clip() as f64 * scale,
            far: c.far_clip() as f64 * scale,
            size: DVec2::new(k.width as f64, k.height as f64),
            centre: m.w_axis.truncate(),
            forward: m.z_axis.truncate().normalize(),
        }
    }

    /// OpenCV pixel of camera-frame point `q`; None behind a perspective camera, or where the
    /// distortion folds (its inverse does not lead back to the point: the point lies outside
    /// the part of the view the image covers).
    fn pixel(&self, q: DVec3) -> Option<DVec2> {
        let mut n = if self.ortho {
            q.truncate()
        } else if q.z > 0.0 {
            q.truncate() / q.z
        } else {
            return None;
        };
        if let Some(d) = &self.dist {
            let dn = d.distort(n);
            // 1e-9: far above Newton's residual (1e-13), far below a fold's jump.
            if (d.undistort(dn).0 - n).length() > 1e-9 * (1.0 + n.length()) {
                return None;
            }
            n = dn;
        }
        let [fx, fy, cx, cy] = self.k;
        Some(DVec2::new(fx * n.x + cx, fy * n.y + cy))
    }

    /// Whether pixel `px` of camera-frame point `q` lies on the image, within the clip range.
    fn frames(&self, q: DVec3, px: DVec2) -> bool {
        let lo = DVec2::splat(-0.5);
        let hi = self.size - 0.5;
        q.z >= self.near && q.z <= self.far && px.cmpge(lo).all() && px.cmplt(hi).all()
    }
}

impl FlowScene {
    /// The neighbouring frame's time.
    pub fn time_of(&self, dir: Dir) -> f32 {
        match dir {
            Dir::Forward => self.time + self.step,
            Dir::Backward => self.time - self.step,
        }
    }

    /// Whether something other than the point itself lies between the camera `v` and world
    /// point `p` (camera depth `z`, on shape `shape`) at time `time`.
    fn hidden(&self, v: &View, p: DVec3, z: f64, shape: u32, time: f32) -> bool {
        let (o, len) = if v.ortho {
            let len = z - v.near;
            (p - v.forward * len, len)
        } else {
            let a = v.near / z;
            let to = p - v.centre;
            (v.centre + to * a, to.length() * (1.0 - a))
        };
        let d = (p - o) / len;
        // Stop 1e-4 short of the point: its own surface there is not an occluder.
        let ray = crate::ray::Ray {
            o: o.as_vec3(),
            d: d.as_vec3(),
            t_max: (len * (1.0 - 1e-4)) as f32,
            time,
        };
        match self.scene.intersect(&ray) {
            None => false,
            // A grazing view of the point's own surface may meet it a little early (an f32 hit
            // near a tangent is good to ~3e-4 of the radius): within 1e-3 of the distance, on
            // the same shape, it is the point itself.
            Some(h) => !(h.shape == shape && (h.p.as_dvec3() - p).length() <= 1e-3 * len),
        }
    }

    /// Each pixel's track to the frame `dir` (row-major, `hits` from `aov::first_hits`;
    /// `source`: the frame's own camera).
    pub fn tracks(
        &self,
        source: &Camera,
        hits: &[Option<Hit>],
        width: u32,
        dir: Dir,
    ) -> Vec<Track> {
        let (t, t2) = (self.time, self.time_of(dir));
        let (src, dst) = match dir {
            Dir::Forward => (View::new(source), View::new(&self.forward)),
            Dir::Backward => (View::new(source), View::new(&self.backward)),
        };
        // Per shape: M(t')·M(t)⁻¹ (None: it stays still).
        let rel: Vec<Option<DMat4>> = (0..self.scene.shapes.len() as u32)
            .map(|s| {
                let m = self.scene.shape_motion(s)?;
                Some(m.matrix(t2).as_dmat4() * m.matrix(t).as_dmat4().inverse())
            })
            .collect();
        hits.par_iter()
            .enumerate()
            .with_min_len(256)
            .map(|(i, h)| {
                let Some(h) = h else {
                    return Track {
                        occluded: 1.0,
                        ..Track::default()
                    };
                };
                let centre = DVec2::new((i % width as usize) as f64, (i / width as usize) as f64);
                let p = h.p.as_dvec3();
                let p2 = rel
                    .get(h.shape as usize)
                    .copied()
                    .flatten()
                    .map_or(p, |m| m.transform_point3(p));
                let (q, q2) = (src.r * p + src.t, dst.r * p2 + dst.t);
                let mut track = Track {
                    world: (p2 - p).as_vec3().to_array(),
                    camera: (q2 - q).as_vec3().to_array(),
                    occluded: 1.0,
                    ..Track::default()
                };
                // Behind the camera there is no image position: flow 0, occluded.
                if let Some(px) = dst.pixel(q2) {
                    track.flow = (px - centre).as_vec2().to_array();
                    let seen = dst.frames(q2, px) && !self.hidden(&dst, p2, q2.z, h.shape, t2);
                    track.occluded = if seen { 0.0 } else { 1.0 };
                }
                track
            })
            .collect()
    }

    /// The flow layers `aovs` asks for, in its order (each direction traced once).
    pub fn layers(
        &self,
        source: &Camera,
        hits: &[Option<Hit>],
        width: u32,
        aovs: &[Aov],
    ) -> Vec<Channel> {
        let mut out = Vec::new();
        for dir in [Dir::Forward, Dir::Backward] {
            if !aovs.iter().any(|a| a.flow_dir() == Some(dir)) {
                continue;
            }
            let tracks = self.tracks(source, hits, width, dir);
            for &aov in aovs.iter().filter(|a| a.flow_dir() == Some(dir)) {
                let value = |tr: &Track, c: usize| match aov {
                    Aov::Flow(_) => tr.flow[c],
                    Aov::FlowOcclusion(_) => tr.occluded,
                    Aov::SceneFlow(_) => tr.world[c],
                    _ => tr.camera[c],
                };
                for (c, ch) in aov.channels().iter().enumerate() {
                    out.push(Channel {
                        name: format!("{}.{ch}", aov.name()),
                        data: tracks.iter().map(|tr| value(tr, c)).collect(),
                    });
                }
            }
        }
        out
    }
}
