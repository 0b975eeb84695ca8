//! The BSDFs at hits on numpy arrays (`scene.bsdf_eval / bsdf_pdf / bsdf_sample`): each hit's
//! material at its N wavelengths, seen from the ray that found it (wi = −d). Values include
//! the cosine factor, as the renderer's: f · |cos θ_o|.

use crate::arrays::{self, with_lanes};
use crate::load::Scene;
use crate::parts::{Hit, Hits};
use glam::Vec3;
use numpy::{AllowTypeChange, PyArrayLike1, PyArrayLike2, PyUntypedArrayMethods};
use prism_core::bsdf::{Bsdf, BsdfLike};
use prism_core::scene::Scene as Built;
use prism_core::spectrum::Wavelengths;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// Runs `f` on the BSDF at hit `h` (None for a miss), with wi and a local frame.
fn at<const N: usize, T>(
    sc: &Built,
    h: &Hit,
    wl: &Wavelengths<N>,
    f: impl FnOnce(&Bsdf<'_, N>, Vec3, &prism_core::math::Frame) -> T,
) -> Option<T> {
    let si = h.si.as_ref()?;
    let wi = si.frame.to_local(-h.d);
    let mut bsdf = Bsdf::default();
    sc.materials[sc.shape_material[si.shape as usize] as usize].fill_bsdf(si, wi, wl, &mut bsdf);
    Some(f(&bsdf, wi, &si.frame))
}

/// The (M, N) wavelengths of `hits`, checked.
fn lanes(
    hits: &Hits,
    wavelengths: &PyArrayLike2<'_, f32, AllowTypeChange>,
) -> PyResult<(usize, Vec<f32>)> {
    let n = wavelengths.shape()[1];
    let lambda = arrays::nm(arrays::rows(wavelengths, n, "wavelengths")?, "wavelengths")?;
    arrays::same_len(lambda.len() / n.max(1), hits.hits.len(), "wavelengths")?;
    Ok((n, lambda))
}

#[pymethods]
impl Scene {
    /// f(wi, wo) · |cos θ_o| (M, N) at `hits` for outgoing world directions `wo` (M, 3).
    fn bsdf_eval<'py>(
        &self,
        py: Python<'py>,
        hits: &Hits,
        wo: PyArrayLike2<'py, f32, AllowTypeChange>,
        wavelengths: PyArrayLike2<'py, f32, AllowTypeChange>,
    ) -> PyResult<Bound<'py, PyAny>> {
        hits.of(self)?;
        let wo = arrays::vec3s(&wo, "wo")?;
        arrays::same_len(wo.len(), hits.hits.len(), "wo")?;
        let (n, lambda) = lanes(hits, &wavelengths)?;
        let st = self.read();
        let sc = &st.job.scene;
        let f = with_lanes!(n, N => py.detach(|| {
            let wl = arrays::wavelengths::<N>(&lambda);
            let mut out = vec![0f32; wo.len() * N];
            for (i, h) in hits.hits.iter().enumerate() {
                if let Some(f) = at(sc, h, &wl[i], |b, wi, fr| b.eval(wi, fr.to_local(wo[i]))) {
                    out[i * N..(i + 1) * N].copy_from_slice(&std::array::from_fn::<f32, N, _>(|j| f[j]));
                }
            }
            out
        }));
        arrays::out(py, f, n)
    }

    /// The solid-angle density (M,) with which `bsdf_sample` at `hits` (its hero wavelength,
    /// the first) picks world direction `wo` (M, 3).
    fn bsdf_pdf<'py>(
        &self,
        py: Python<'py>,
        hits: &Hits,
        wo: PyArrayLike2<'py, f32, AllowTypeChange>,
        wavelengths: PyArrayLike2<'py, f32, AllowTypeChange>,
    ) -> PyResult<Bound<'py, PyAny>> {
        hits.of(self)?;
        let wo = arrays::vec3s(&wo, "wo")?;
        arrays::same_len(wo.len(), hits.hits.len(), "wo")?;
        let (n, lambda) = lanes(hits, &wavelengths)?;
        let st = self.read();
        let sc = &st.job.scene;
        let pdf: Vec<f32> = with_lanes!(n, N => py.detach(|| {
            let wl = arrays::wavelengths::<N>(&lambda);
            hits.hits
                .iter()
                .enumerate()
                .map(|(i, h)| at(sc, h, &wl[i], |b, wi, fr| b.pdf(wi, fr.to_local(wo[i]))).unwrap_or(0.0))
                .collect()
        }));
        arrays::out(py, pdf, 0)
    }

    /// Samples a direction at each hit with `u_lobe` (M,) and `u_dir` (M, 2). Returns a dict:
    /// `wo` (M, 3) world direction, `pdf` (M,), `weight` (M, N) = f · |cos| / pdf (the
    /// throughput's factor), `delta` (M,) (a specular lobe, whose direction emitter sampling
    /// cannot find), `eta` (M,) (relative IOR crossed, 1 for reflection) and `valid` (M,).
    fn bsdf_sample<'py>(
        &self,
        py: Python<'py>,
        hits: &Hits,
        u_lobe: PyArrayLike1<'py, f32, AllowTypeChange>,
        u_dir: PyArrayLike2<'py, f32, AllowTypeChange>,
        wavelengths: PyArrayLike2<'py, f32, AllowTypeChange>,
    ) -> PyResult<Bound<'py, PyDict>> {
        hits.of(self)?;
        let m = hits.hits.len();
        let ul = arrays::unit(arrays::floats(&u_lobe), "u_lobe")?;
        let ud = arrays::unit2(arrays::vec2s(&u_dir, "u_dir")?, "u_dir")?;
        arrays::same_len(ul.len(), m, "u_lobe")?;
        arrays::same_len(ud.len(), m, "u_dir")?;
        let (n, lambda) = lanes(hits, &wavelengths)?;
        let st = self.read();
        let sc = &st.job.scene;
        let (wo, pdf, weight, delta, eta, valid) = with_lanes!(n, N => py.detach(|| {
            let wl = arrays::wavelengths::<N>(&lambda);
            let mut o = (vec![Vec3::ZERO; m], vec![0f32; m], vec![0f32; m * N], vec![false; m], vec![1f32; m], vec![false; m]);
            for (i, h) in hits.hits.iter().enumerate() {
                let s = at(sc, h, &wl[i], |b, wi, fr| {
                    b.sample(wi, ul[i], ud[i]).map(|s| (s, fr.to_world(s.wo)))
                });
                let Some(Some((s, w))) = s else { continue };
                o.0[i] = w;
                o.1[i] = s.pdf;
                for j in 0..N {
                    o.2[i * N + j] = s.weight[j];
                }
                o.3[i] = s.delta;
                o.4[i] = s.eta;
                o.5[i] = true;
            }
            o
        }));
        let d = PyDict::new(py);
        d.set_item("wo", arrays::out3(py, &wo)?)?;
        d.set_item("pdf", arrays::out(py, pdf, 0)?)?;
        d.set_item("weight", arrays::out(py, weight, n)?)?;
        d.set_item("delta", arrays::out(py, delta, 0)?)?;
        d.set_item("eta", arrays::out(py, eta, 0)?)?;
        d.set_item("valid", arrays::out(py, valid, 0)?)?;
        Ok(d)
    }
}
