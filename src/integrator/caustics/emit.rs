//! Where light paths start: on a target's disk facing a source at infinity (an environment
//! map's bright cells, a directional light), or on an area light towards a target's cone.

use super::Caustics;
use crate::emitter::AreaEmitter;
use crate::math::sampling::{square_to_disk_concentric, square_to_uniform_cone};
use crate::math::Frame;
use crate::ray::Ray;
use crate::scene::Scene;
use crate::spectrum::{Spectrum, Wavelengths};
use glam::{Vec2, Vec3};

impl Caustics<'_> {
    /// A light path arriving from infinity, travelling along `dir` with radiance (or, for a
    /// directional light, irradiance) `le` and direction density `pdf_dir`: its ray, starting
    /// on a target's disk facing the light, and its throughput.
    pub(super) fn emit_from_infinity<const N: usize>(
        &self,
        dir: Vec3,
        le: Spectrum<N>,
        pdf_dir: f32,
        u2: &mut impl FnMut() -> Vec2,
    ) -> Option<(Ray, Spectrum<N>)> {
        let (t, _, _) = self.by_area.sample_discrete(u2().x);
        let frame = Frame::from_normal(dir);
        let disk = square_to_disk_concentric(u2()) * self.targets[t].radius;
        let q = self.targets[t].center + frame.to_world(Vec3::new(disk.x, disk.y, 0.0));
        // Density of that point in the plane: every disk covering it could have produced it.
        let covering = self
            .targets
            .iter()
            .filter(|t| {
                let v = t.center - q;
                (v - v.dot(dir) * dir).length_squared() <= t.radius * t.radius
            })
            .count();
        if covering == 0 || pdf_dir.is_nan() || pdf_dir <= 0.0 {
            return None;
        }
        // Start outside the scene's bounding sphere, upstream of the plane.
        let o = q + dir * ((self.center - q).dot(dir) - self.radius);
        Some((
            Ray::new(o, dir),
            le * (self.total_area / (covering as f32 * pdf_dir)),
        ))
    }

    /// A light path leaving area light `light`: a point on it (by area, or by the triangle weights
    /// of a textured light; its radiance at that point), a direction uniform in
    /// the cone of one target (chosen by the cones' solid angles); its ray and throughput.
    pub(super) fn emit_from_area<const N: usize>(
        &self,
        scene: &Scene,
        light: &AreaEmitter,
        wl: &Wavelengths<N>,
        u2: &mut impl FnMut() -> Vec2,
    ) -> Option<(Ray, Spectrum<N>)> {
        let (p, uv) = light.sample_area_uv(u2(), &scene.shapes[light.shape as usize]);
        // 1 − cos of each target's cone from p (2: p is inside its bounding sphere).
        let cones = || {
            self.targets.iter().map(move |t| {
                let v = t.center - p.p;
                let s2 = t.radius * t.radius / v.length_squared();
                let omc = if s2 >= 1.0 {
                    2.0
                } else {
                    s2 / (1.0 + (1.0 - s2).sqrt())
                };
                (v.normalize_or_zero(), omc)
            })
        };
        let total: f32 = cones().map(|(_, omc)| omc).sum();
        let u = u2();
        let mut pick = u.x * total;
        let (axis, omc) = cones()
            .find(|&(_, omc)| {
                pick -= omc;
                pick < 0.0
            })
            .or_else(|| cones().next_back())?;
        let local = square_to_uniform_cone(u2(), 1.0 - omc);
        let d = if omc >= 2.0 {
            local
        } else {
            Frame::from_normal(axis).to_world(local)
        };
        let cos_light = p.n.dot(d);
        if cos_light.is_nan() || cos_light <= 0.0 || p.pdf_area.is_nan() || p.pdf_area <= 0.0 {
            return None;
        }
        // Every cone holding d could have produced it: pdf = count / Σ (2π (1 − cos)).
        let covering = cones()
            .filter(|&(a, omc)| omc >= 2.0 || 1.0 - d.dot(a) <= omc)
            .count()
            .max(1);
        let pdf_dir = covering as f32 / (2.0 * std::f32::consts::PI * total);
        let le = light.radiance.eval(uv, wl);
        let ray = crate::ray::spawn(p.p, p.p_error, p.n, d);
        Some((ray, le * (cos_light / (p.pdf_area * pdf_dir))))
    }
}
