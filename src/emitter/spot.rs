//! A spot light (Mitsuba 3's `spot`): a point at the origin of its local frame emitting along
//! local +z. The intensity is `intensity` within `beam_width` of the axis, falls linearly in
//! angle to 0 at `cutoff_angle`, and is 0 beyond (checked against Mitsuba 3 by
//! `tests/emitters_mitsuba.rs`).

use super::EmitterSample;
use crate::interaction::SurfaceInteraction;
use crate::math::Transform;
use crate::spectrum::{Curve, Wavelengths};
use glam::{Mat3, Vec3};

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
    cos_cutoff: f32,
    cos_beam: f32,
}

impl Spot {
    /// `cutoff` in (0, π/2], `beam` in [0, cutoff] (radians; the config checks).
    pub fn new(to_world: &Transform, intensity: Curve, cutoff: f32, beam: f32) -> Spot {
        Spot {
            position: to_world.point(Vec3::ZERO),
            to_local: Mat3::from_mat4(to_world.inv),
            intensity,
            cutoff,
            beam,
            cos_cutoff: cutoff.cos(),
            cos_beam: beam.cos(),
        }
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
            ((self.cutoff - cos_t.clamp(-1.0, 1.0).acos()) / (self.cutoff - self.beam))
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn falloff_is_linear_in_angle() {
        let s = Spot::new(
            &Transform::IDENTITY,
            Curve::Constant(1.0),
            30f32.to_radians(),
            20f32.to_radians(),
        );
        let at = |deg: f32| {
            let t = deg.to_radians();
            s.falloff(Vec3::new(t.sin(), 0.0, t.cos()))
        };
        assert_eq!(at(0.0), 1.0);
        assert_eq!(at(19.0), 1.0);
        assert!((at(25.0) - 0.5).abs() < 1e-4);
        assert!((at(28.0) - 0.2).abs() < 1e-4);
        assert_eq!(at(30.5), 0.0);
        assert_eq!(at(120.0), 0.0);
        // A hard edge when the beam fills the cone.
        let hard = Spot::new(&Transform::IDENTITY, Curve::Constant(1.0), 0.5, 0.5);
        assert_eq!(
            hard.falloff(Vec3::new(0.47f32.sin(), 0.0, 0.47f32.cos())),
            1.0
        );
        assert_eq!(
            hard.falloff(Vec3::new(0.53f32.sin(), 0.0, 0.53f32.cos())),
            0.0
        );
    }
}
