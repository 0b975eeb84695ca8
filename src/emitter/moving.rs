//! A light that moves while the shutter is open: a point, spot, directional light or
//! environment map in its own frame, carried by a keyframed `Motion` to the world at each
//! sample's time (the shading point's `time`, or the escaping ray's). Lights that do not move,
//! and every light of a scene rendered at an instant, are the plain kinds: they pay nothing.

use super::{Emitter, EmitterSample};
use crate::interaction::SurfaceInteraction;
use crate::motion::Motion;
use crate::spectrum::{Spectrum, Wavelengths};
use glam::{Vec2, Vec3};

#[derive(Clone, Debug)]
pub struct MovingLight {
    /// The light in its own frame: what the motion carries (an environment map: only
    /// rotated, its keys checked to hold no scale or translation).
    pub light: Emitter,
    pub motion: Motion,
    /// The shutter's opening (the pose `prism export` writes).
    pub open: f32,
}

impl MovingLight {
    /// Samples the light at `si` in its pose at `si.time`.
    pub fn sample_li<const N: usize>(
        &self,
        si: &SurfaceInteraction,
        u: Vec2,
        wl: &Wavelengths<N>,
    ) -> Option<EmitterSample<N>> {
        let m = self.motion.matrix(si.time);
        self.light.sample_li_carried(&m, si, u, wl)
    }

    /// Radiance from infinity along `d` at `time` (a moving environment map: the map's own
    /// direction is the world's turned back by the rotation then). Out of line: it calls
    /// `Emitter::le_env_at`, which calls it; the cycle kept `le_env_at` and `pdf_li_env_at`
    /// out of the path loop for every environment-lit scene, moving or not.
    #[inline(never)]
    pub fn le_env<const N: usize>(&self, d: Vec3, time: f32, wl: &Wavelengths<N>) -> Spectrum<N> {
        let local = self.motion.rotation.at(time).inverse() * d;
        self.light.le_env_at(local, time, wl)
    }

    /// Solid-angle density of `sample_li` producing direction `d` at `time` (out of line, as
    /// `le_env`).
    #[inline(never)]
    pub fn pdf_env(&self, d: Vec3, time: f32) -> f32 {
        let local = self.motion.rotation.at(time).inverse() * d;
        self.light.pdf_li_env_at(local, time)
    }

    /// The light as a static one in its pose at the shutter's opening.
    pub fn posed(&self) -> Emitter {
        self.light.carried(&self.motion.matrix(self.open))
    }
}
