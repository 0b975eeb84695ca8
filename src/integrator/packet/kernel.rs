//! The packet kernel's stages over W lanes. Each stage is the scalar integrator's code for one
//! path (`integrator::path::radiance` without dispersion, which `unsupported` sends to the
//! scalar integrator; with caustic light tracing's split where the render has it), run for
//! every busy lane in turn, so every lane does the scalar integrator's operations in its
//! order: the bits cannot depend on W.
//!
//! A lane owns a pixel until it has traced all its samples, one after another, and sums each
//! into the pixel's accumulators as it finishes: in sample order, as the scalar loop does, with
//! no reordering between lanes. Its sampler's per-pixel scrambles are made once per pixel (a
//! lane that hopped between pixels remade them at every hop).

use crate::bsdf::{Bsdf, BsdfLike};
use crate::integrator::path::{Dispersion, Path};
use crate::integrator::{adaptive, add_sample, Sums, TileCounts, TileOut, TILE};
use crate::interaction::SurfaceInteraction;
use crate::ray::Ray;
use crate::sampler::{PixelSampler, BOUNCE_DIMS, CAMERA_DIMS};
use crate::sensor::Sensor;
use crate::spectrum::Wavelengths;
use glam::{Vec2, Vec3};

use super::passes::{Fixed, Pass, Pilots, Rest};
use super::TileArgs;

/// One lane: the pixel it owns, and the path it traces.
struct Lane<'a, const N: usize> {
    /// True while it traces a path.
    busy: bool,
    /// The pixel it owns (index in the tile), if any, and its (x, y) in the image.
    pixel: Option<usize>,
    xy: (u32, u32),
    /// Its pixel's next sample to start, and the end of the pass's samples of it.
    next: u32,
    to: u32,
    /// Its pixel's accumulators.
    sums: Sums,
    /// Caustic light tracing's share, as `path::radiance` keeps it: the chain of smooth
    /// vertices so far, and whether the current hit is glossy.
    chain: Option<u32>,
    glossy: bool,
    sampler: PixelSampler,
    wl: Wavelengths<N>,
    ray: Ray,
    path: Path<N>,
    depth: u32,
    /// The BSDF at the current hit, rebuilt in place at each (as the scalar loop does).
    bsdf: Bsdf<'a, N>,
}

impl<const N: usize> Lane<'_, N> {
    /// Ends the lane's path: its radiance is its pixel's next sample.
    #[inline(always)]
    fn finish<const SE: bool>(&mut self, sensor: &Sensor, clamp: f32, counts: &mut TileCounts) {
        self.busy = false;
        add_sample::<N, SE>(sensor, clamp, self.path.l, &self.wl, &mut self.sums, counts);
    }
}

/// Renders one tile in packets of W paths: one pass at a fixed spp, two under adaptive
/// sampling (`passes`).
#[inline(always)]
pub(super) fn tile<const N: usize, const W: usize, const SE: bool, const C: bool>(
    a: TileArgs,
) -> TileOut {
    let (_, settings, sensor, _, _, x0, y0) = a;
    let (tw, th) = (
        (x0 + TILE).min(settings.width) - x0,
        (y0 + TILE).min(settings.height) - y0,
    );
    let slots = sensor.slots();
    let pixels = (tw * th) as usize;
    // Sized for the tile: lanes finish their pixels out of order.
    let mut out = TileOut {
        means: vec![0.0; pixels * slots],
        se: vec![0.0; if SE { pixels * slots } else { 0 }],
        spp: vec![0; pixels],
        counts: TileCounts::default(),
    };
    let seed = settings.seed;
    let Some(ad) = &settings.adaptive else {
        let mut fixed = Fixed::<SE> {
            seed,
            spp: settings.spp,
        };
        run::<N, W, SE, C, _>(a, &mut fixed, &mut out);
        return out;
    };
    let judged = adaptive::target_slots(ad, sensor);
    let pilot_pass = |seed| Pilots {
        seed,
        min: ad.min,
        sums: (0..pixels).map(|_| Sums::new(slots, true)).collect(),
    };
    let mut pilots = pilot_pass(seed);
    run::<N, W, true, C, _>(a, &mut pilots, &mut out);
    let near = adaptive::counts(ad, settings.sampler, &pilots.pilots(&judged), (tw, th));
    let mut own = None;
    if near.iter().any(Option::is_none) {
        // A pixel alone in its tile: a pilot of its own from a stream of its own, discarded.
        let mut p = pilot_pass(adaptive::pilot_seed(seed));
        run::<N, W, true, C, _>(a, &mut p, &mut out);
        own = Some(p.sums);
    }
    let counts = near
        .iter()
        .enumerate()
        .map(|(p, c)| match (c, &own) {
            (Some(c), _) => *c,
            (None, Some(o)) => {
                let s = &o[p];
                adaptive::count(ad, settings.sampler, ad.min, &s.acc, &s.acc2, &judged)
            }
            (None, None) => unreachable!("own pilots are drawn where a count is missing"),
        })
        .collect();
    let mut rest = Rest::<SE> {
        seed,
        min: ad.min,
        counts,
        pilots: pilots.sums,
    };
    run::<N, W, SE, C, _>(a, &mut rest, &mut out);
    out
}

/// One pass of the tile at (x0, y0) in packets of W paths (`SQ`: sums of squares too; `C`:
/// the paths caustic light tracing takes are left out, as `path::radiance` leaves them).
#[inline(always)]
fn run<const N: usize, const W: usize, const SQ: bool, const C: bool, P: Pass>(
    a: TileArgs,
    pass: &mut P,
    out: &mut TileOut,
) {
    let (scene, settings, sensor, caustics, progress, x0, y0) = a;
    // Known to be None in the copy without caustics, so its checks compile away there.
    let caustics = if C { caustics } else { None };
    let tw = (x0 + TILE).min(settings.width) - x0;
    let pixels = out.spp.len();
    let clamp = settings.path.clamp.unwrap_or(f32::INFINITY);
    let max_depth = match settings.path.max_depth {
        d if d < 0 => u32::MAX,
        d => d as u32,
    };
    let n_emitters = scene.emitters.len();
    let placeholder_wl = settings.wavelengths.sample::<N>(0.5);
    let mut lanes: [Lane<N>; W] = std::array::from_fn(|_| Lane {
        busy: false,
        pixel: None,
        xy: (0, 0),
        next: 0,
        to: 0,
        sums: Sums::new(sensor.slots(), SQ),
        chain: None,
        glossy: false,
        sampler: PixelSampler::new(settings.sampler, pass.seed(), 0),
        wl: placeholder_wl,
        ray: Ray::new(Vec3::ZERO, Vec3::Z),
        path: Path::start(Vec3::ZERO, n_emitters, Dispersion::default()),
        depth: 1,
        bsdf: Bsdf::default(),
    });
    let mut next_pixel = 0usize;
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
        // Refill: an idle lane starts its pixel's next sample; once the pixel has the pass's
        // samples it is handed to the pass and the lane takes the tile's next pixel.
        for lane in lanes.iter_mut().filter(|l| !l.busy) {
            let started = loop {
                match lane.pixel {
                    Some(_) if lane.next < lane.to => break true,
                    Some(p) => {
                        pass.end(p, &lane.sums, out);
                        lane.pixel = None;
                    }
                    None if next_pixel == pixels => break false,
                    None => {
                        let p = next_pixel;
                        next_pixel += 1;
                        let (from, to) = pass.range(p);
                        out.counts.samples += to.saturating_sub(from) as u64;
                        pass.begin(p, &mut lane.sums);
                        let (x, y) = (x0 + p as u32 % tw, y0 + p as u32 / tw);
                        let pixel = y as u64 * settings.width as u64 + x as u64;
                        lane.sampler.reset(settings.sampler, pass.seed(), pixel);
                        (lane.pixel, lane.xy, lane.next, lane.to) = (Some(p), (x, y), from, to);
                    }
                }
            };
            if !started {
                continue;
            }
            let (x, y) = lane.xy;
            let sampler = &mut lane.sampler;
            sampler.start(lane.next);
            lane.next += 1;
            let offset = settings.filter.sample(sampler.next_2d());
            let film = Vec2::new(x as f32 + 0.5, y as f32 + 0.5) + offset;
            lane.wl = settings.wavelengths.sample::<N>(sampler.next_1d());
            lane.ray = scene.camera_ray(film, y, sampler);
            lane.path = Path::start(lane.ray.o, n_emitters, settings.dispersion);
            lane.depth = 1;
            lane.chain = None;
            lane.busy = true;
            if max_depth == 0 {
                // The path ends at the camera: a zero sample (the lane refills next step).
                lane.finish::<SQ>(sensor, clamp, &mut out.counts);
            }
        }
        if lanes.iter().all(|l| !l.busy) {
            if lanes.iter().all(|l| l.pixel.is_none()) {
                break; // every pixel handed to the pass
            }
            continue; // paths ended at the camera (max_depth 0): refill
        }

        // Trace: one ray per lane through the BVH.
        for (lane, hit) in lanes.iter().zip(hits.iter_mut()) {
            if lane.busy {
                *hit = scene.intersect(&lane.ray);
            }
        }

        // Emission at the hit (or from the environment on a miss); the BSDF at the hit. The
        // lanes that go on to scatter are listed by kind of BSDF (`Scatter`).
        let mut scatter = Scatter::<W>::default();
        for (i, (lane, hit)) in lanes.iter_mut().zip(hits.iter()).enumerate() {
            if !lane.busy {
                continue;
            }
            let (ray, path, wl, chain) = (&lane.ray, &mut lane.path, &lane.wl, lane.chain);
            let show = lane.depth > 1 || !settings.path.hide_emitters;
            let Some(si) = hit else {
                if show {
                    for &e in &scene.environment {
                        if matches!((caustics, chain), (Some(c), Some(1..)) if c.takes(e, ray.d)) {
                            continue;
                        }
                        path.add_environment(&scene.emitters[e as usize], ray, wl);
                    }
                }
                lane.finish::<SQ>(sensor, clamp, &mut out.counts);
                continue;
            };
            if let Some(e) = scene.shape_emitter[si.shape as usize].filter(
                |&e| !matches!((caustics, chain), (Some(c), Some(1..)) if c.takes(e, ray.d)),
            ) {
                path.add_hit_emission(scene, e, si, ray.d, wl, show);
            }
            if lane.depth >= max_depth {
                lane.finish::<SQ>(sensor, clamp, &mut out.counts);
                continue;
            }
            let dim = CAMERA_DIMS + (lane.depth - 1).min(1 << 20) * BOUNCE_DIMS;
            lane.sampler.set_dimension(dim);
            let material = &scene.materials[scene.shape_material[si.shape as usize] as usize];
            material.fill_bsdf(si, si.frame.to_local(-ray.d), wl, &mut lane.bsdf);
            lane.glossy = caustics.is_some_and(|c| lane.bsdf.glossy(c.max_roughness()));
            scatter.push(i, matches!(lane.bsdf, Bsdf::Mixture(_)));
        }

        // Scatter: one pass per kind of BSDF, each over the lanes holding that kind.
        for kind in 0..2 {
            for &i in scatter.list(kind) {
                let (lane, Some(si)) = (&mut lanes[i as usize], &hits[i as usize]) else {
                    continue;
                };
                let (ray, path, wl, sampler) =
                    (&mut lane.ray, &mut lane.path, &lane.wl, &mut lane.sampler);
                // A glossy vertex continuing the chain leaves its emitter samples of the light
                // tracer's sources to it.
                let skip = match lane.chain {
                    Some(_) if lane.glossy && lane.depth >= 2 => caustics,
                    _ => None,
                };
                // The list's kind: this match takes the same arm all through a list.
                let goes_on = match &lane.bsdf {
                    Bsdf::Diffuse(d) => path.scatter::<false>(d, si, ray, scene, wl, sampler, skip),
                    Bsdf::Mixture(m) => path.scatter::<false>(m, si, ray, scene, wl, sampler, skip),
                };
                if !goes_on {
                    lane.finish::<SQ>(sensor, clamp, &mut out.counts);
                } else if caustics.is_some() {
                    lane.chain = match (lane.depth, lane.chain) {
                        (1, _) if !path.prev_delta && !lane.glossy => Some(0),
                        (2.., Some(k)) if path.prev_delta || lane.glossy => Some(k + 1),
                        _ => None,
                    };
                }
            }
        }

        // Russian roulette, then the next bounce, for the lanes that scattered and go on.
        for kind in 0..2 {
            for &i in scatter.list(kind) {
                let lane = &mut lanes[i as usize];
                if !lane.busy {
                    continue;
                }
                if lane.depth >= settings.path.rr_depth {
                    let path = &mut lane.path;
                    let q = (path.beta.max_value() * path.lane_w * path.eta * path.eta).min(0.95);
                    if lane.sampler.next_1d() >= q {
                        lane.finish::<SQ>(sensor, clamp, &mut out.counts);
                        continue;
                    }
                    lane.path.beta /= q;
                }
                lane.depth += 1;
            }
        }
    }
}

/// The lanes that scatter at this bounce, listed by kind of BSDF (0: diffuse, 1: mixture), in
/// lane order. Each pass then runs over its own lanes, where a pass over all of them took a
/// branch on the kind at every lane, mispredicted where the kinds mix; lanes are independent,
/// so the order of the passes changes no bit. Filled without a branch on the kind.
struct Scatter<const W: usize> {
    lanes: [[u8; W]; 2],
    len: [usize; 2],
}

impl<const W: usize> Default for Scatter<W> {
    fn default() -> Self {
        Scatter {
            lanes: [[0; W]; 2],
            len: [0; 2],
        }
    }
}

impl<const W: usize> Scatter<W> {
    #[inline(always)]
    fn push(&mut self, lane: usize, mixture: bool) {
        let k = mixture as usize;
        self.lanes[k][self.len[k]] = lane as u8;
        self.len[k] += 1;
    }

    /// The lanes of kind `k`.
    #[inline(always)]
    fn list(&self, k: usize) -> &[u8] {
        &self.lanes[k][..self.len[k]]
    }
}
