//! Emitters: area lights on shapes, point and spot lights, a directional light, and a constant
//! or image-based environment. Each can be sampled from a surface point (`sample_li`) and report
//! the density with which it would have produced a given direction (`pdf_li`), which multiple
//! importance sampling needs.

mod area;
mod envmap;
mod moving;
mod moving_area;
mod parallelogram;
mod radiance;
mod spot;

use crate::interaction::SurfaceInteraction;
use crate::math::sampling::{square_to_uniform_sphere, UNIFORM_SPHERE_PDF};
use crate::ray::Ray;
use crate::shape::Shape;
use crate::spectrum::{Curve, Spectrum, Wavelengths};
pub use area::{AreaEmitter, AreaLightSample};
pub use envmap::{illuminant as envmap_illuminant, BrightCells, EnvMap, TAIL_END, TAIL_KELVIN};
use glam::{Vec2, Vec3};
pub use moving::MovingLight;
pub use moving_area::MovingArea;
pub use radiance::{AreaRadiance, EmissionTexel, EmissionTexture};
pub use spot::Spot;

#[derive(Clone, Debug)]
pub enum Emitter {
    /// Emits `radiance` from the front side of a shape.
    Area(AreaEmitter),
    /// Emits `intensity` (W sr⁻¹ nm⁻¹) equally in all directions from a point.
    Point { position: Vec3, intensity: Curve },
    /// Radiance `radiance` arriving from every direction at infinity.
    Constant { radiance: Curve },
    // Spot, directional and environment-map emitters.
    /// A point light emitting into a cone, with a linear falloff in angle near its edge.
    Spot(Spot),
    /// Light arriving from a single direction at infinity: `direction` is the way it travels
    /// (unit), `irradiance` (W m⁻² nm⁻¹) what a surface facing the light receives.
    Directional { direction: Vec3, irradiance: Curve },
    /// Radiance at infinity read from a latitude-longitude image.
    Envmap(Box<EnvMap>),
    /// A point, spot, directional light or environment map moving while the shutter is open.
    Moving(Box<MovingLight>),
    /// An area light on a shape moving while the shutter is open.
    MovingArea(Box<MovingArea>),
}

/// Light arriving at a point from a sampled point on an emitter.
#[derive(Clone, Copy, Debug)]
pub struct EmitterSample<const N: usize> {
    /// Unit direction from the receiving point towards the light.
    pub wi: Vec3,
    /// The shadow ray to test visibility with.
    pub shadow: Ray,
    /// Emitted radiance (intensity / distance² for a point light) at the lanes.
    pub radiance: Spectrum<N>,
    /// Solid-angle density of `wi` (1 for a delta light).
    pub pdf: f32,
    pub delta: bool,
}

impl Emitter {
    pub fn is_environment(&self) -> bool {
        // Only lights that escaping rays can see; a directional light is a delta in direction,
        // which no ray hits.
        matches!(self, Emitter::Constant { .. } | Emitter::Envmap(_))
            || matches!(self, Emitter::Moving(m) if m.light.is_environment())
    }

    /// Samples light arriving at `si`. None if the sample carries nothing (back side, zero pdf).
    /// The path loop does not call this: it samples area lights and environment maps for a
    /// direction first and looks their radiance up only for unoccluded samples
    /// (`AreaEmitter::sample_point`, `EnvMap::sample`), and calls `sample_li_other` for the
    /// rest, out of line (with every kind inline the loop grew too large to inline).
    #[inline(always)]
    pub fn sample_li<const N: usize>(
        &self,
        si: &SurfaceInteraction,
        u: Vec2,
        wl: &Wavelengths<N>,
        shapes: &[Shape],
    ) -> Option<EmitterSample<N>> {
        match self {
            Emitter::Area(a) => a.sample_li(si, u, wl, shapes),
            _ => self.sample_li_other(si, u, wl),
        }
    }

    /// `sample_li` for every kind but area lights.
    #[inline(never)]
    pub(crate) fn sample_li_other<const N: usize>(
        &self,
        si: &SurfaceInteraction,
        u: Vec2,
        wl: &Wavelengths<N>,
    ) -> Option<EmitterSample<N>> {
        match self {
            Emitter::Area(_) => unreachable!("area lights are sampled by `sample_li`"),
            Emitter::MovingArea(m) => m.sample_point(si, u).map(|s| EmitterSample {
                wi: s.wi,
                shadow: s.shadow,
                radiance: m.area.radiance.eval(s.uv, wl),
                pdf: s.pdf,
                delta: false,
            }),
            Emitter::Point {
                position,
                intensity,
            } => {
                let to = *position - si.p;
                let d2 = to.length_squared();
                if d2 <= 0.0 {
                    return None;
                }
                let shadow = si.spawn_to(*position, Vec3::ZERO, None);
                Some(EmitterSample {
                    wi: to / d2.sqrt(),
                    shadow,
                    radiance: intensity.eval(wl) * (1.0 / d2),
                    pdf: 1.0,
                    delta: true,
                })
            }
            Emitter::Constant { radiance } => {
                let wi = square_to_uniform_sphere(u);
                Some(EmitterSample {
                    wi,
                    shadow: si.spawn(wi),
                    radiance: radiance.eval(wl),
                    pdf: UNIFORM_SPHERE_PDF,
                    delta: false,
                })
            }
            Emitter::Spot(s) => s.sample_li(si, wl),
            Emitter::Directional {
                direction,
                irradiance,
            } => {
                let wi = -*direction;
                // Radiance = irradiance with pdf 1: f·L/pdf is then E·f·cos θ, as it should be.
                Some(EmitterSample {
                    wi,
                    shadow: si.spawn(wi),
                    radiance: irradiance.eval(wl),
                    pdf: 1.0,
                    delta: true,
                })
            }
            Emitter::Moving(m) => m.sample_li(si, u, wl),
            Emitter::Envmap(m) => {
                let (wi, pdf) = m.sample(u)?;
                Some(EmitterSample {
                    wi,
                    shadow: si.spawn(wi),
                    radiance: m.eval(wi, wl),
                    pdf,
                    delta: false,
                })
            }
        }
    }

    /// `sample_li_other` for the light carried by `m` (world from the light's own frame: a
    /// moving light at a sample's time, `MovingLight`). An environment map turns by `m`'s
    /// rotation only (its keys hold no scale or translation).
    pub(crate) fn sample_li_carried<const N: usize>(
        &self,
        m: &glam::Mat4,
        si: &SurfaceInteraction,
        u: Vec2,
        wl: &Wavelengths<N>,
    ) -> Option<EmitterSample<N>> {
        match self {
            Emitter::Point {
                position,
                intensity,
            } => {
                let p = m.transform_point3(*position);
                let to = p - si.p;
                let d2 = to.length_squared();
                if d2 <= 0.0 {
                    return None;
                }
                Some(EmitterSample {
                    wi: to / d2.sqrt(),
                    shadow: si.spawn_to(p, Vec3::ZERO, None),
                    radiance: intensity.eval(wl) * (1.0 / d2),
                    pdf: 1.0,
                    delta: true,
                })
            }
            Emitter::Spot(s) => s.sample_li_moved(m, si, wl),
            Emitter::Directional {
                direction,
                irradiance,
            } => {
                let wi = -m.transform_vector3(*direction).try_normalize()?;
                Some(EmitterSample {
                    wi,
                    shadow: si.spawn(wi),
                    radiance: irradiance.eval(wl),
                    pdf: 1.0,
                    delta: true,
                })
            }
            Emitter::Envmap(map) => {
                let (local, pdf) = map.sample(u)?;
                let wi = m.transform_vector3(local).normalize();
                Some(EmitterSample {
                    wi,
                    shadow: si.spawn(wi),
                    radiance: map.eval(local, wl),
                    pdf,
                    delta: false,
                })
            }
            _ => None,
        }
    }

    /// The light carried by `m` as a static one (`prism export` of a moving light).
    pub(crate) fn carried(&self, m: &glam::Mat4) -> Emitter {
        match self {
            Emitter::Point {
                position,
                intensity,
            } => Emitter::Point {
                position: m.transform_point3(*position),
                intensity: intensity.clone(),
            },
            Emitter::Spot(s) => Emitter::Spot(s.carried(m)),
            Emitter::Directional {
                direction,
                irradiance,
            } => Emitter::Directional {
                direction: m.transform_vector3(*direction).normalize_or(*direction),
                irradiance: irradiance.clone(),
            },
            other => other.clone(),
        }
    }

    /// Solid-angle density of `sample_li` from `p` producing the hit `light` (area emitters).
    #[inline]
    pub fn pdf_li_hit(&self, p: Vec3, light: &SurfaceInteraction, shapes: &[Shape]) -> f32 {
        match self {
            Emitter::Area(a) => a.pdf_li(p, light, shapes),
            Emitter::MovingArea(m) => m.pdf_li(p, light),
            _ => 0.0,
        }
    }

    /// Solid-angle density of `sample_li` producing direction `d` towards infinity (a moving
    /// map in its pose at time 0).
    #[inline]
    pub fn pdf_li_env(&self, d: Vec3) -> f32 {
        self.pdf_li_env_at(d, 0.0)
    }

    /// `pdf_li_env` at `time`. Always inlined: a moving map's own lookup is out of line
    /// (`MovingLight::pdf_env`), so a still scene's path loop pays no call.
    #[inline(always)]
    pub fn pdf_li_env_at(&self, d: Vec3, time: f32) -> f32 {
        match self {
            Emitter::Constant { .. } => UNIFORM_SPHERE_PDF,
            Emitter::Envmap(m) => m.pdf(d),
            Emitter::Moving(m) => m.pdf_env(d, time),
            _ => 0.0,
        }
    }

    /// Radiance arriving from infinity along direction `d` (environment emitters; a moving map
    /// in its pose at time 0).
    #[inline]
    pub fn le_env<const N: usize>(&self, d: Vec3, wl: &Wavelengths<N>) -> Spectrum<N> {
        self.le_env_at(d, 0.0, wl)
    }

    /// `le_env_at` and `pdf_li_env_at` together: an environment map finds the direction's
    /// place on the map once for both (the same bits as the two calls).
    #[inline(always)]
    pub fn le_and_pdf_env_at<const N: usize>(
        &self,
        d: Vec3,
        time: f32,
        wl: &Wavelengths<N>,
    ) -> (Spectrum<N>, f32) {
        match self {
            Emitter::Envmap(m) => m.eval_and_pdf(d, wl),
            _ => (self.le_env_at(d, time, wl), self.pdf_li_env_at(d, time)),
        }
    }

    /// `le_env` at `time` (the escaping ray's).
    #[inline]
    pub fn le_env_at<const N: usize>(
        &self,
        d: Vec3,
        time: f32,
        wl: &Wavelengths<N>,
    ) -> Spectrum<N> {
        match self {
            Emitter::Constant { radiance } => radiance.eval(wl),
            Emitter::Envmap(m) => m.eval(d, wl),
            Emitter::Moving(m) => m.le_env(d, time, wl),
            _ => Spectrum::zero(),
        }
    }
}
