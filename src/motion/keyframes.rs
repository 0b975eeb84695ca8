//! Keyframe tracks: a value at each of a list of increasing times (seconds), interpolated
//! between them. Before the first key a track holds the first value, after the last the last.
//!
//! `Cubic` is a cubic Hermite spline; the RON loader gives it Catmull-Rom tangents (finite
//! differences (p[k+1] − p[k−1]) / (t[k+1] − t[k−1]), one-sided at the ends), glTF's
//! CUBICSPLINE its own. Tangents are derivatives per second, as glTF 2.0 defines them.

use glam::{Quat, Vec3, Vec4};

/// How a track moves between two keys.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Interp {
    /// Holds each key's value until the next key.
    Step,
    /// Straight lines (rotations: slerp, the shortest arc).
    #[default]
    Linear,
    /// Cubic Hermite with the track's tangents (rotations: componentwise, then normalised, as
    /// glTF 2.0 specifies).
    Cubic,
}

/// A value a track can hold.
pub trait Key: Copy {
    fn lerp_key(a: Self, b: Self, u: f32) -> Self;
    /// a·x + b·y + c·z + d·w, then made valid (a rotation is normalised).
    fn combine(terms: [(f32, Self); 4]) -> Self;
}

impl Key for Vec3 {
    #[inline]
    fn lerp_key(a: Self, b: Self, u: f32) -> Self {
        a + (b - a) * u
    }
    #[inline]
    fn combine(t: [(f32, Self); 4]) -> Self {
        t[0].1 * t[0].0 + t[1].1 * t[1].0 + t[2].1 * t[2].0 + t[3].1 * t[3].0
    }
}

impl Key for Quat {
    #[inline]
    fn lerp_key(a: Self, b: Self, u: f32) -> Self {
        crate::math::rotation::slerp(a, b, u)
    }
    #[inline]
    fn combine(t: [(f32, Self); 4]) -> Self {
        let v = |k: usize| Vec4::from(t[k].1) * t[k].0;
        Quat::from_vec4(v(0) + v(1) + v(2) + v(3)).normalize()
    }
}

/// Keys at increasing times; `tangents` (in, out) per key only for `Cubic`.
#[derive(Clone, Debug, PartialEq)]
pub struct Track<T> {
    pub times: Vec<f32>,
    pub values: Vec<T>,
    pub tangents: Vec<(T, T)>,
    pub interp: Interp,
}

impl<T: Key> Track<T> {
    /// A track that never moves.
    pub fn constant(v: T) -> Self {
        Track {
            times: vec![0.0],
            values: vec![v],
            tangents: Vec::new(),
            interp: Interp::Step,
        }
    }

    /// The value at time `t`.
    pub fn at(&self, t: f32) -> T {
        let n = self.times.len();
        // First key after t (keys strictly increase: the loader checks).
        let k = self.times.partition_point(|&tk| tk <= t);
        if k == 0 {
            return self.values[0];
        }
        if k == n {
            return self.values[n - 1];
        }
        let (t0, t1) = (self.times[k - 1], self.times[k]);
        let (p0, p1) = (self.values[k - 1], self.values[k]);
        let dt = t1 - t0;
        let u = (t - t0) / dt;
        match self.interp {
            Interp::Step => p0,
            Interp::Linear => T::lerp_key(p0, p1, u),
            Interp::Cubic => {
                let (m0, m1) = (self.tangents[k - 1].1, self.tangents[k].0);
                let (u2, u3) = (u * u, u * u * u);
                T::combine([
                    (2.0 * u3 - 3.0 * u2 + 1.0, p0),
                    ((u3 - 2.0 * u2 + u) * dt, m0),
                    (-2.0 * u3 + 3.0 * u2, p1),
                    ((u3 - u2) * dt, m1),
                ])
            }
        }
    }
}

/// Catmull-Rom tangents (per second) for keys `values` at `times`, the same coming in and
/// going out: central differences inside, one-sided at the ends. Rotations are put on one
/// hemisphere first (q and −q are one rotation) by the caller.
pub fn catmull_rom<T: Key>(times: &[f32], values: &[T]) -> Vec<(T, T)> {
    let n = values.len();
    (0..n)
        .map(|k| {
            let (a, b) = (k.saturating_sub(1), (k + 1).min(n - 1));
            let m = if a == b {
                T::combine([(0.0, values[k]); 4])
            } else {
                let inv = 1.0 / (times[b] - times[a]);
                T::combine([
                    (inv, values[b]),
                    (-inv, values[a]),
                    (0.0, values[k]),
                    (0.0, values[k]),
                ])
            };
            (m, m)
        })
        .collect()
}

/// Catmull-Rom tangents of rotation keys: the keys taken on one hemisphere (each q or −q,
/// whichever is nearer its predecessor), differenced componentwise without normalising.
pub fn catmull_rom_rotations(times: &[f32], values: &mut [Quat]) -> Vec<(Quat, Quat)> {
    for k in 1..values.len() {
        if values[k].dot(values[k - 1]) < 0.0 {
            values[k] = -values[k];
        }
    }
    let n = values.len();
    (0..n)
        .map(|k| {
            let (a, b) = (k.saturating_sub(1), (k + 1).min(n - 1));
            let m = if a == b {
                Vec4::ZERO
            } else {
                (Vec4::from(values[b]) - Vec4::from(values[a])) / (times[b] - times[a])
            };
            let q = Quat::from_vec4(m);
            (q, q)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn track(times: &[f32], xs: &[f32], interp: Interp) -> Track<Vec3> {
        let values: Vec<Vec3> = xs.iter().map(|&x| Vec3::new(x, 2.0 * x, 0.0)).collect();
        let tangents = if interp == Interp::Cubic {
            catmull_rom(times, &values)
        } else {
            Vec::new()
        };
        Track {
            times: times.to_vec(),
            values,
            tangents,
            interp,
        }
    }

    /// Linear: p0 + (p1 − p0)(t − t0)/(t1 − t0) exactly (to f32 rounding, 1e-6), held outside.
    #[test]
    fn linear_is_the_chord_and_holds_at_the_ends() {
        let tr = track(&[0.0, 1.0, 3.0], &[1.0, 3.0, -1.0], Interp::Linear);
        for (t, want) in [
            (-1.0, 1.0),
            (0.25, 1.5),
            (1.0, 3.0),
            (2.0, 1.0),
            (5.0, -1.0),
        ] {
            let v = tr.at(t);
            assert!(
                (v.x - want).abs() < 1e-6 && (v.y - 2.0 * want).abs() < 1e-6,
                "t {t}: {v}"
            );
        }
    }

    #[test]
    fn step_holds_the_previous_key() {
        let tr = track(&[0.0, 1.0, 3.0], &[1.0, 3.0, -1.0], Interp::Step);
        assert_eq!(tr.at(0.999).x, 1.0);
        assert_eq!(tr.at(1.0).x, 3.0);
        assert_eq!(tr.at(2.9).x, 3.0);
        assert_eq!(tr.at(3.5).x, -1.0);
    }

    /// Catmull-Rom's central differences are a quadratic's exact derivative on evenly spaced
    /// keys, so between inner keys it reproduces x = t² (to 1e-5, f32 rounding).
    #[test]
    fn catmull_rom_reproduces_a_quadratic_inside() {
        let ts = [0.0, 0.5, 1.0, 1.5, 2.0];
        let xs: Vec<f32> = ts.iter().map(|t| t * t).collect();
        let tr = track(&ts, &xs, Interp::Cubic);
        for t in [0.6f32, 0.77, 1.0, 1.2, 1.45] {
            assert!((tr.at(t).x - t * t).abs() < 1e-5, "t {t}: {}", tr.at(t).x);
        }
    }

    /// Hermite with the exact derivative as tangents reproduces a cubic: x = t³ − t.
    #[test]
    fn hermite_with_exact_tangents_reproduces_a_cubic() {
        let f = |t: f32| t * t * t - t;
        let df = |t: f32| 3.0 * t * t - 1.0;
        let ts = [-1.0f32, 0.5, 2.0];
        let tr = Track {
            times: ts.to_vec(),
            values: ts.iter().map(|&t| Vec3::splat(f(t))).collect(),
            tangents: ts
                .iter()
                .map(|&t| (Vec3::splat(df(t)), Vec3::splat(df(t))))
                .collect(),
            interp: Interp::Cubic,
        };
        for t in [-0.9f32, -0.2, 0.5, 1.1, 1.99] {
            assert!((tr.at(t).x - f(t)).abs() < 1e-5, "t {t}");
        }
    }

    /// Slerp turns at constant angular speed: a quarter of the way from 0° to 120° about an
    /// axis is 30° about it (to 1e-5 rad).
    #[test]
    #[allow(clippy::disallowed_methods)] // to_axis_angle reads the test's result back
    fn slerp_turns_at_constant_speed() {
        let axis = Vec3::new(1.0, 2.0, -0.5).normalize();
        let tr = Track {
            times: vec![2.0, 4.0],
            values: vec![
                Quat::IDENTITY,
                crate::math::rotation::quat(axis, 120f32.to_radians()),
            ],
            tangents: Vec::new(),
            interp: Interp::Linear,
        };
        let (ax, angle) = tr.at(2.5).to_axis_angle();
        assert!((angle - 30f32.to_radians()).abs() < 1e-5, "{angle}");
        assert!((ax - axis).length() < 1e-4);
    }

    /// A cubic rotation track stays a unit quaternion and passes through its keys (1e-6).
    #[test]
    #[allow(clippy::disallowed_methods)] // to_axis_angle reads the test's result back
    fn cubic_rotation_passes_through_its_keys() {
        let ts = [0.0f32, 1.0, 2.0];
        let mut qs = [
            Quat::IDENTITY,
            -crate::math::rotation::quat(Vec3::Y, 1.0), // the other hemisphere: made continuous
            crate::math::rotation::quat(Vec3::Y, 2.0),
        ];
        let tangents = catmull_rom_rotations(&ts, &mut qs);
        let tr = Track {
            times: ts.to_vec(),
            values: qs.to_vec(),
            tangents,
            interp: Interp::Cubic,
        };
        for (k, &t) in ts.iter().enumerate() {
            assert!(tr.at(t).dot(qs[k]).abs() > 1.0 - 1e-6);
        }
        let mid = tr.at(0.5);
        assert!((mid.length() - 1.0).abs() < 1e-6);
        // A steady spin about y: half-way between the first keys it has turned about 0.5 rad
        // (a componentwise cubic on the unit sphere, with a one-sided start tangent, is not
        // exactly constant-speed: 2e-2 rad).
        assert!(
            (mid.to_axis_angle().1 - 0.5).abs() < 2e-2,
            "{:?}",
            mid.to_axis_angle()
        );
    }
}
