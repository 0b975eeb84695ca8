//! A light-path vertex connected to the camera: its importance, and its splats through the
//! pixel filter.

use super::{Caustics, Splat};
use crate::bsdf::{Bsdf, BsdfLike};
use crate::integrator::RenderSettings;
use crate::interaction::SurfaceInteraction;
use crate::scene::Scene;
use crate::spectrum::{Spectrum, Wavelengths};
use glam::{Vec2, Vec3};

impl Caustics<'_> {
    /// Connects light-path vertex `si` (light arriving from `towards_light`, throughput `beta`)
    /// to the camera and splats what the camera sees through the pixel filter.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn connect<const N: usize>(
        &self,
        scene: &Scene,
        settings: &RenderSettings,
        si: &SurfaceInteraction,
        bsdf: &Bsdf<N>,
        towards_light: Vec3,
        beta: Spectrum<N>,
        wl: &Wavelengths<N>,
        out: &mut Vec<Splat<N>>,
    ) {
        let Some(pr) = scene.camera.project(si.p, settings.filter.radius()) else {
            return;
        };
        let (wc, wo) = (si.frame.to_local(pr.wi), si.frame.to_local(towards_light));
        // f · |cos θ| at the light's side, in the shading frame.
        let f = bsdf.eval(wc, wo);
        let cos_light = si.ng.dot(towards_light).abs();
        if f.is_zero() || cos_light <= 0.0 {
            return;
        }
        if scene.occluded(&si.spawn_to(scene.camera.position(), Vec3::ZERO, None)) {
            return;
        }
        // beta · f_s |cos_s| / |cos_g| (shading normals: Veach's adjoint correction), times the
        // camera's solid angle per area at the point and its film area per solid angle.
        let g = si.ng.dot(pr.wi).abs() / (cos_light * pr.dist * pr.dist) * pr.importance;
        let c = beta * f * g;
        if !c.is_finite() {
            return;
        }
        let filter = &settings.filter;
        let r = filter.radius();
        let (w, h) = (settings.width as i64, settings.height as i64);
        let (x0, x1) = (
            (pr.film.x - r).floor() as i64,
            (pr.film.x + r).floor() as i64,
        );
        let (y0, y1) = (
            (pr.film.y - r).floor() as i64,
            (pr.film.y + r).floor() as i64,
        );
        for y in y0.max(0)..=y1.min(h - 1) {
            for x in x0.max(0)..=x1.min(w - 1) {
                let centre = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                let wf = filter.eval(pr.film - centre);
                if wf > 0.0 {
                    out.push(Splat {
                        pixel: (y * w + x) as u32,
                        l: c * wf,
                        wl: *wl,
                    });
                }
            }
        }
    }
}
