//! numpy in and out for the vectorised parts: (M, k) float32 arrays (any float dtype is
//! converted), checked for shape with an error that says what was expected.

use crate::SceneError;
use glam::{Vec2, Vec3};
use numpy::{
    AllowTypeChange, PyArray1, PyArrayLike1, PyArrayLike2, PyArrayMethods, PyUntypedArrayMethods,
};
use pyo3::prelude::*;

/// The rows of `a`, which must be (M, k); `name` names it in the error.
pub fn rows(
    a: &PyArrayLike2<'_, f32, AllowTypeChange>,
    k: usize,
    name: &str,
) -> PyResult<Vec<f32>> {
    let shape = a.shape();
    if shape[1] != k {
        return Err(SceneError::new_err(format!(
            "{name} must be an (M, {k}) array, got shape {shape:?}"
        )));
    }
    Ok(a.as_array().iter().copied().collect())
}

pub fn vec3s(a: &PyArrayLike2<'_, f32, AllowTypeChange>, name: &str) -> PyResult<Vec<Vec3>> {
    Ok(rows(a, 3, name)?
        .chunks_exact(3)
        .map(Vec3::from_slice)
        .collect())
}

pub fn vec2s(a: &PyArrayLike2<'_, f32, AllowTypeChange>, name: &str) -> PyResult<Vec<Vec2>> {
    Ok(rows(a, 2, name)?
        .chunks_exact(2)
        .map(Vec2::from_slice)
        .collect())
}

pub fn floats(a: &PyArrayLike1<'_, f32, AllowTypeChange>) -> Vec<f32> {
    a.as_array().iter().copied().collect()
}

/// Checks that `n` rows were given where `m` are needed.
pub fn same_len(n: usize, m: usize, name: &str) -> PyResult<()> {
    if n == m {
        Ok(())
    } else {
        Err(SceneError::new_err(format!(
            "{name} has {n} rows, but there are {m} rays"
        )))
    }
}

/// A flat buffer as an (M, k) array (k = 0: (M,)).
pub fn out<'py, T: numpy::Element>(
    py: Python<'py>,
    v: Vec<T>,
    k: usize,
) -> PyResult<Bound<'py, PyAny>> {
    let a = PyArray1::from_vec(py, v);
    if k == 0 {
        return Ok(a.into_any());
    }
    let m = a.len() / k;
    Ok(a.reshape([m, k])?.into_any())
}

pub fn out3<'py>(py: Python<'py>, v: &[Vec3]) -> PyResult<Bound<'py, PyAny>> {
    out(py, v.iter().flat_map(|p| p.to_array()).collect(), 3)
}

/// Runs `$body` with the const `$n` bound to the lane count `$lanes` (one of prism's).
macro_rules! with_lanes {
    ($lanes:expr, $n:ident => $body:expr) => {
        match $lanes {
            1 => { const $n: usize = 1; $body }
            2 => { const $n: usize = 2; $body }
            4 => { const $n: usize = 4; $body }
            8 => { const $n: usize = 8; $body }
            16 => { const $n: usize = 16; $body }
            k => {
                return Err($crate::SceneError::new_err(format!(
                    "{k} wavelengths per ray is not supported; give an (M, N) array with N one of {:?}",
                    prism_core::integrator::SUPPORTED_LANES
                )))
            }
        }
    };
}
pub(crate) use with_lanes;

/// The (M, N) wavelengths as each ray's `Wavelengths<N>` (pdfs 1: the parts use λ only).
pub fn wavelengths<const N: usize>(lambda: &[f32]) -> Vec<prism_core::spectrum::Wavelengths<N>> {
    lambda
        .chunks_exact(N)
        .map(|c| prism_core::spectrum::Wavelengths {
            lambda: c.try_into().expect("N lanes"),
            pdf: [1.0; N],
        })
        .collect()
}

/// Uniform numbers for a sampling decision: each in [0, 1], as a sampler gives them (outside
/// it a sampling routine could index past its tables).
pub fn unit(v: Vec<f32>, name: &str) -> PyResult<Vec<f32>> {
    match v.iter().find(|u| !(0.0..=1.0).contains(*u)) {
        None => Ok(v),
        Some(u) => Err(SceneError::new_err(format!(
            "{name} holds {u}; uniform numbers must lie in [0, 1]"
        ))),
    }
}

pub fn unit2(v: Vec<Vec2>, name: &str) -> PyResult<Vec<Vec2>> {
    unit(v.iter().flat_map(|u| u.to_array()).collect(), name)?;
    Ok(v)
}

/// Wavelengths in nm: finite and positive, at most `load::MAX_NM`.
pub fn nm(v: Vec<f32>, name: &str) -> PyResult<Vec<f32>> {
    let max = prism_core::load::MAX_NM;
    match v.iter().find(|l| !(**l > 0.0 && **l <= max)) {
        None => Ok(v),
        Some(l) => Err(SceneError::new_err(format!(
            "{name} holds {l}; wavelengths are in nm, positive and at most {max}"
        ))),
    }
}
