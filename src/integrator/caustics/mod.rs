//! Caustics by light tracing: light paths from the scene's bright sources, through Dirac
//! (smooth) and glossy surfaces, connected to the camera at the first surface that is neither.
//!
//! A path tracer finds a caustic (camera → diffuse surface → mirror or glass → a sun) only when
//! a BSDF-sampled ray from the diffuse surface happens to leave the smooth surface towards the
//! sun: rarely, with a large weight, as fireflies. Traced from the sun instead, the same path is
//! easy: shoot at the smooth objects, follow their Dirac lobes, and connect the diffuse surface
//! the light lands on to the camera. The two estimators split the paths between them, so every
//! path is counted once and the image stays unbiased:
//!
//! - the light tracer takes the paths camera → x₁ → y₁ … y_m → source (m ≥ 1), where x₁, the
//!   surface the camera sees, is not glossy and scattered through a smooth lobe, each yᵢ either
//!   scattered through a Dirac lobe or is glossy (every lobe Dirac or a microfacet conductor or
//!   dielectric no rougher than `max_roughness`: frosted glass, brushed metal), and "source" is
//!   an environment map's bright cells (`bright_ratio`), a directional light or an area light;
//! - the path tracer leaves exactly those out, at its environment lookups and at its emitter
//!   samples from glossy yᵢ (`Caustics::takes`), and keeps everything else. Directional lights
//!   it could never reach through a Dirac lobe: those caustics, missing from any unidirectional
//!   path tracer, are added.
//!
//! Caustics seen through a mirror or glass (camera → glass → floor → glass → sun) stay with the
//! path tracer: a light path cannot connect to the camera through a Dirac lobe.
//!
//! Light paths aim at the objects that can focus light (their bounding spheres): from infinity
//! they start on disks facing the source, one per object; from an area light they leave in the
//! cones the objects subtend. Almost every light path so reaches such an object. Their
//! contributions are splatted through the pixel filter; light paths are traced in fixed chunks
//! whose splats are added in chunk order, so the image is the same whatever the thread count.
//! Light paths carry flux (importance transport), so a refraction's radiance scaling η² is
//! undone along them, and shading normals get Veach's adjoint correction. A dispersive
//! refraction keeps the hero wavelength alone (pbrt-v4's rule) on the light path.
//!
//! ```ron
//! integrator: (max_depth: 8, caustics: Some((light_paths: 0.1, bright_ratio: 50, max_roughness: 0.3, area_lights: true)))
//! ```

use super::RenderSettings;
use crate::bsdf::{Bsdf, BsdfLike};
use crate::emitter::{AreaEmitter, BrightCells, Emitter, EnvMap};
use crate::math::distribution::Distribution1D;
use crate::math::rng::{hash3, Pcg32};
use crate::scene::Scene;
use crate::sensor::Sensor;
use crate::spectrum::Curve;
use glam::{Vec2, Vec3};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

mod connect;
mod emit;
mod sums;

use sums::{Chunk, Splat, Sums};

/// Settings of caustic light tracing (`integrator.caustics`); off when left out.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CausticSettings {
    /// Light paths per camera sample (their number is width · height · spp · this).
    pub light_paths: f32,
    /// An environment map's sampling cells at least this many times brighter than the map's
    /// mean (its sun) are light-traced sources; the rest of the map stays with the path tracer.
    pub bright_ratio: f32,
    /// Microfacet lobes up to this roughness (α) count as glossy: light paths follow them.
    pub max_roughness: f32,
    /// Area lights are sources too (their caustics through smooth objects).
    pub area_lights: bool,
    /// For tests only (not in the scene format): the path tracer keeps the light tracer's
    /// paths too, so they count twice. tests/caustics.rs shows its split tests fail then.
    #[doc(hidden)]
    #[serde(skip)]
    pub count_twice: bool,
}

impl Default for CausticSettings {
    fn default() -> Self {
        Self {
            light_paths: 0.1,
            bright_ratio: 50.0,
            max_roughness: 0.3,
            area_lights: true,
            count_twice: false,
        }
    }
}

/// Where light paths start.
enum Source<'a> {
    /// The bright cells of environment map `emitter`.
    Env {
        emitter: u32,
        map: &'a EnvMap,
        cells: BrightCells,
    },
    /// Directional light `emitter`: `direction` is the way the light travels.
    Directional {
        emitter: u32,
        direction: Vec3,
        irradiance: &'a Curve,
    },
    /// Area light `emitter`.
    Area {
        emitter: u32,
        light: &'a AreaEmitter,
    },
}

/// An object with a Dirac lobe, as light paths aim at it: its bounding sphere.
struct Target {
    center: Vec3,
    radius: f32,
}

/// Light paths' sources and targets for one scene.
pub struct Caustics<'a> {
    sources: Vec<Source<'a>>,
    targets: Vec<Target>,
    /// Targets by cross-section area.
    by_area: Distribution1D,
    total_area: f32,
    /// The scene's bounding sphere (light paths start outside it).
    center: Vec3,
    radius: f32,
    settings: CausticSettings,
}

/// Light paths per chunk (one random stream each; chunks are the unit of parallel work) and
/// chunks whose splats are held in memory at once.
const CHUNK: u64 = 4096;
const BATCH: u64 = 64;

impl<'a> Caustics<'a> {
    /// The sources and targets of `scene`; None if it has no source or no object with a Dirac
    /// lobe (then there are no such caustics, and the path tracer keeps every path).
    pub fn new(scene: &'a Scene, settings: CausticSettings) -> Option<Caustics<'a>> {
        let sources: Vec<Source> = scene
            .emitters
            .iter()
            .enumerate()
            .filter_map(|(e, em)| match em {
                Emitter::Envmap(map) => {
                    map.bright_cells(settings.bright_ratio)
                        .map(|cells| Source::Env {
                            emitter: e as u32,
                            map,
                            cells,
                        })
                }
                Emitter::Directional {
                    direction,
                    irradiance,
                } => Some(Source::Directional {
                    emitter: e as u32,
                    direction: *direction,
                    irradiance,
                }),
                Emitter::Area(light) if settings.area_lights => Some(Source::Area {
                    emitter: e as u32,
                    light,
                }),
                _ => None,
            })
            .collect();
        let targets: Vec<Target> = scene
            .shapes
            .iter()
            .enumerate()
            .filter(|&(s, _)| scene.materials[scene.shape_material[s] as usize].focuses_light())
            .filter_map(|(_, shape)| {
                let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
                for i in 0..shape.prim_count() {
                    let (a, b) = shape.prim_geom(i).bounds();
                    (lo, hi) = (lo.min(a), hi.max(b));
                }
                let (center, radius) = ((lo + hi) * 0.5, (hi - lo).length() * 0.5 * 1.001);
                (radius > 0.0 && radius.is_finite()).then_some(Target { center, radius })
            })
            .collect();
        if sources.is_empty() || targets.is_empty() {
            return None;
        }
        let areas: Vec<f32> = targets
            .iter()
            .map(|t| std::f32::consts::PI * t.radius * t.radius)
            .collect();
        let (lo, hi) = scene.bounds();
        Some(Caustics {
            sources,
            by_area: Distribution1D::new(&areas),
            total_area: areas.iter().sum(),
            targets,
            center: (lo + hi) * 0.5,
            radius: (hi - lo).length() * 0.5 * 1.01 + 1e-3,
            settings,
        })
    }

    /// True if a camera path of the light tracer's form (see the module docs) that reaches
    /// emitter `e` in direction `d` is the light tracer's: the path tracer then leaves it out.
    #[inline]
    pub fn takes(&self, e: u32, d: Vec3) -> bool {
        !self.settings.count_twice
            && self.sources.iter().any(|s| match s {
                Source::Env {
                    emitter,
                    map,
                    cells,
                    ..
                } => *emitter == e && cells.contains(map.cell(d)),
                Source::Directional { emitter, .. } | Source::Area { emitter, .. } => *emitter == e,
            })
    }

    /// Microfacet lobes up to this roughness are glossy (`BsdfLike::glossy`).
    #[inline]
    pub fn max_roughness(&self) -> f32 {
        self.settings.max_roughness
    }

    /// Traces the light paths of a render whose camera estimates took `samples` samples in
    /// all (`light_paths` per camera sample: an adaptive render's count is known only after
    /// its camera pass) and returns what they add to each pixel's accumulator slots
    /// (`sensor.slots()` per pixel, means over the light paths) and, with `SE`, the variance
    /// of those means (empty otherwise).
    pub fn render<const N: usize, const SE: bool>(
        &self,
        scene: &Scene,
        settings: &RenderSettings,
        sensor: &Sensor,
        samples: u64,
    ) -> (Vec<f64>, Vec<f64>) {
        let pixels = (settings.width * settings.height) as usize;
        let mut sums = Sums::new(pixels, sensor.slots(), SE);
        let paths = ((samples as f64 * self.settings.light_paths as f64).round() as u64).max(1);
        let chunks = paths.div_ceil(CHUNK);
        let seed = hash3(settings.seed, 0xca05_71c5, 0);
        let mut next = 0;
        while next < chunks {
            // Indexed by their offset in the batch (a u64 range is not an indexed iterator).
            let batch: Vec<Chunk<N>> = (0..(chunks - next).min(BATCH) as usize)
                .into_par_iter()
                // Every chunk its own job, as the camera pass's tiles: rayon otherwise runs a
                // range of chunks as one leaf, and a thread finished early waits for it.
                .with_max_len(1)
                .map(|i| {
                    let c = next + i as u64;
                    let mut out = Chunk::default();
                    for k in c * CHUNK..((c + 1) * CHUNK).min(paths) {
                        let start = out.splats.len();
                        self.trace::<N>(scene, settings, hash3(seed, k, 1), &mut out.splats);
                        if SE && out.splats.len() > start {
                            out.starts.push(start as u32);
                        }
                    }
                    out
                })
                .collect();
            for chunk in &batch {
                sums.add::<N, SE>(sensor, chunk);
            }
            next += BATCH;
        }
        sums.finish(paths)
    }

    /// One light path, its splats appended to `out`.
    fn trace<const N: usize>(
        &self,
        scene: &Scene,
        settings: &RenderSettings,
        seed: u64,
        out: &mut Vec<Splat<N>>,
    ) {
        let mut rng = Pcg32::new(seed, 0x11);
        let mut u2 = || Vec2::new(rng.next_f32(), rng.next_f32());
        let u = u2();
        let wl = settings.wavelengths.sample::<N>(u.x);
        let n_src = self.sources.len();
        let src = &self.sources[((u.y * n_src as f32) as usize).min(n_src - 1)];
        let Some((mut ray, mut beta)) = (match src {
            Source::Env { map, cells, .. } => map
                .sample_bright(cells, u2())
                .and_then(|(d, pdf)| self.emit_from_infinity(-d, map.eval(d, &wl), pdf, &mut u2)),
            Source::Directional {
                direction,
                irradiance,
                ..
            } => self.emit_from_infinity(*direction, irradiance.eval(&wl), 1.0, &mut u2),
            Source::Area { light, .. } => self.emit_from_area(scene, light, &wl, &mut u2),
        }) else {
            return;
        };
        beta *= n_src as f32;
        let max_depth = if settings.path.max_depth < 0 {
            u32::MAX
        } else {
            settings.path.max_depth as u32
        };
        let mut bsdf = Bsdf::default();
        // Vertices of the chain so far (each a Dirac event or a glossy surface).
        let mut dirac = 0u32;
        let mut terminated = false;
        while !beta.is_zero() {
            let Some(si) = scene.intersect(&ray) else {
                return;
            };
            let material = &scene.materials[scene.shape_material[si.shape as usize] as usize];
            let towards_light = -ray.d;
            let wi = si.frame.to_local(towards_light);
            material.fill_bsdf(&si, wi, &wl, &mut bsdf);
            // The camera path of this light path has dirac + 2 segments. Glossy surfaces seen
            // by the camera stay with the path tracer (connections through a glossy lobe would
            // be the fireflies here).
            let glossy = bsdf.glossy(self.settings.max_roughness);
            if dirac >= 1 && dirac + 2 <= max_depth && bsdf.has_smooth() && !glossy {
                self.connect(scene, settings, &si, &bsdf, towards_light, beta, &wl, out);
            }
            if dirac + 3 > max_depth {
                return;
            }
            let u = u2();
            let Some(bs) = bsdf.sample(wi, u.x, u2()) else {
                return;
            };
            if !bs.delta && !glossy {
                return;
            }
            let wo_world = si.frame.to_world(bs.wo);
            // Light paths carry flux: the BSDF's radiance scaling of a refraction (η_ti² in the
            // direction it was sampled) is undone; and with shading normals the adjoint BSDF
            // trades the shading cosine of the sampled side for the light side's (Veach 1997,
            // 5.3), a factor 1 where shading and geometric normals agree.
            let (cos_ls, cos_lg) = (wi.z.abs(), si.ng.dot(towards_light).abs());
            let (cos_os, cos_og) = (bs.wo.z.abs(), si.ng.dot(wo_world).abs());
            if cos_lg * cos_os <= 0.0 {
                return;
            }
            beta *= bs.weight * (bs.eta * bs.eta * cos_ls * cos_og / (cos_lg * cos_os));
            let refracted = bs.eta != 1.0;
            if N > 1 && refracted && !terminated && bs.pdf_lanes.0.iter().any(|&p| p != bs.pdf) {
                // A dispersive event: the other lanes would leave in other directions. Keep the
                // hero alone (pbrt-v4's rule): its estimate then stands for all N lanes.
                for k in 1..N {
                    beta[k] = 0.0;
                }
                beta[0] *= N as f32;
                terminated = true;
            }
            dirac += 1;
            // Long chains (inside glass) end by Russian roulette.
            if dirac >= 8 {
                if u.y >= 0.9 {
                    return;
                }
                beta /= 0.9;
            }
            ray = si.spawn(wo_world);
        }
    }
}

#[cfg(test)]
mod tests;
