//! The render-ready scene: world-space shapes with their materials and emitters, the camera,
//! and the acceleration structure. `load` builds it from a config; the integrator only
//! reads it.

use crate::accel::{Accel, AccelKind, Prim};
use crate::bsdf::Material;
use crate::camera::Camera;
use crate::emitter::Emitter;
use crate::interaction::SurfaceInteraction;
use crate::math::Frame;
use crate::ray::Ray;
use crate::sampler::PixelSampler;
use crate::shape::{PrimHit, Shape, SurfacePoint};
use glam::Vec2;

/// What moves in a scene with an open shutter (`Scene::with_motion`).
#[derive(Default)]
pub struct Motions {
    /// Moving shapes: index into the scene's shapes (object space) and their motion.
    pub shapes: Vec<(u32, crate::motion::Motion)>,
    pub timing: Option<SceneTiming>,
}

/// The shutter's timing and the interval `span` that every row's exposure lies in.
pub struct SceneTiming {
    pub timing: crate::motion::Timing,
    pub span: (f32, f32),
}

pub struct Scene {
    pub camera: Camera,
    pub shapes: Vec<Shape>,
    /// Material of each shape (index into `materials`).
    pub shape_material: Vec<u32>,
    /// Emitter of each shape, if it is an area light (index into `emitters`).
    pub shape_emitter: Vec<Option<u32>>,
    pub materials: Vec<Material>,
    pub emitters: Vec<Emitter>,
    /// Indices of the emitters at infinity (looked up when a ray escapes).
    pub environment: Vec<u32>,
    /// Name of each shape, where its source names it (glTF: the node's name).
    pub shape_name: Vec<Option<String>>,
    accel: Accel,
    /// Shape of each scene-wide primitive id, and each shape's first id.
    prim_shape: Vec<u32>,
    shape_first_prim: Vec<u32>,
    /// The instanced meshes' two-level BVH (`accel::instances`); None in most scenes.
    instances: Option<crate::accel::instances::Instances>,
    /// Triangles of the instances, counted per instance (for `primitive_count`).
    instanced_prims: usize,
    /// Per shape: the shading frame of each triangle of a flat mesh (`Mesh::is_flat`), so a
    /// hit need not rebuild it (`flat_frames`); empty for other shapes.
    shape_frames: Vec<Box<[Frame]>>,
    /// Shapes moving while the shutter is open (`accel::moving`); None in static scenes.
    moving: Option<crate::accel::moving::Moving>,
    /// The shutter interval and the camera's motion; None when the scene is rendered at an
    /// instant (every static scene).
    pub timing: Option<Box<crate::motion::Timing>>,
}

impl Scene {
    /// Assembles a scene and builds its acceleration structure. Primitives with zero area or
    /// non-finite coordinates are left out of it (they could only produce NaNs).
    pub fn new(
        camera: Camera,
        shapes: Vec<Shape>,
        shape_material: Vec<u32>,
        shape_emitter: Vec<Option<u32>>,
        materials: Vec<Material>,
        emitters: Vec<Emitter>,
        accel: AccelKind,
    ) -> Scene {
        let (m, e) = (shape_material, shape_emitter);
        let none = Motions::default();
        Scene::with_motion(camera, shapes, m, e, materials, emitters, accel, none)
    }

    /// As `new`, with shapes that move while the shutter is open (`motions.shapes`: shape
    /// index and motion; those shapes are in object space) and the shutter's timing.
    #[allow(clippy::too_many_arguments)]
    pub fn with_motion(
        camera: Camera,
        shapes: Vec<Shape>,
        shape_material: Vec<u32>,
        shape_emitter: Vec<Option<u32>>,
        materials: Vec<Material>,
        emitters: Vec<Emitter>,
        accel: AccelKind,
        motions: Motions,
    ) -> Scene {
        let mut moving_at: Vec<Option<crate::motion::Motion>> = vec![None; shapes.len()];
        for (i, m) in motions.shapes {
            moving_at[i as usize] = Some(m);
        }
        let mut moving = Vec::new();
        let mut prim_shape = Vec::new();
        let mut shape_first_prim = Vec::with_capacity(shapes.len());
        let mut prims = Vec::new();
        let mut instanced = Vec::new();
        for (si, shape) in shapes.iter().enumerate() {
            shape_first_prim.push(prim_shape.len() as u32);
            if let Some(m) = moving_at[si].take() {
                moving.push((si as u32, shape, m));
                continue;
            }
            if let Shape::Instance(inst) = shape {
                instanced.push((si as u32, inst));
                continue;
            }
            for i in 0..shape.prim_count() {
                let id = prim_shape.len() as u32;
                prim_shape.push(si as u32);
                if !shape.prim_is_degenerate(i) {
                    prims.push(Prim {
                        id,
                        geom: shape.prim_geom(i),
                    });
                }
            }
        }
        let environment = emitters
            .iter()
            .enumerate()
            .filter(|(_, e)| e.is_environment())
            .map(|(i, _)| i as u32)
            .collect();
        let instances = crate::accel::instances::Instances::build(&instanced);
        let instanced_prims = instanced
            .iter()
            .map(|(_, i)| i.mesh.indices.len())
            .sum::<usize>()
            + moving.iter().map(|(_, s, _)| s.prim_count()).sum::<usize>();
        drop(instanced);
        let (t0, t1) = motions.timing.as_ref().map_or((0.0, 0.0), |t| t.span);
        let moving = crate::accel::moving::Moving::build(moving, t0, t1);
        Scene {
            shape_frames: flat_frames(&shapes),
            moving,
            timing: motions.timing.map(|t| Box::new(t.timing)),
            instances,
            instanced_prims,
            shape_name: vec![None; shapes.len()],
            camera,
            shapes,
            shape_material,
            shape_emitter,
            materials,
            emitters,
            environment,
            accel: Accel::build(prims, accel),
            prim_shape,
            shape_first_prim,
        }
    }

    /// The closest surface along `ray`.
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<SurfaceInteraction> {
        match &self.moving {
            None => self.intersect_static(ray),
            Some(m) => self.intersect_moving(m, ray),
        }
    }

    /// The closest static surface, then the moving shapes' up to it at the ray's time. Out of
    /// line, so static scenes carry none of it.
    #[inline(never)]
    fn intersect_moving(
        &self,
        m: &crate::accel::moving::Moving,
        ray: &Ray,
    ) -> Option<SurfaceInteraction> {
        let fixed = self.intersect_static(ray);
        let t_max = fixed.as_ref().map_or(ray.t_max, |si| si.t);
        let Some(h) = m.intersect(ray, t_max, &self.shapes) else {
            return fixed;
        };
        let s = h.surface;
        Some(SurfaceInteraction {
            p: s.p,
            p_error: s.p_error,
            ng: s.ng,
            frame: s.frame,
            uv: s.uv,
            t: h.t,
            shape: h.shape,
            prim: h.prim,
            time: ray.time,
            bary: h.bary,
        })
    }

    /// The closest surface of the shapes that do not move.
    #[inline(always)]
    fn intersect_static(&self, ray: &Ray) -> Option<SurfaceInteraction> {
        let (shape, local, h) = match &self.instances {
            None => self.flat_hit(self.accel.intersect(ray)?),
            Some(inst) => self.intersect_two_level(inst, ray)?,
        };
        let s = self.surface(shape, local, ray, &h.hit);
        Some(SurfaceInteraction {
            p: s.p,
            p_error: s.p_error,
            ng: s.ng,
            frame: s.frame,
            uv: s.uv,
            t: h.hit.t,
            shape,
            prim: local,
            time: ray.time,
            bary: Vec2::new(h.hit.b1, h.hit.b2),
        })
    }

    /// Surface data at a hit of primitive `prim` of shape `shape`: `Shape::surface`, with a flat
    /// mesh's kept frame where it has one (the same bits).
    #[inline(always)]
    fn surface(&self, shape: u32, prim: u32, ray: &Ray, hit: &PrimHit) -> SurfacePoint {
        let sh = &self.shapes[shape as usize];
        let frames = &self.shape_frames[shape as usize];
        if let (Shape::Mesh(m), Some(f)) = (sh, frames.get(prim as usize)) {
            let s = m.flat_surface(prim as usize, hit.b1, hit.b2, f);
            return SurfacePoint {
                p: s.p,
                p_error: s.p_error,
                ng: s.ng,
                frame: s.frame,
                uv: s.uv,
            };
        }
        sh.surface(prim as usize, ray, hit)
    }

    /// The closest hit of a scene with instances: the flat structure's, then the instances'
    /// up to it. Out of line, so scenes without instances carry none of it.
    #[inline(never)]
    fn intersect_two_level(
        &self,
        inst: &crate::accel::instances::Instances,
        ray: &Ray,
    ) -> Option<(u32, u32, crate::accel::Hit)> {
        let flat = self.accel.intersect(ray);
        let mut r = *ray;
        if let Some(h) = &flat {
            r.t_max = h.hit.t;
        }
        match inst.intersect(&r) {
            Some((shape, h)) => Some((shape, h.prim, h)),
            None => flat.map(|h| self.flat_hit(h)),
        }
    }

    /// A flat structure's hit as (shape, its local primitive, hit).
    #[inline(always)]
    fn flat_hit(&self, h: crate::accel::Hit) -> (u32, u32, crate::accel::Hit) {
        let shape = self.prim_shape[h.prim as usize];
        (shape, h.prim - self.shape_first_prim[shape as usize], h)
    }

    /// True if something blocks `ray` before its `t_max`.
    #[inline(always)]
    pub fn occluded(&self, ray: &Ray) -> bool {
        let fixed = match &self.instances {
            None => self.accel.occluded(ray),
            Some(inst) => self.occluded_two_level(inst, ray),
        };
        fixed || self.moving.as_ref().is_some_and(|m| m.occluded(ray))
    }

    /// The time the scene's camera pose and the sidecar describe: the shutter's opening (0,
    /// or the instant, for a scene built at an instant).
    pub fn frame_time(&self) -> f32 {
        self.timing.as_ref().map_or(0.0, |t| t.shutter.open)
    }

    /// The motion of shape `shape` while the shutter is open (None: it stays still, or the
    /// scene was built at an instant).
    pub fn shape_motion(&self, shape: u32) -> Option<&crate::motion::Motion> {
        self.moving.as_ref()?.motion(shape)
    }

    /// The camera ray through `film` (pixel row `row`): at the instant the scene was built
    /// for, or with an open shutter at a time the sampler draws (`motion::Timing`).
    #[inline(always)]
    pub fn camera_ray(&self, film: glam::Vec2, row: u32, sampler: &mut PixelSampler) -> Ray {
        match &self.timing {
            None => self.camera.ray(film, sampler),
            Some(t) => t.camera_ray(&self.camera, film, row, sampler),
        }
    }

    #[inline(never)]
    fn occluded_two_level(&self, inst: &crate::accel::instances::Instances, ray: &Ray) -> bool {
        self.accel.occluded(ray) || inst.occluded(ray)
    }

    /// Scene bounds (min, max), moving shapes' over the shutter interval included.
    pub fn bounds(&self) -> (glam::Vec3, glam::Vec3) {
        let fixed = self.static_bounds();
        match &self.moving {
            None => fixed,
            Some(m) if self.prim_shape.is_empty() && self.instances.is_none() => m.bounds(),
            Some(m) => (fixed.0.min(m.bounds().0), fixed.1.max(m.bounds().1)),
        }
    }

    fn static_bounds(&self) -> (glam::Vec3, glam::Vec3) {
        match &self.instances {
            None => self.accel.bounds(),
            Some(inst) if self.prim_shape.is_empty() => inst.bounds(),
            Some(inst) => {
                let (a, b) = (self.accel.bounds(), inst.bounds());
                (a.0.min(b.0), a.1.max(b.1))
            }
        }
    }

    /// Number of primitives in the scene (instances' triangles counted per instance), before
    /// degenerate removal.
    pub fn primitive_count(&self) -> usize {
        self.prim_shape.len() + self.instanced_prims
    }

    /// Instances, unique instanced meshes and their triangles ((0, 0, 0) without instancing).
    pub fn instance_counts(&self) -> (usize, usize, u64) {
        self.instances.as_ref().map_or((0, 0, 0), |i| i.counts())
    }
}

/// Most triangles whose frames a scene keeps (`flat_frames`): 36 bytes each, 2.4 MB in all, a
/// table that stays in the caches; flat meshes beyond it rebuild their frames at each hit.
const FLAT_FRAMES_MAX: usize = 1 << 16;

/// The frames of the triangles of the flat meshes among `shapes` (`Scene::shape_frames`), in
/// shape order while their count stays within `FLAT_FRAMES_MAX`; empty for every other shape.
fn flat_frames(shapes: &[Shape]) -> Vec<Box<[Frame]>> {
    let mut left = FLAT_FRAMES_MAX;
    let frames = |s: &Shape| match s {
        Shape::Mesh(m) if m.is_flat() && m.indices.len() <= left => {
            left -= m.indices.len();
            (0..m.indices.len()).map(|i| m.flat_frame(i)).collect()
        }
        _ => Box::default(),
    };
    shapes.iter().map(frames).collect()
}
