//! A spot light (Mitsuba 3's `spot`): a point at the origin of its local frame emitting along
//! local +z. The intensity is `intensity` within `beam_width` of the axis, falls linearly in
//! angle to 0 at `cutoff_angle`, and is 0 beyond (checked against Mitsuba 3 by
//! `tests/emitters_mitsuba.rs`).

use super::EmitterSample;
use crate::interaction::SurfaceInteraction;
use crate::math::portable;
use crate::math::Transform;
use crate::spectrum::{Curve, Wavelengths};
use glam::{Mat3, Mat4, Vec3};

#[derive(Clone, Debug)]
pub struct Spot {
    position: Vec3,
    /// World vectors → the light's local frame (Mitsuba applies the inverse transform, then
    /// normalises, so a scaled `to_world` shapes the cone the same way in both).
    to_local: Mat3,
    intensity: Curve,
    /// Angles in radians, and their cosines.
    cutoff: f32,
    beam: f32,
    /// The angles as given, in degrees (for `prism export`).
    cutoff_deg: f32,
    beam_deg: f32,
    cos_cutoff: f32,
    cos_beam: f32,
}

impl Spot {
    /// `cutoff_deg` in (0, 90], `beam_deg` in [0, cutoff_deg] (degrees; the config checks).
    pub fn new(to_world: &Transform, intensity: Curve, cutoff_deg: f32, beam_deg: f32) -> Spot {
        let (cutoff, beam) = (cutoff_deg.to_radians(), beam_deg.to_radians());
        Spot {
            position: to_world.point(Vec3::ZERO),
            to_local: Mat3::from_mat4(to_world.inv),
            intensity,
            cutoff,
            beam,
            cos_cutoff: portable::cos(cutoff),
            cos_beam: portable::cos(beam),
            cutoff_deg,
            beam_deg,
        }
    }

    /// The light's `to_world` (rebuilt from what rendering keeps: exact to f32 rounding).
    pub fn to_world(&self) -> Mat4 {
        let m = self.to_local.inverse();
        Mat4::from_cols(
            m.x_axis.extend(0.0),
            m.y_axis.extend(0.0),
            m.z_axis.extend(0.0),
            self.position.extend(1.0),
        )
    }

    /// The intensity on the axis (W sr⁻¹ nm⁻¹).
    pub fn intensity(&self) -> &Curve {
        &self.intensity
    }

    /// The cutoff angle and the beam width, in degrees.
    pub fn angles_deg(&self) -> (f32, f32) {
        (self.cutoff_deg, self.beam_deg)
    }

    /// The fraction of the peak intensity emitted along `local` (a unit vector in the light's
    /// frame): 1 inside the beam, (cutoff − θ)/(cutoff − beam) in the transition, 0 outside.
    #[inline]
    pub fn falloff(&self, local: Vec3) -> f32 {
        let cos_t = local.z;
        if cos_t <= self.cos_cutoff {
            0.0
        } else if cos_t >= self.cos_beam {
            1.0
        } else {
            // Only reached when beam < θ < cutoff, so the width is not zero.
            ((self.cutoff - portable::acos(cos_t.clamp(-1.0, 1.0))) / (self.cutoff - self.beam))
                .clamp(0.0, 1.0)
        }
    }

    #[inline]
    pub fn sample_li<const N: usize>(
        &self,
        si: &SurfaceInteraction,
        wl: &Wavelengths<N>,
    ) -> Option<EmitterSample<N>> {
        let to = self.position - si.p;
        let d2 = to.length_squared();
        if d2 <= 0.0 {
            return None;
        }
        let wi = to / d2.sqrt();
        let falloff = self.falloff((self.to_local * -wi).normalize());
        if falloff <= 0.0 {
            return None;
        }
        Some(EmitterSample {
            wi,
            shadow: si.spawn_to(self.position, Vec3::ZERO, None),
            radiance: self.intensity.eval(wl) * (falloff / d2),
            pdf: 1.0,
            delta: true,
        })
    }
}

impl Spot {
    /// The light carried by `m` (world from its frame), as a static one.
    pub fn carried(&self, m: &Mat4) -> Spot {
        let t = Transform::from_matrix(*m * self.to_world()).unwrap_or(Transform::IDENTITY);
        Spot::new(&t, self.intensity.clone(), self.cutoff_deg, self.beam_deg)
    }

    /// `sample_li` with the light carried by `m` (world from the light's own frame: a moving
    /// light, `emitter::moving`).
    pub fn sample_li_moved<const N: usize>(
        &self,
        m: &Mat4,
        si: &SurfaceInteraction,
        wl: &Wavelengths<N>,
    ) -> Option<EmitterSample<N>> {
        let inv = Mat3::from_mat4(*m).inverse();
        if !inv.is_finite() {
            return None; // a scale through 0 at this instant
        }
        let position = m.transform_point3(self.position);
        let to = position - si.p;
        let d2 = to.length_squared();
        if d2 <= 0.0 {
            return None;
        }
        let wi = to / d2.sqrt();
        let falloff = self.falloff((self.to_local * inv * -wi).normalize());
        if falloff <= 0.0 {
            return None;
        }
        Some(EmitterSample {
            wi,
            shadow: si.spawn_to(position, Vec3::ZERO, None),
            radiance: self.intensity.eval(wl) * (falloff / d2),
            pdf: 1.0,
            delta: true,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn falloff_is_linear_in_angle() {
        let s = Spot::new(&Transform::IDENTITY, Curve::Constant(1.0), 30.0, 20.0);
        let at = |deg: f32| {
            let t = deg.to_radians();
            s.falloff(Vec3::new(portable::sin(t), 0.0, portable::cos(t)))
        };
        assert_eq!(at(0.0), 1.0);
        assert_eq!(at(19.0), 1.0);
        assert!((at(25.0) - 0.5).abs() < 1e-4);
        assert!((at(28.0) - 0.2).abs() < 1e-4);
        assert_eq!(at(30.5), 0.0);
        assert_eq!(at(120.0), 0.0);
        // A hard edge when the beam fills the cone.
        let hard = Spot::new(
            &Transform::IDENTITY,
            Curve::Constant(1.0),
            0.5f32.to_degrees(),
            0.5f32.to_degrees(),
        );
        assert_eq!(
            hard.falloff(Vec3::new(
                portable::sin(0.47f32),
                0.0,
                portable::cos(0.47f32)
            )),
            1.0
        );
        assert_eq!(
            hard.falloff(Vec3::new(
                portable::sin(0.53f32),
                0.0,
                portable::cos(0.53f32)
            )),
            0.0
        );
    }
}
