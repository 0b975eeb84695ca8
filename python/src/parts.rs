//! The path tracer's parts on numpy arrays, one call for M rays with the GIL released, for
//! estimators written in Python (examples/python/): camera rays, intersection, and the
//! emitters (`bsdfs` has the BSDFs). Directions are world-space unit vectors; spectra are
//! (M, N) arrays at each ray's N wavelengths.

use crate::arrays::{self, with_lanes};
use crate::load::Scene;
use glam::{Vec2, Vec3};
use numpy::{AllowTypeChange, PyArrayLike1, PyArrayLike2, PyUntypedArrayMethods};
use prism_core::camera::Camera;
use prism_core::emitter::Emitter;
use prism_core::interaction::SurfaceInteraction;
use prism_core::ray::Ray;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// One ray's outcome: where it started (the previous vertex for a spawned ray), its direction
/// and its hit.
#[derive(Clone, Copy)]
pub struct Hit {
    pub o: Vec3,
    pub d: Vec3,
    pub si: Option<SurfaceInteraction>,
}

/// M rays' hits (`scene.intersect`): arrays of distances `t` (inf where missed), points `p`,
/// geometric normals `n`, shading normals `ns`, `uv`, and the `shape`, `material` and
/// `emitter` indices (−1: none), and `valid` (hit something).
#[pyclass(frozen, module = "prism")]
pub struct Hits {
    pub hits: Vec<Hit>,
    /// The scene that traced them (its address): another scene's shapes are not theirs.
    scene: usize,
    /// Material and emitter of each hit, as the scene was when it was traced.
    material: Vec<i32>,
    emitter: Vec<i32>,
}

impl Hits {
    fn new(scene: &Scene, job: &prism_core::load::Job, hits: Vec<Hit>) -> Hits {
        let sc = &job.scene;
        let of = |h: &Hit, f: &dyn Fn(usize) -> i32| h.si.map_or(-1, |s| f(s.shape as usize));
        Hits {
            material: hits
                .iter()
                .map(|h| of(h, &|s| sc.shape_material[s] as i32))
                .collect(),
            emitter: hits
                .iter()
                .map(|h| of(h, &|s| sc.shape_emitter[s].map_or(-1, |e| e as i32)))
                .collect(),
            hits,
            scene: scene as *const Scene as usize,
        }
    }

    /// Refuses hits that `scene` did not trace.
    pub fn of(&self, scene: &Scene) -> PyResult<&[Hit]> {
        if self.scene == scene as *const Scene as usize {
            Ok(&self.hits)
        } else {
            Err(crate::SceneError::new_err(
                "these hits were traced in another scene; pass them to the scene whose intersect made them",
            ))
        }
    }

    fn each<T: Copy>(&self, f: impl Fn(&SurfaceInteraction) -> T, none: T) -> Vec<T> {
        self.hits
            .iter()
            .map(|h| h.si.as_ref().map_or(none, &f))
            .collect()
    }
}

#[pymethods]
impl Hits {
    fn __len__(&self) -> usize {
        self.hits.len()
    }
    #[getter]
    fn valid<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        arrays::out(py, self.hits.iter().map(|h| h.si.is_some()).collect(), 0)
    }
    #[getter]
    fn t<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        arrays::out(py, self.each(|s| s.t, f32::INFINITY), 0)
    }
    #[getter]
    fn p<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        arrays::out3(py, &self.each(|s| s.p, Vec3::ZERO))
    }
    #[getter]
    fn n<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        arrays::out3(py, &self.each(|s| s.ng, Vec3::ZERO))
    }
    #[getter]
    fn ns<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        arrays::out3(py, &self.each(|s| s.frame.n, Vec3::ZERO))
    }
    #[getter]
    fn uv<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let v = self
            .hits
            .iter()
            .flat_map(|h| h.si.map_or(Vec2::ZERO, |s| s.uv).to_array())
            .collect();
        arrays::out(py, v, 2)
    }
    #[getter]
    fn shape<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        arrays::out(py, self.each(|s| s.shape as i32, -1), 0)
    }
    #[getter]
    fn material<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        arrays::out(py, self.material.clone(), 0)
    }
    #[getter]
    fn emitter<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        arrays::out(py, self.emitter.clone(), 0)
    }
    /// The rays' directions (unit).
    #[getter]
    fn d<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        arrays::out3(py, &self.hits.iter().map(|h| h.d).collect::<Vec<_>>())
    }
}

#[pymethods]
impl Scene {
    /// Camera rays through film positions: pixel (x, y) (M, 2) plus an offset drawn from the
    /// pixel filter with `u_film` (M, 2) in [0, 1)², through the lens at `u_lens` (M, 2) in
    /// [0, 1)² (a thin lens's point on its aperture, as the render draws it at the sampler's
    /// dimension `prism.LENS_DIM`; the other cameras have no lens and ignore it, and a thin
    /// lens without it is refused: its centre alone would show no depth of field). Returns
    /// (origins, directions), each (M, 3).
    #[pyo3(signature = (pixel, u_film, u_lens=None))]
    fn camera_rays<'py>(
        &self,
        py: Python<'py>,
        pixel: PyArrayLike2<'py, f32, AllowTypeChange>,
        u_film: PyArrayLike2<'py, f32, AllowTypeChange>,
        u_lens: Option<PyArrayLike2<'py, f32, AllowTypeChange>>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let px = arrays::vec2s(&pixel, "pixel")?;
        if let Some(p) = px.iter().find(|p| !p.is_finite()) {
            return Err(crate::SceneError::new_err(format!(
                "pixel holds {p}; film positions must be finite"
            )));
        }
        let u = arrays::unit2(arrays::vec2s(&u_film, "u_film")?, "u_film")?;
        arrays::same_len(u.len(), px.len(), "u_film")?;
        let lens = match &u_lens {
            Some(l) => Some(arrays::unit2(arrays::vec2s(l, "u_lens")?, "u_lens")?),
            None => None,
        };
        if let Some(l) = &lens {
            arrays::same_len(l.len(), px.len(), "u_lens")?;
        }
        let st = self.read();
        let job = &st.job;
        let cam = &job.scene.camera;
        if let (Camera::ThinLens(_), None) = (cam, &lens) {
            return Err(crate::SceneError::new_err(
                "this scene's camera is a thin lens, whose rays start anywhere on its aperture: \
                 pass u_lens, (M, 2) uniforms in [0, 1) (e.g. rng.random((M, 2)))",
            ));
        }
        let rays: Vec<Ray> = py.detach(|| {
            let f = &job.settings.filter;
            px.iter()
                .zip(&u)
                .enumerate()
                .map(|(i, (p, u))| {
                    let film = *p + Vec2::splat(0.5) + f.sample(*u);
                    match (cam, &lens) {
                        (Camera::ThinLens(t), Some(l)) => t.ray(film, l[i]),
                        _ => cam.center_ray(film),
                    }
                })
                .collect()
        });
        let o: Vec<Vec3> = rays.iter().map(|r| r.o).collect();
        let d: Vec<Vec3> = rays.iter().map(|r| r.d).collect();
        Ok((arrays::out3(py, &o)?, arrays::out3(py, &d)?))
    }

    /// The closest hits of rays from `o` along `d` (each (M, 3); `d` is normalised, and a zero
    /// or non-finite ray, or one from beyond the scenes' extent limit of 1e18, misses).
    fn intersect(
        &self,
        py: Python<'_>,
        o: PyArrayLike2<'_, f32, AllowTypeChange>,
        d: PyArrayLike2<'_, f32, AllowTypeChange>,
    ) -> PyResult<Hits> {
        let o = arrays::vec3s(&o, "o")?;
        let d = arrays::vec3s(&d, "d")?;
        arrays::same_len(d.len(), o.len(), "d")?;
        let st = self.read();
        let job = &st.job;
        Ok(py.detach(|| {
            let hits = o
                .iter()
                .zip(&d)
                .map(|(&o, &d)| {
                    let d = d.normalize_or_zero();
                    // Only rays a scene can hold reach the traversal: a NaN or a coordinate
                    // past the loader's extent limit would make NaN slab tests (issue 27).
                    let far = prism_core::load::extent::MAX_COORD;
                    let ok = d.is_finite()
                        && d != Vec3::ZERO
                        && o.is_finite()
                        && o.abs().max_element() <= far;
                    Hit {
                        o,
                        d,
                        si: ok.then(|| job.scene.intersect(&Ray::new(o, d))).flatten(),
                    }
                })
                .collect();
            Hits::new(self, job, hits)
        }))
    }

    /// The next hits of rays leaving `hits` in directions `d` (M, 3), started off the surface
    /// as the renderer starts them; a missed ray stays missed, and a zero direction misses.
    fn intersect_from(
        &self,
        py: Python<'_>,
        hits: &Hits,
        d: PyArrayLike2<'_, f32, AllowTypeChange>,
    ) -> PyResult<Hits> {
        hits.of(self)?;
        let d = arrays::vec3s(&d, "d")?;
        arrays::same_len(d.len(), hits.hits.len(), "d")?;
        let st = self.read();
        let job = &st.job;
        Ok(py.detach(|| {
            let next = hits
                .hits
                .iter()
                .zip(&d)
                .map(|(h, &d)| match &h.si {
                    None => Hit { si: None, ..*h },
                    Some(si) => {
                        let d = d.normalize_or_zero();
                        Hit {
                            o: si.p,
                            d,
                            si: (d != Vec3::ZERO)
                                .then(|| job.scene.intersect(&si.spawn(d)))
                                .flatten(),
                        }
                    }
                })
                .collect();
            Hits::new(self, job, next)
        }))
    }

    /// Emitter sampling at `hits`: an emitter chosen uniformly with `u_select` (M,), a point
    /// or direction on it with `u` (M, 2), radiance at `wavelengths` (M, N). Returns a dict:
    /// `wi` (M, 3) towards the light, `pdf` (M,) solid-angle density times the choice's
    /// probability, `radiance` (M, N) (0 where occluded or nothing was sampled), `delta` (M,)
    /// (a point or directional light, which BSDF sampling cannot hit) and `emitter` (M,).
    fn emitter_sample<'py>(
        &self,
        py: Python<'py>,
        hits: &Hits,
        u_select: PyArrayLike1<'py, f32, AllowTypeChange>,
        u: PyArrayLike2<'py, f32, AllowTypeChange>,
        wavelengths: PyArrayLike2<'py, f32, AllowTypeChange>,
    ) -> PyResult<Bound<'py, PyDict>> {
        hits.of(self)?;
        let m = hits.hits.len();
        let us = arrays::unit(arrays::floats(&u_select), "u_select")?;
        let u = arrays::unit2(arrays::vec2s(&u, "u")?, "u")?;
        arrays::same_len(us.len(), m, "u_select")?;
        arrays::same_len(u.len(), m, "u")?;
        let n = wavelengths.shape()[1];
        let lambda = arrays::nm(arrays::rows(&wavelengths, n, "wavelengths")?, "wavelengths")?;
        arrays::same_len(lambda.len() / n.max(1), m, "wavelengths")?;
        let st = self.read();
        let job = &st.job;
        let (wi, pdf, le, delta, which) = with_lanes!(n, N => py.detach(|| {
            let wl = arrays::wavelengths::<N>(&lambda);
            let sc = &job.scene;
            let k = sc.emitters.len();
            let mut out = (vec![Vec3::ZERO; m], vec![0f32; m], vec![0f32; m * N], vec![false; m], vec![-1i32; m]);
            for i in 0..m {
                let Some(si) = &hits.hits[i].si else { continue };
                if k == 0 {
                    continue;
                }
                let e = ((us[i] * k as f32) as usize).min(k - 1);
                out.4[i] = e as i32;
                let Some(s) = sc.emitters[e].sample_li(si, u[i], &wl[i], &sc.shapes) else { continue };
                out.0[i] = s.wi;
                out.1[i] = s.pdf / k as f32;
                out.3[i] = s.delta;
                if !sc.occluded(&s.shadow) {
                    for j in 0..N {
                        out.2[i * N + j] = s.radiance[j];
                    }
                }
            }
            out
        }));
        let d = PyDict::new(py);
        d.set_item("wi", arrays::out3(py, &wi)?)?;
        d.set_item("pdf", arrays::out(py, pdf, 0)?)?;
        d.set_item("radiance", arrays::out(py, le, n)?)?;
        d.set_item("delta", arrays::out(py, delta, 0)?)?;
        d.set_item("emitter", arrays::out(py, which, 0)?)?;
        Ok(d)
    }

    /// Radiance the rays of `hits` receive from what they hit: an area light's front side, or
    /// for a missed ray the environment (every emitter at infinity); (M, N) at `wavelengths`.
    fn emitter_eval<'py>(
        &self,
        py: Python<'py>,
        hits: &Hits,
        wavelengths: PyArrayLike2<'py, f32, AllowTypeChange>,
    ) -> PyResult<Bound<'py, PyAny>> {
        hits.of(self)?;
        let m = hits.hits.len();
        let n = wavelengths.shape()[1];
        let lambda = arrays::nm(arrays::rows(&wavelengths, n, "wavelengths")?, "wavelengths")?;
        arrays::same_len(lambda.len() / n.max(1), m, "wavelengths")?;
        let st = self.read();
        let job = &st.job;
        let le = with_lanes!(n, N => py.detach(|| {
            let wl = arrays::wavelengths::<N>(&lambda);
            let sc = &job.scene;
            let mut le = vec![0f32; m * N];
            for (i, h) in hits.hits.iter().enumerate() {
                let mut add = |s: prism_core::spectrum::Spectrum<N>| {
                    for j in 0..N {
                        le[i * N + j] += s[j];
                    }
                };
                match &h.si {
                    None => sc.environment.iter().for_each(|&e| add(sc.emitters[e as usize].le_env(h.d, &wl[i]))),
                    Some(si) => {
                        let e = sc.shape_emitter[si.shape as usize];
                        if let Some(Emitter::Area(a)) = e.map(|e| &sc.emitters[e as usize]) {
                            if si.ng.dot(-h.d) > 0.0 {
                                add(a.radiance.eval(si.uv, &wl[i]));
                            }
                        }
                    }
                }
            }
            le
        }));
        arrays::out(py, le, n)
    }

    /// The density (solid angle, times the emitter's choice probability) with which
    /// `emitter_sample` at each ray's origin would have sampled what the ray hit: an area
    /// light's point, or for a missed ray its direction on the environment; 0 otherwise. The
    /// MIS weight of a BSDF-sampled ray that lands on a light needs it.
    fn emitter_pdf<'py>(&self, py: Python<'py>, hits: &Hits) -> PyResult<Bound<'py, PyAny>> {
        hits.of(self)?;
        let st = self.read();
        let job = &st.job;
        let pdf: Vec<f32> = py.detach(|| {
            let sc = &job.scene;
            let k = sc.emitters.len().max(1) as f32;
            hits.hits
                .iter()
                .map(|h| match &h.si {
                    None => {
                        sc.environment
                            .iter()
                            .map(|&e| sc.emitters[e as usize].pdf_li_env(h.d))
                            .sum::<f32>()
                            / k
                    }
                    Some(si) => sc.shape_emitter[si.shape as usize].map_or(0.0, |e| {
                        sc.emitters[e as usize].pdf_li_hit(h.o, si, &sc.shapes) / k
                    }),
                })
                .collect()
        });
        arrays::out(py, pdf, 0)
    }
}
