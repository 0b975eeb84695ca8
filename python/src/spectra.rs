//! Wavelengths, spectra and random numbers for estimators written in Python:
//! `prism.sample_wavelengths`, `scene.sample_wavelengths`, `prism.spectrum`, `prism.cie_xyz`
//! and `prism.sampler_stream` (the numbers a render's sampler gives).

use crate::arrays::{self, with_lanes};
use crate::load::{to_json, Scene};
use crate::SceneError;
use numpy::{AllowTypeChange, PyArrayLike1, PyArrayMethods, PyUntypedArrayMethods};
use prism_core::config::SpectrumConfig;
use prism_core::load::spectrum::{Context, Role};
use prism_core::sampler::{PixelSampler, SamplerKind};
use prism_core::spectrum::{WavelengthSampler, WavelengthSampling};
use pyo3::prelude::*;
use std::path::Path;

/// An enum's value from its name (serde's), or a SceneError listing `choices`.
fn variant<T: serde::de::DeserializeOwned>(name: &str, what: &str, choices: &str) -> PyResult<T> {
    serde_json::from_value(serde_json::Value::String(name.into())).map_err(|_| {
        SceneError::new_err(format!("unknown {what} \"{name}\"; use one of {choices}"))
    })
}

/// Whether `(lo, hi)` nm is a range a scene may render: positive, increasing, at most
/// `load::MAX_NM` (the loader's `spectral.range` check).
fn valid_range((lo, hi): (f32, f32)) -> bool {
    lo.is_finite() && lo > 0.0 && lo < hi && hi <= prism_core::load::MAX_NM
}

/// Draws wavelengths for `u` (M,) as a render does: each row's hero at u and N − 1 companions
/// at u + j/N (mod 1). Returns (wavelengths, pdf), each (M, N), pdf in 1/nm.
fn sample(
    s: &WavelengthSampler,
    u: &[f32],
    n: usize,
    py: Python<'_>,
) -> PyResult<(Py<PyAny>, Py<PyAny>)> {
    let (l, p) = with_lanes!(n, N => py.detach(|| {
        let mut l = Vec::with_capacity(u.len() * N);
        let mut p = Vec::with_capacity(u.len() * N);
        for &u in u {
            let w = s.sample::<N>(u);
            l.extend(w.lambda);
            p.extend(w.pdf);
        }
        (l, p)
    }));
    Ok((
        arrays::out(py, l, n)?.unbind(),
        arrays::out(py, p, n)?.unbind(),
    ))
}

/// Wavelengths for `u` (M,) in [0, 1): `lanes` per row over `range` (nm), by `sampling`
/// ("Visible" or "Uniform"). Returns (wavelengths, pdf), each (M, lanes).
#[pyfunction]
#[pyo3(signature = (u, lanes=4, range=(360.0, 830.0), sampling="Visible"))]
pub fn sample_wavelengths(
    py: Python<'_>,
    u: PyArrayLike1<'_, f32, AllowTypeChange>,
    lanes: usize,
    range: (f32, f32),
    sampling: &str,
) -> PyResult<(Py<PyAny>, Py<PyAny>)> {
    let kind: WavelengthSampling = variant(sampling, "sampling", "\"Visible\", \"Uniform\"")?;
    let (lo, hi) = range;
    if kind == WavelengthSampling::Sensor || !valid_range(range) {
        return Err(SceneError::new_err(format!(
            "sample_wavelengths takes sampling \"Visible\" or \"Uniform\" over a positive, increasing range that ends by {} nm (got {sampling:?}, {range:?}); a scene's sensor sampling is scene.sample_wavelengths", prism_core::load::MAX_NM
        )));
    }
    sample(
        &WavelengthSampler::new(kind, lo, hi),
        &arrays::unit(arrays::floats(&u), "u")?,
        lanes,
        py,
    )
}

/// `spec` (a spectrum as `load_dict` takes it, or a number) at `wavelengths` (any shape, nm),
/// as the scene loader resolves it for `role` ("reflectance": RGB uplifted bounded;
/// "emission": RGB uplifted times D65; "ior"; "response"), checked over `range`.
#[pyfunction]
#[pyo3(signature = (spec, wavelengths, role="reflectance", range=(360.0, 830.0)))]
pub fn spectrum<'py>(
    py: Python<'py>,
    spec: &Bound<'py, PyAny>,
    wavelengths: numpy::PyArrayLikeDyn<'py, f32, AllowTypeChange>,
    role: &str,
    range: (f32, f32),
) -> PyResult<Bound<'py, PyAny>> {
    let role: Role = match role {
        "reflectance" => Role::Reflectance,
        "emission" => Role::Emission,
        "ior" => Role::Ior,
        "response" => Role::Response,
        r => {
            return Err(SceneError::new_err(format!(
                "unknown role \"{r}\"; use \"reflectance\", \"emission\", \"ior\" or \"response\""
            )))
        }
    };
    // The loader's check of a scene's `spectral.range`: a spectrum resolved over a range
    // reaching 1e9 nm tabulates it nm by nm (minutes, gigabytes), and an empty or reversed
    // one gives values for nothing.
    if !valid_range(range) {
        return Err(SceneError::new_err(format!(
            "spectrum: range {range:?} must be positive and increasing and end by {} nm, as a scene's spectral.range; give e.g. range=(360, 830)",
            prism_core::load::MAX_NM
        )));
    }
    let file = Path::new("<spectrum>");
    let text = to_json(py, spec, file, "the spectrum")?;
    let v: serde_json::Value = serde_json::from_str(&text).expect("json.dumps writes JSON");
    let v = match v {
        serde_json::Value::Number(n) => serde_json::json!({ "Constant": n }),
        v => v,
    };
    let cfg: SpectrumConfig = serde_json::from_value(v).map_err(|e| {
        SceneError::new_err(format!(
            "{file}: spectrum: {e}\n  hint: give a number or a spectrum as load_dict takes it, e.g. {{\"Rgb\": [0.8, 0.2, 0.1]}} or {{\"Named\": \"D65\"}}",
            file = file.display()
        ))
    })?;
    let ctx = Context {
        file,
        field: "spectrum",
        range,
    };
    let curve = cfg
        .resolve(role, &ctx, &mut Vec::new())
        .map_err(|e| crate::to_py(e.into()))?;
    let shape = wavelengths.shape().to_vec();
    let l = arrays::nm(
        wavelengths.as_array().iter().copied().collect(),
        "wavelengths",
    )?;
    let v: Vec<f32> = py.detach(|| l.iter().map(|&l| curve.eval_one(l)).collect());
    Ok(numpy::PyArray1::from_vec(py, v).reshape(shape)?.into_any())
}

/// The CIE 1931 colour-matching functions at `wavelengths` (M, N) divided by ∫ȳ: the weights
/// with which the sensor adds a lane's radiance (times 1 / (N p)) to X, Y, Z. Shape (M, N, 3).
#[pyfunction]
pub fn cie_xyz<'py>(
    py: Python<'py>,
    wavelengths: numpy::PyArrayLikeDyn<'py, f32, AllowTypeChange>,
) -> PyResult<Bound<'py, PyAny>> {
    let cmf = prism_core::sensor::Observer::Cie1931.cmf();
    let mut shape = wavelengths.shape().to_vec();
    shape.push(3);
    let l = arrays::nm(
        wavelengths.as_array().iter().copied().collect(),
        "wavelengths",
    )?;
    let v: Vec<f32> = l
        .iter()
        .flat_map(|&l| cmf.eval(l).map(|c| c / cmf.y_integral))
        .collect();
    Ok(numpy::PyArray1::from_vec(py, v).reshape(shape)?.into_any())
}

/// The most numbers one `sampler_stream` call returns (f32: 1 GiB).
const MAX_NUMBERS: u64 = 1 << 28;

/// The numbers a render's sampler gives: for each row i, sample `sample[i]` of pixel
/// `pixel[i]` (y · width + x) under (`kind`, `seed`), dimensions `start` .. `start + count`
/// (camera: film x, y, wavelength, spare; then 8 per bounce). Shape (M, count).
#[pyfunction]
#[pyo3(signature = (pixel, sample, start=0, count=4, kind="Independent", seed=0))]
pub fn sampler_stream<'py>(
    py: Python<'py>,
    pixel: Vec<u64>,
    sample: Vec<u32>,
    start: u32,
    count: usize,
    kind: &str,
    seed: u64,
) -> PyResult<Bound<'py, PyAny>> {
    let kind: SamplerKind = variant(kind, "sampler", "\"Independent\", \"Sobol\"")?;
    arrays::same_len(sample.len(), pixel.len(), "sample")?;
    // The output is allocated whole: a count past what memory holds would abort the process.
    let total = (pixel.len() as u64).saturating_mul(count as u64);
    if total > MAX_NUMBERS {
        return Err(SceneError::new_err(format!(
            "sampler_stream: {} rows × count={count} is {total} numbers, more than the \
             {MAX_NUMBERS} (1 GiB) one call returns; ask for fewer rows or dimensions per call",
            pixel.len()
        )));
    }
    let v = py.detach(|| {
        let mut v = Vec::with_capacity(pixel.len() * count);
        for (&p, &s) in pixel.iter().zip(&sample) {
            let mut ps = PixelSampler::new(kind, seed, p);
            ps.start(s);
            ps.set_dimension(start);
            v.extend((0..count).map(|_| ps.next_1d()));
        }
        v
    });
    arrays::out(py, v, count)
}

#[pymethods]
impl Scene {
    /// Wavelengths for `u` (M,) as this scene's render draws them (its lane count, range and
    /// sampling, the sensor's too). Returns (wavelengths, pdf), each (M, N).
    #[pyo3(name = "sample_wavelengths")]
    fn scene_sample_wavelengths(
        &self,
        py: Python<'_>,
        u: PyArrayLike1<'_, f32, AllowTypeChange>,
    ) -> PyResult<(Py<PyAny>, Py<PyAny>)> {
        let (s, n) = {
            let st = self.read();
            (st.job.settings.wavelengths, st.job.settings.lanes)
        };
        sample(&s, &arrays::unit(arrays::floats(&u), "u")?, n, py)
    }
}
