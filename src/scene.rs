//! The render-ready scene: world-space shapes with their materials and emitters, the camera,
//! and the acceleration structure. `load` builds it from a config; the integrator only
//! reads it.

use crate::accel::{Accel, AccelKind, Prim};
use crate::bsdf::Material;
use crate::camera::Camera;
use crate::emitter::Emitter;
use crate::interaction::SurfaceInteraction;
use crate::ray::Ray;
use crate::shape::Shape;
use glam::Vec2;

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
        let mut prim_shape = Vec::new();
        let mut shape_first_prim = Vec::with_capacity(shapes.len());
        let mut prims = Vec::new();
        let mut instanced = Vec::new();
        for (si, shape) in shapes.iter().enumerate() {
            shape_first_prim.push(prim_shape.len() as u32);
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
        let instanced_prims = instanced.iter().map(|(_, i)| i.mesh.indices.len()).sum();
        drop(instanced);
        Scene {
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
        let (shape, local, h) = match &self.instances {
            None => self.flat_hit(self.accel.intersect(ray)?),
            Some(inst) => self.intersect_two_level(inst, ray)?,
        };
        let s = self.shapes[shape as usize].surface(local as usize, ray, &h.hit);
        Some(SurfaceInteraction {
            p: s.p,
            p_error: s.p_error,
            ng: s.ng,
            frame: s.frame,
            uv: s.uv,
            t: h.hit.t,
            shape,
            prim: local,
            bary: Vec2::new(h.hit.b1, h.hit.b2),
        })
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
        match &self.instances {
            None => self.accel.occluded(ray),
            Some(inst) => self.occluded_two_level(inst, ray),
        }
    }

    #[inline(never)]
    fn occluded_two_level(&self, inst: &crate::accel::instances::Instances, ray: &Ray) -> bool {
        self.accel.occluded(ray) || inst.occluded(ray)
    }

    /// Scene bounds (min, max).
    pub fn bounds(&self) -> (glam::Vec3, glam::Vec3) {
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
