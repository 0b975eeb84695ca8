//! Time: keyframed transforms (`Motion`) and the camera's shutter (`Shutter`).
//!
//! A `Motion` is three tracks, translation, rotation and scale, each with its own keys (glTF
//! animates them separately; a RON key sets all three). At time t the transform is
//! T(t) · R(t) · S(t). A node moving under a moving node (a glTF node animated under another,
//! or under the shape's own RON animation) is a chain: its `parent` motion, the static
//! transforms between the two, then its own track, parent(t) · offset · T(t) · R(t) · S(t);
//! one track (`parent` None) costs one branch more. A scene whose shutter is an instant is built with every transform
//! evaluated there and renders as a static scene does; only a shutter that stays open makes
//! the renderer trace moving objects per ray (`accel::moving`).

pub mod keyframes;

use crate::camera::Camera;
use crate::math::Transform;
use crate::ray::Ray;
use crate::sampler::PixelSampler;
use glam::{Mat4, Quat, Vec2, Vec3};
pub use keyframes::{Interp, Track};

/// The sampler dimension of a camera sample's time: the spare fourth lane of the camera's
/// group (film x, film y, wavelength, time), so time is stratified with the film position and
/// a scene without a shutter interval draws exactly the numbers it always did.
pub const TIME_DIM: u32 = 3;

#[derive(Clone, Debug, PartialEq)]
pub struct Motion {
    pub translation: Track<Vec3>,
    pub rotation: Track<Quat>,
    pub scale: Track<Vec3>,
    /// The moving transform above this one (None: a single track). Boxed: a chain is rare,
    /// and a single track stays small.
    pub parent: Option<Box<Parent>>,
}

/// A motion's moving parent and the static transforms between the two.
#[derive(Clone, Debug, PartialEq)]
pub struct Parent {
    pub motion: Motion,
    pub offset: Mat4,
}

impl Motion {
    /// One track of translation, rotation and scale keys.
    pub fn trs(translation: Track<Vec3>, rotation: Track<Quat>, scale: Track<Vec3>) -> Motion {
        Motion {
            translation,
            rotation,
            scale,
            parent: None,
        }
    }

    /// A motion that holds the identity (the root of a chain under static transforms).
    pub fn still() -> Motion {
        Motion::trs(
            Track::constant(Vec3::ZERO),
            Track::constant(Quat::IDENTITY),
            Track::constant(Vec3::ONE),
        )
    }

    /// `self` carried by `parent` through the static `offset`: parent(t) · offset · self(t).
    /// `self`'s own parent, if any, is replaced (callers chain a single track).
    pub fn under(self, parent: Motion, offset: Mat4) -> Motion {
        Motion {
            parent: Some(Box::new(Parent {
                motion: parent,
                offset,
            })),
            ..self
        }
    }

    /// This motion and its moving parents, innermost first.
    pub fn chain(&self) -> impl Iterator<Item = &Motion> {
        std::iter::successors(Some(self), |m| m.parent.as_deref().map(|p| &p.motion))
    }

    /// The first and last key time of every track of the chain (None: no keys).
    pub fn key_span(&self) -> Option<(f32, f32)> {
        self.chain()
            .flat_map(|m| [&m.translation.times, &m.rotation.times, &m.scale.times])
            .filter_map(|ts| Some((*ts.first()?, *ts.last()?)))
            .reduce(|(a, b), (c, d)| (a.min(c), b.max(d)))
    }

    /// This motion's own track at time `t`, T · R · S, without its parent: the whole
    /// transform of a motion with no parent (every RON camera, every single-track shape).
    #[inline]
    pub fn own(&self, t: f32) -> Mat4 {
        Mat4::from_scale_rotation_translation(
            self.scale.at(t),
            self.rotation.at(t),
            self.translation.at(t),
        )
    }

    /// The transform at time `t`: T · R · S, under the parent's (parent · offset · T · R · S).
    #[inline]
    pub fn matrix(&self, t: f32) -> Mat4 {
        let own = self.own(t);
        match &self.parent {
            None => own,
            Some(p) => p.motion.matrix(t) * p.offset * own,
        }
    }

    /// The transform at time `t` with its inverse (None where a scale passes through 0).
    pub fn at(&self, t: f32) -> Option<Transform> {
        Transform::from_matrix(self.matrix(t))
    }

    /// The instants `bounds` and the loader's checks sample on [t0, t1]: every key inside it
    /// and `STEPS` evenly spaced ones per key interval (and over the whole span), of every
    /// track of the chain.
    pub fn samples(&self, t0: f32, t1: f32) -> Vec<f32> {
        const STEPS: usize = 64;
        let mut ts = vec![t0, t1];
        let tracks = self
            .chain()
            .flat_map(|m| [&m.translation.times, &m.rotation.times, &m.scale.times]);
        for times in tracks {
            ts.extend(times.iter().copied().filter(|&t| t > t0 && t < t1));
            for w in times.windows(2) {
                let (a, b) = (w[0].max(t0), w[1].min(t1));
                if a < b {
                    ts.extend((1..STEPS).map(|i| a + (b - a) * i as f32 / STEPS as f32));
                }
            }
        }
        ts.extend((1..STEPS).map(|i| t0 + (t1 - t0) * i as f32 / STEPS as f32));
        ts.sort_by(f32::total_cmp);
        ts.dedup();
        ts
    }

    /// World bounds of the object box `lo..hi` over the times [t0, t1]: the union of the
    /// box's images at `samples`, padded by the largest distance a corner moves between two
    /// neighbouring samples. Between samples a corner's path stays within half its arc length
    /// of them, and at 64 samples per key interval the arc is within a fraction of a percent
    /// of the chord for any motion that turns less than a radian per step, so the pad (a whole
    /// chord) holds it.
    pub fn bounds(&self, (lo, hi): (Vec3, Vec3), t0: f32, t1: f32) -> (Vec3, Vec3) {
        let corners: [Vec3; 8] = std::array::from_fn(|i| {
            Vec3::select(glam::BVec3::new(i & 1 != 0, i & 2 != 0, i & 4 != 0), hi, lo)
        });
        let (mut blo, mut bhi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        let mut pad = 0.0f32;
        let mut prev: Option<[Vec3; 8]> = None;
        for t in self.samples(t0, t1) {
            let m = self.matrix(t);
            let pts = corners.map(|c| m.transform_point3(c));
            for p in pts {
                blo = blo.min(p);
                bhi = bhi.max(p);
            }
            if let Some(q) = prev {
                for (a, b) in pts.iter().zip(q) {
                    pad = pad.max(a.distance(b));
                }
            }
            prev = Some(pts);
        }
        // A box's rotated image may reach past its corners' box by the box's half diagonal
        // between samples only through rotation, which the chord pad covers.
        (blo - pad, bhi + pad)
    }
}

/// When the camera's film records, in seconds: every row from `open` to `close`, or with a
/// rolling shutter (`readout` > 0) row y from open + y·readout to close + y·readout (rows
/// read top to bottom, as a CMOS sensor does).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shutter {
    pub open: f32,
    pub close: f32,
    /// Seconds between the starts of two neighbouring rows' exposures.
    pub readout: f32,
}

impl Shutter {
    /// The time of a camera sample in pixel row `row` with sample `u` ∈ [0, 1).
    #[inline]
    pub fn time(&self, row: u32, u: f32) -> f32 {
        self.open + row as f32 * self.readout + u * (self.close - self.open)
    }

    /// The first and last instants any row records.
    pub fn span(&self, rows: u32) -> (f32, f32) {
        let last = rows.saturating_sub(1) as f32 * self.readout;
        (self.open, self.close + last)
    }
}

/// A scene's time while the shutter stays open: each camera sample draws its time, and a moving
/// camera's ray is carried from its pose at `shutter.open` (the scene's `Camera`) to its pose
/// at that time.
#[derive(Clone, Debug)]
pub struct Timing {
    pub shutter: Shutter,
    /// The camera's motion and the inverse of its pose at `shutter.open`.
    pub camera: Option<(Motion, Mat4)>,
}

impl Timing {
    /// The camera ray through `film` in pixel row `row`, at a time the sampler draws
    /// (`TIME_DIM`).
    #[inline]
    pub fn camera_ray(
        &self,
        camera: &Camera,
        film: Vec2,
        row: u32,
        sampler: &mut PixelSampler,
    ) -> Ray {
        sampler.set_dimension(TIME_DIM);
        let time = self.shutter.time(row, sampler.next_1d());
        let ray = camera.ray(film, sampler);
        Ray {
            time,
            ..self.moved(ray, time)
        }
    }

    /// A ray of the camera at `shutter.open` carried to the camera's pose at `time`.
    pub fn moved(&self, ray: Ray, time: f32) -> Ray {
        let Some((motion, open_inv)) = &self.camera else {
            return ray;
        };
        // A chain-free motion (every RON camera) takes its own track inline: the recursive
        // `matrix` is not inlined here, and this runs once per camera ray.
        let at = match motion.parent {
            None => motion.own(time),
            Some(_) => motion.matrix(time),
        };
        let rel = at * *open_inv;
        let d = rel.transform_vector3(ray.d);
        let len = d.length();
        Ray {
            o: rel.transform_point3(ray.o),
            d: d / len,
            t_max: ray.t_max * len,
            time,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::portable;

    fn linear(keys: &[(f32, Mat4)]) -> Motion {
        let d: Vec<(Vec3, Quat, Vec3)> = keys
            .iter()
            .map(|(_, m)| m.to_scale_rotation_translation())
            .collect();
        let times: Vec<f32> = keys.iter().map(|k| k.0).collect();
        let tr = |values| Track {
            times: times.clone(),
            values,
            tangents: Vec::new(),
            interp: Interp::Linear,
        };
        Motion::trs(
            tr(d.iter().map(|k| k.2).collect()),
            Track {
                times: times.clone(),
                values: d.iter().map(|k| k.1).collect(),
                tangents: Vec::new(),
                interp: Interp::Linear,
            },
            tr(d.iter().map(|k| k.0).collect()),
        )
    }

    /// A point on a spinning, sliding object: the closed form at the middle time (1e-5).
    #[test]
    fn trs_at_a_time_is_the_closed_form() {
        let m = linear(&[
            (0.0, Mat4::from_translation(Vec3::new(0.0, 0.0, 0.0))),
            (
                2.0,
                Mat4::from_translation(Vec3::new(4.0, 0.0, 0.0))
                    * crate::math::rotation::axis_angle(Vec3::Z, 1.0),
            ),
        ]);
        let p = m.matrix(1.0).transform_point3(Vec3::X);
        let want = Vec3::new(2.0 + portable::cos(0.5f32), portable::sin(0.5f32), 0.0);
        assert!((p - want).length() < 1e-5, "{p} vs {want}");
    }

    /// The bounds over an interval hold the box at every time of it (checked at 1000 times)
    /// and are not loose for a translation (within the pad of one 1/64 step, 1e-4 tolerance).
    #[test]
    fn bounds_hold_the_moving_box() {
        let m = linear(&[
            (0.0, Mat4::IDENTITY),
            (
                1.0,
                Mat4::from_translation(Vec3::new(3.0, 1.0, 0.0))
                    * crate::math::rotation::axis_angle(Vec3::Y, 2.5),
            ),
        ]);
        let obj = (Vec3::splat(-1.0), Vec3::splat(1.0));
        let (lo, hi) = m.bounds(obj, 0.1, 0.9);
        for i in 0..=1000 {
            let t = 0.1 + 0.8 * i as f32 / 1000.0;
            let mat = m.matrix(t);
            for c in 0..8 {
                let v = Vec3::new(
                    if c & 1 != 0 { 1.0 } else { -1.0 },
                    if c & 2 != 0 { 1.0 } else { -1.0 },
                    if c & 4 != 0 { 1.0 } else { -1.0 },
                );
                let p = mat.transform_point3(v);
                assert!(p.cmpge(lo).all() && p.cmple(hi).all(), "t {t}: {p} outside");
            }
        }
        let slide = linear(&[
            (0.0, Mat4::IDENTITY),
            (1.0, Mat4::from_translation(Vec3::new(64.0, 0.0, 0.0))),
        ]);
        let (lo, hi) = slide.bounds(obj, 0.0, 1.0);
        assert!(
            (lo.x + 2.0).abs() < 1e-4 && (hi.x - 66.0).abs() < 1e-4,
            "{lo} {hi}"
        );
    }

    #[test]
    fn rolling_shutter_rows_start_later() {
        let s = Shutter {
            open: 1.0,
            close: 1.5,
            readout: 0.01,
        };
        assert_eq!(s.time(0, 0.0), 1.0);
        assert!((s.time(10, 0.5) - 1.35).abs() < 1e-6);
        assert!((s.span(11).1 - 1.6).abs() < 1e-6);
    }
}
