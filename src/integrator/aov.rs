//! The AOV pass: one ray per pixel centre for the geometry and id layers, and, for `alpha`,
//! the colour pass's own camera rays again (same sampler dimensions, so the same rays). The
//! colour pass is the same code with or without it; the pixel-centre rays are traced only when a
//! layer needs them or the scene asks for the sidecar's boxes (`boxes: true`, `--boxes`), so a
//! render without AOVs traces nothing more than its colour pass. Conventions in `film::aov`.
//! `pipeline::add_layers` runs the pass for a loaded job (the integrator knows no job).

use super::RenderSettings;
use crate::camera::Camera;
use crate::film::{Aov, Channel, UintChannel};
use crate::sampler::PixelSampler;
use crate::scene::Scene;
use glam::{DVec3, Vec2, Vec3};
use rayon::prelude::*;

/// Whether `aov` is made from the pixel-centre hits (`alpha`, `stderr` and `spp` are not).
pub fn uses_hits(aov: Aov) -> bool {
    !matches!(aov, Aov::Alpha | Aov::Stderr | Aov::Spp)
}

/// The surface a pixel-centre ray meets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub p: Vec3,
    pub ng: Vec3,
    pub ns: Vec3,
    pub uv: Vec2,
    pub shape: u32,
    /// Where textures are read (uv, and the triangle for vertex colours).
    pub tex: crate::texture::TexPoint,
    /// The camera ray meets the side the shading normal points to (`twosided`'s front).
    pub front: bool,
}

/// The first hit of the ray through each pixel centre, row-major.
pub fn first_hits(scene: &Scene, width: u32, height: u32) -> Vec<Option<Hit>> {
    (0..width as usize * height as usize)
        .into_par_iter()
        .with_min_len(256)
        .map(|i| {
            let (x, y) = ((i % width as usize) as f32, (i / width as usize) as f32);
            // At the frame's time (the shutter's opening), where the camera stands.
            let ray = crate::ray::Ray {
                time: scene.frame_time(),
                ..scene.camera.center_ray(Vec2::new(x + 0.5, y + 0.5))
            };
            scene.intersect(&ray).map(|si| Hit {
                p: si.p,
                ng: si.ng,
                ns: si.frame.n,
                uv: si.uv,
                shape: si.shape,
                tex: (&si).into(),
                front: ray.d.dot(si.frame.n) < 0.0,
            })
        })
        .collect()
}

/// Fraction of each pixel's camera samples that hit a surface (the colour pass's rays: the
/// first `counts[pixel]` of its stream, or `settings.spp` without counts).
pub fn coverage(scene: &Scene, settings: &RenderSettings, counts: Option<&[u32]>) -> Vec<f32> {
    let (w, h) = (settings.width, settings.height);
    (0..w as usize * h as usize)
        .into_par_iter()
        .with_min_len(16)
        .map(|i| {
            let pixel = i as u64;
            let (x, y) = ((pixel % w as u64) as f32, (pixel / w as u64) as f32);
            let mut sampler = PixelSampler::new(settings.sampler, settings.seed, pixel);
            let mut hits = 0u32;
            let n = counts.map_or(settings.spp, |c| c[i]);
            for s in 0..n {
                sampler.start(s);
                let offset = settings.filter.sample(sampler.next_2d());
                let film = Vec2::new(x + 0.5, y + 0.5) + offset;
                let ray = scene.camera_ray(film, y as u32, &mut sampler);
                hits += scene.intersect(&ray).is_some() as u32;
            }
            (hits as f64 / n as f64) as f32
        })
        .collect()
}

/// Distance from the camera centre and depth along its axis (OpenCV's z) of world point `p`.
fn distance_depth(camera: &Camera, r: &glam::DMat3, t: DVec3, p: Vec3) -> (f32, f32) {
    let q = *r * p.as_dvec3() + t;
    let dist = match camera {
        Camera::Orthographic(_) => q.z,
        _ => q.length(),
    };
    (dist as f32, q.z as f32)
}

/// The layers `aovs` asks for, from the pixel-centre hits (`label_ids`, `instance_ids`: each
/// shape's; material ids from the scene; `counts`: each pixel's sample count, as `coverage`
/// takes it). Float layers first, then the id layers.
pub fn layers(
    scene: &Scene,
    settings: &RenderSettings,
    hits: &[Option<Hit>],
    aovs: &[Aov],
    label_ids: &[u32],
    instance_ids: &[u32],
    counts: Option<&[u32]>,
) -> (Vec<Channel>, Vec<UintChannel>) {
    let (r, t) = scene.camera.world_to_opencv();
    let rf = r.as_mat3();
    let mut floats = Vec::new();
    let mut ids = Vec::new();
    let push = |floats: &mut Vec<Channel>, aov: Aov, f: &dyn Fn(&Option<Hit>) -> [f32; 3]| {
        for (c, ch) in aov.channels().iter().enumerate() {
            floats.push(Channel {
                name: format!("{}.{ch}", aov.name()),
                data: hits.iter().map(|h| f(h)[c]).collect(),
            });
        }
    };
    let inf = f32::INFINITY;
    for &aov in aovs {
        match aov {
            Aov::Distance => push(&mut floats, aov, &|h| {
                h.map_or([inf; 3], |h| {
                    [distance_depth(&scene.camera, &r, t, h.p).0; 3]
                })
            }),
            Aov::Depth => push(&mut floats, aov, &|h| {
                h.map_or([inf; 3], |h| {
                    [distance_depth(&scene.camera, &r, t, h.p).1; 3]
                })
            }),
            Aov::Position => push(&mut floats, aov, &|h| {
                h.map_or([0.0; 3], |h| h.p.to_array())
            }),
            Aov::Normal => push(&mut floats, aov, &|h| {
                h.map_or([0.0; 3], |h| h.ns.to_array())
            }),
            Aov::GeoNormal => push(&mut floats, aov, &|h| {
                h.map_or([0.0; 3], |h| h.ng.to_array())
            }),
            Aov::NormalCamera => push(&mut floats, aov, &|h| {
                h.map_or([0.0; 3], |h| (rf * h.ns).normalize().to_array())
            }),
            Aov::GeoNormalCamera => push(&mut floats, aov, &|h| {
                h.map_or([0.0; 3], |h| (rf * h.ng).normalize().to_array())
            }),
            Aov::Uv => push(&mut floats, aov, &|h| {
                h.map_or([0.0; 3], |h| [h.uv.x, h.uv.y, 0.0])
            }),
            // `add_layers` (flow: `integrator::flow`)
            Aov::Stderr
            | Aov::Albedo
            | Aov::Flow(_)
            | Aov::FlowOcclusion(_)
            | Aov::SceneFlow(_)
            | Aov::SceneFlowCamera(_) => {}
            Aov::Alpha => floats.push(Channel {
                name: "alpha.A".into(),
                data: coverage(scene, settings, counts),
            }),
            Aov::Spp => ids.push(UintChannel {
                name: "spp.N".into(),
                data: match counts {
                    Some(c) => c.to_vec(),
                    None => vec![settings.spp; (settings.width * settings.height) as usize],
                },
            }),
            Aov::Instance | Aov::Label | Aov::Material => {
                let id = |h: &Option<Hit>| {
                    h.map_or(0, |h| match aov {
                        Aov::Instance => instance_ids[h.shape as usize],
                        Aov::Label => label_ids[h.shape as usize],
                        _ => scene.shape_material[h.shape as usize] + 1,
                    })
                };
                ids.push(UintChannel {
                    name: format!("{}.ID", aov.name()),
                    data: hits.iter().map(id).collect(),
                });
            }
        }
    }
    (floats, ids)
}
