//! Intel Embree 3 as a backend (cargo feature `embree`): triangles go into one Embree triangle
//! geometry, spheres and disks into one user geometry whose callbacks call prism's own
//! intersection code.
//!
//! What a hit means is kept identical to the other backends:
//! - Embree's own triangle test finds candidates; an intersection filter then re-runs prism's
//!   watertight test on each candidate, rejects those prism rejects (in particular hits within
//!   t's rounding-error bound, which would otherwise bring back self-shadowing on rotated
//!   planes) and replaces Embree's t and (u, v) with prism's. (u, v) are the barycentrics of
//!   vertices 1 and 2 in both conventions.
//! - Rays cover [0, t_max] in Embree against (0, t_max) in prism. A hit at exactly t = 0 cannot
//!   survive the filter (prism rejects it) and one at exactly t_max is a measure-zero event; the
//!   scene's ray offsets keep both away in practice.
//! - The scene is built with `ROBUST` so Embree avoids the traversal shortcuts that can lose
//!   hits on shared edges: prism's meshes must stay watertight.

use super::{Hit, Prim};
use crate::ray::Ray;
use crate::shape::{triangle, PrimGeom, PrimHit};
use embree3::{
    BufferUsage, Device, Format, GeometryKind, HitN, IntersectContext, IntersectFunctionNArgs,
    OccludedFunctionNArgs, RayHit, RayN, Scene, SceneFlags, SoAHit, SoARay, ValidityN, INVALID_ID,
};
use std::sync::Arc;

pub struct Embree {
    scene: Scene<'static>,
    /// Triangles first (Embree's primitive i of the triangle geometry is `geoms[i]`), then the
    /// analytic shapes (primitive j of the user geometry is `geoms[n_tris + j]`). Shared with the
    /// callbacks.
    geoms: Arc<Vec<PrimGeom>>,
    /// Scene-wide id of each entry of `geoms`.
    ids: Vec<u32>,
    n_tris: u32,
    tri_geom: u32,
    user_geom: u32,
}

impl Embree {
    pub fn build(prims: Vec<Prim>) -> Self {
        Self::build_with(prims, true)
    }

    /// `exact` false leaves out the filter that applies prism's triangle test, so hits come
    /// from Embree's own arithmetic (t and barycentrics may differ in the last bits, and near
    /// hits are not rejected). Renders never use that; benches/traversal.rs does, to show
    /// what the filter costs.
    pub fn build_with(prims: Vec<Prim>, exact: bool) -> Self {
        let (tris, analytic): (Vec<Prim>, Vec<Prim>) = prims
            .into_iter()
            .partition(|p| matches!(p.geom, PrimGeom::Triangle(_)));
        let n_tris = tris.len() as u32;
        let ids = tris.iter().chain(&analytic).map(|p| p.id).collect();
        let geoms: Arc<Vec<PrimGeom>> =
            Arc::new(tris.iter().chain(&analytic).map(|p| p.geom).collect());

        let device = Device::new().expect("cannot create the Embree device");
        let mut scene = device
            .create_scene()
            .expect("cannot create an Embree scene");
        scene.set_flags(SceneFlags::ROBUST);
        let mut tri_geom = INVALID_ID;
        let mut user_geom = INVALID_ID;
        if n_tris > 0 {
            let g = triangle_geometry(&device, &geoms[..n_tris as usize], geoms.clone(), exact);
            tri_geom = scene.attach_geometry(&g);
        }
        if !analytic.is_empty() {
            let g = user_geometry(&device, n_tris, analytic.len() as u32, geoms.clone());
            user_geom = scene.attach_geometry(&g);
        }
        scene.commit();
        Self {
            scene,
            geoms,
            ids,
            n_tris,
            tri_geom,
            user_geom,
        }
    }

    pub fn prims(&self) -> &[PrimGeom] {
        &self.geoms
    }

    /// Index into `geoms` of Embree's (geometry, primitive) pair.
    #[inline]
    fn index(&self, geom_id: u32, prim_id: u32) -> usize {
        if geom_id == self.tri_geom {
            prim_id as usize
        } else {
            debug_assert_eq!(geom_id, self.user_geom);
            (self.n_tris + prim_id) as usize
        }
    }

    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        let mut rh = RayHit::from(embree_ray(ray));
        // Incoherent: prism traces one path vertex at a time, in no particular order.
        let mut ctx = IntersectContext::incoherent();
        self.scene.intersect(&mut ctx, &mut rh);
        if rh.hit.geomID == INVALID_ID {
            return None;
        }
        Some(Hit {
            prim: self.ids[self.index(rh.hit.geomID, rh.hit.primID)],
            hit: PrimHit {
                t: rh.ray.tfar,
                b1: rh.hit.u,
                b2: rh.hit.v,
            },
        })
    }

    #[inline]
    pub fn occluded(&self, ray: &Ray) -> bool {
        let mut r = embree_ray(ray);
        let mut ctx = IntersectContext::incoherent();
        self.scene.occluded(&mut ctx, &mut r)
    }
}

#[inline]
fn embree_ray(ray: &Ray) -> embree3::Ray {
    embree3::Ray::segment(ray.o.into(), ray.d.into(), 0.0, ray.t_max)
}

/// prism's ray for lane `i` of an Embree packet, with Embree's current `tfar` as its t_max.
#[inline]
fn prism_ray<R: SoARay>(rays: &R, i: usize) -> Ray {
    Ray {
        o: rays.org(i).into(),
        d: rays.dir(i).into(),
        t_max: rays.tfar(i),
        time: 0.0,
    }
}

/// The triangle geometry: an unshared vertex buffer (three vertices per triangle, as prism's
/// `PrimGeom` stores them), and the filters that apply prism's triangle test to each candidate.
fn triangle_geometry(
    device: &Device,
    tris: &[PrimGeom],
    geoms: Arc<Vec<PrimGeom>>,
    exact: bool,
) -> embree3::Geometry<'static> {
    let n = tris.len();
    let mut g = device
        .create_geometry(GeometryKind::TRIANGLE)
        .expect("cannot create an Embree triangle geometry");
    {
        let mut verts = g
            .set_new_buffer::<[f32; 3]>(BufferUsage::VERTEX, 0, Format::FLOAT3, 12, 3 * n)
            .expect("cannot allocate Embree's vertex buffer");
        for (k, p) in tris.iter().enumerate() {
            let PrimGeom::Triangle(v) = p else {
                unreachable!("only triangles are passed here")
            };
            for j in 0..3 {
                verts[3 * k + j] = v[j].into();
            }
        }
    }
    {
        let mut idx = g
            .set_new_buffer::<[u32; 3]>(BufferUsage::INDEX, 0, Format::UINT3, 12, n)
            .expect("cannot allocate Embree's index buffer");
        for (k, t) in idx.iter_mut().enumerate() {
            let b = 3 * k as u32;
            *t = [b, b + 1, b + 2];
        }
    }
    if !exact {
        return g.commit();
    }
    g.set_intersect_filter_function_owned(
        |rays: RayN<'_>, mut hits: HitN<'_>, mut valid: ValidityN<'_>, _, data| {
            let geoms: &Arc<Vec<PrimGeom>> = data.expect("filter data is set");
            let mut rays = rays;
            for i in 0..valid.len() {
                if valid[i] == 0 {
                    continue;
                }
                match prism_triangle_hit(geoms, &rays, &hits, i) {
                    Some(h) => {
                        rays.set_tfar(i, h.t);
                        hits.set_uv(i, [h.b1, h.b2]);
                    }
                    None => valid[i] = 0,
                }
            }
        },
        geoms.clone(),
    );
    g.set_occluded_filter_function_owned(
        |rays: RayN<'_>, hits: HitN<'_>, mut valid: ValidityN<'_>, _, data| {
            let geoms: &Arc<Vec<PrimGeom>> = data.expect("filter data is set");
            for i in 0..valid.len() {
                if valid[i] != 0 && prism_triangle_hit(geoms, &rays, &hits, i).is_none() {
                    valid[i] = 0;
                }
            }
        },
        geoms,
    );
    g.commit()
}

/// prism's own test of the triangle Embree reports for lane `i`. The ray's `tfar` holds Embree's
/// candidate distance, so the test gets no upper bound beyond that of the floats: only whether
/// prism also sees a hit, and where, matters here.
#[inline]
fn prism_triangle_hit(
    geoms: &[PrimGeom],
    rays: &RayN<'_>,
    hits: &HitN<'_>,
    i: usize,
) -> Option<PrimHit> {
    let PrimGeom::Triangle(v) = &geoms[hits.prim_id(i) as usize] else {
        return None;
    };
    let ray = prism_ray(rays, i);
    triangle::intersect(&triangle::RayShear::new(&ray), f32::INFINITY, v).map(|h| PrimHit {
        t: h.t,
        b1: h.b1,
        b2: h.b2,
    })
}

/// Spheres and disks as one Embree user geometry of `count` primitives (`geoms[first + j]`).
fn user_geometry(
    device: &Device,
    first: u32,
    count: u32,
    geoms: Arc<Vec<PrimGeom>>,
) -> embree3::Geometry<'static> {
    let mut g = device
        .create_geometry(GeometryKind::USER)
        .expect("cannot create an Embree user geometry");
    g.set_user_primitive_count(count);
    let bounds_data = geoms.clone();
    g.set_bounds_function_owned(
        move |b: &mut embree3::Bounds, prim: u32, _time: u32, _: Option<&()>| {
            let (lo, hi) = bounds_data[(first + prim) as usize].bounds();
            (b.lower_x, b.lower_y, b.lower_z) = (lo.x, lo.y, lo.z);
            (b.upper_x, b.upper_y, b.upper_z) = (hi.x, hi.y, hi.z);
        },
        (),
    );
    let isect_data = geoms.clone();
    g.set_intersect_function_owned(
        move |args: &mut IntersectFunctionNArgs<'_, ()>| {
            let geom = &isect_data[(first + args.prim_id()) as usize];
            for i in 0..args.len() {
                if args.valid_n()[i] == 0 {
                    continue;
                }
                let mut r = args.ray(i);
                let ray = Ray {
                    o: r.org().into(),
                    d: r.dir().into(),
                    t_max: r.tfar,
                    time: 0.0,
                };
                if let Some(h) = geom.intersect_analytic(&ray, r.tfar) {
                    r.tfar = h.t;
                    let hit = embree3::Hit {
                        Ng_x: 0.0,
                        Ng_y: 0.0,
                        Ng_z: 0.0,
                        u: h.b1,
                        v: h.b2,
                        primID: args.prim_id(),
                        geomID: args.geom_id(),
                        instID: [INVALID_ID],
                    };
                    args.commit_hit(i, &r, &hit);
                }
            }
        },
        (),
    );
    g.set_occluded_function_owned(
        move |args: &mut OccludedFunctionNArgs<'_, ()>| {
            let geom = &geoms[(first + args.prim_id()) as usize];
            for i in 0..args.len() {
                if args.valid_n()[i] == 0 {
                    continue;
                }
                let r = args.ray(i);
                let ray = Ray {
                    o: r.org().into(),
                    d: r.dir().into(),
                    t_max: r.tfar,
                    time: 0.0,
                };
                if geom.intersect_analytic(&ray, r.tfar).is_some() {
                    args.set_occluded(i);
                }
            }
        },
        (),
    );
    g.commit()
}
