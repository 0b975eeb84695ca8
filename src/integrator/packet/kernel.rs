//! The packet kernel's stages over W lanes. Each stage is the scalar integrator's code for one
//! path (`integrator::path::radiance` without dispersion or caustics, which `unsupported`
//! sends to the scalar integrator), run for every busy lane in turn, so every lane does the
//! scalar integrator's operations in its order: the bits cannot depend on W.

use super::stream::{Item, Stream};
use super::TileArgs;
use crate::bsdf::Bsdf;
use crate::integrator::path::{Dispersion, Path};
use crate::integrator::{TileCounts, TileOut, TILE};
use crate::interaction::SurfaceInteraction;
use crate::ray::Ray;
use crate::sampler::{PixelSampler, BOUNCE_DIMS, CAMERA_DIMS};
use crate::spectrum::{Spectrum, Wavelengths};
use glam::{Vec2, Vec3};

/// One lane: the path it traces, and which camera sample that is.
struct Lane<'a, const N: usize> {
    /// The stream item it traces; None when idle.
    item: Option<Item>,
    /// The pixel (index in the image) `sampler` belongs to: a lane taking the same pixel's
    /// next sample keeps it (its Sobol scrambles are made once per pixel).
    pixel: u64,
    sampler: PixelSampler,
    wl: Wavelengths<N>,
    ray: Ray,
    path: Path<N>,
    depth: u32,
    /// The BSDF at the current hit, rebuilt in place at each (as the scalar loop does).
    bsdf: Bsdf<'a, N>,
}

/// Renders one tile in packets of W paths.
#[inline(always)]
pub(super) fn tile<const N: usize, const W: usize, const SE: bool>(a: TileArgs) -> TileOut {
    let (scene, settings, sensor, progress, x0, y0) = a;
    let (x1, y1) = (
        (x0 + TILE).min(settings.width),
        (y0 + TILE).min(settings.height),
    );
    let tw = x1 - x0;
    let slots = sensor.slots();
    let pixels = (tw * (y1 - y0)) as usize;
    let mut out = TileOut {
        means: Vec::with_capacity(pixels * slots),
        se: Vec::with_capacity(if SE { pixels * slots } else { 0 }),
        spp: Vec::with_capacity(pixels),
        counts: TileCounts::default(),
    };
    let clamp = settings.path.clamp.unwrap_or(f32::INFINITY);
    let mut stream = Stream::<N>::new(pixels as u64, settings.spp, slots, SE, clamp);
    let max_depth = match settings.path.max_depth {
        d if d < 0 => u32::MAX,
        d => d as u32,
    };
    let n_emitters = scene.emitters.len();
    let placeholder_wl = settings.wavelengths.sample::<N>(0.5);
    let mut lanes: [Lane<N>; W] = std::array::from_fn(|_| Lane {
        item: None,
        pixel: u64::MAX,
        sampler: PixelSampler::new(settings.sampler, settings.seed, 0),
        wl: placeholder_wl,
        ray: Ray::new(Vec3::ZERO, Vec3::Z),
        path: Path::start(Vec3::ZERO, n_emitters, Dispersion::default()),
        depth: 1,
        bsdf: Bsdf::default(),
    });
    let mut hits: [Option<SurfaceInteraction>; W] = [None; W];
    let mut countdown = super::super::CHECK_EVERY;
    loop {
        // Every so many steps, a caller stopping the render (Ctrl-C in Python) unwinds from
        // here, inside a long tile too.
        countdown -= 1;
        if countdown == 0 {
            countdown = super::super::CHECK_EVERY;
            progress(0);
        }
        // Refill: idle lanes take the stream's next samples, in lane order.
        for lane in lanes.iter_mut().filter(|l| l.item.is_none()) {
            let Some((item, p, s)) = stream.take() else {
                break;
            };
            let (x, y) = (x0 + p as u32 % tw, y0 + p as u32 / tw);
            let pixel = y as u64 * settings.width as u64 + x as u64;
            if lane.pixel != pixel {
                lane.sampler.reset(settings.sampler, settings.seed, pixel);
                lane.pixel = pixel;
            }
            let sampler = &mut lane.sampler;
            sampler.start(s);
            let offset = settings.filter.sample(sampler.next_2d());
            let film = Vec2::new(x as f32 + 0.5, y as f32 + 0.5) + offset;
            lane.wl = settings.wavelengths.sample::<N>(sampler.next_1d());
            lane.ray = scene.camera_ray(film, y, sampler);
            if max_depth == 0 {
                stream.put(item, Spectrum::zero(), lane.wl);
                continue;
            }
            lane.path = Path::start(lane.ray.o, n_emitters, settings.dispersion);
            lane.depth = 1;
            lane.item = Some(item);
        }
        stream.flush::<SE>(sensor, &mut out);
        if lanes.iter().all(|l| l.item.is_none()) {
            if stream.finished() {
                break;
            }
            continue; // paths ended at the camera (max_depth 0): refill
        }

        // Trace: one ray per lane through the BVH.
        for (lane, hit) in lanes.iter().zip(hits.iter_mut()) {
            if lane.item.is_some() {
                *hit = scene.intersect(&lane.ray);
            }
        }

        // Emission at the hit (or from the environment on a miss); the BSDF at the hit.
        for (lane, hit) in lanes.iter_mut().zip(hits.iter()) {
            let Some(item) = lane.item else { continue };
            let (ray, path, wl) = (&lane.ray, &mut lane.path, &lane.wl);
            let show = lane.depth > 1 || !settings.path.hide_emitters;
            let Some(si) = hit else {
                if show {
                    for &e in &scene.environment {
                        path.add_environment(&scene.emitters[e as usize], ray, wl);
                    }
                }
                stream.put(item, path.l, *wl);
                lane.item = None;
                continue;
            };
            if let Some(e) = scene.shape_emitter[si.shape as usize] {
                path.add_hit_emission(scene, e, si, ray.d, wl, show);
            }
            if lane.depth >= max_depth {
                stream.put(item, path.l, *wl);
                lane.item = None;
                continue;
            }
            let dim = CAMERA_DIMS + (lane.depth - 1).min(1 << 20) * BOUNCE_DIMS;
            lane.sampler.set_dimension(dim);
            let material = &scene.materials[scene.shape_material[si.shape as usize] as usize];
            material.fill_bsdf(si, si.frame.to_local(-ray.d), wl, &mut lane.bsdf);
        }

        // Scatter: one pass per kind of BSDF, each over the lanes holding that kind.
        for diffuse_pass in [true, false] {
            for (lane, hit) in lanes.iter_mut().zip(hits.iter()) {
                let (Some(item), Some(si)) = (lane.item, hit) else {
                    continue;
                };
                let (ray, path, wl, sampler) =
                    (&lane.ray, &mut lane.path, &lane.wl, &mut lane.sampler);
                let next = match (&lane.bsdf, diffuse_pass) {
                    (Bsdf::Diffuse(d), true) => {
                        path.scatter::<false>(d, si, -ray.d, scene, wl, sampler, None)
                    }
                    (Bsdf::Mixture(m), false) => {
                        path.scatter::<false>(m, si, -ray.d, scene, wl, sampler, None)
                    }
                    _ => continue,
                };
                match next {
                    Some(r) => lane.ray = r,
                    None => {
                        stream.put(item, path.l, *wl);
                        lane.item = None;
                    }
                }
            }
        }

        // Russian roulette, then the next bounce.
        for (lane, hit) in lanes.iter_mut().zip(hits.iter()) {
            let (Some(item), Some(_)) = (lane.item, hit) else {
                continue;
            };
            let path = &mut lane.path;
            if lane.depth >= settings.path.rr_depth {
                let q = (path.beta.max_value() * path.lane_w * path.eta * path.eta).min(0.95);
                if lane.sampler.next_1d() >= q {
                    stream.put(item, path.l, lane.wl);
                    lane.item = None;
                    continue;
                }
                path.beta /= q;
            }
            lane.depth += 1;
        }
        stream.flush::<SE>(sensor, &mut out);
    }
    out
}
