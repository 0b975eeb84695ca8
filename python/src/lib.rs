//! `import prism`: scenes from files, RON text or dicts, rendered into numpy arrays, written as
//! `prism render` writes them. The render steps themselves live in `glue`; this file declares the
//! module and turns prism's errors into Python's.

mod arrays;
mod bsdfs;
mod dataset;
mod glue;
mod load;
mod params;
mod parts;
mod progress;
mod render;
mod scene_params;
mod spectra;

use prism_core::error::Error;
use pyo3::prelude::*;

pyo3::create_exception!(
    prism,
    SceneError,
    pyo3::exceptions::PyValueError,
    "A scene (or render argument) prism refuses, with the CLI's message: file, place, fix."
);

/// prism's error as Python's: bad input is a `SceneError` carrying the CLI's message (what
/// `prism render` prints after `error: `), a file that cannot be read or written an `OSError`.
pub(crate) fn to_py(e: Error) -> PyErr {
    match e {
        Error::Input(_) => SceneError::new_err(e.to_string()),
        Error::Io { .. } => pyo3::exceptions::PyOSError::new_err(e.to_string()),
        Error::Other(m) => pyo3::exceptions::PyRuntimeError::new_err(m),
    }
}

#[pymodule]
fn prism(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("SceneError", m.py().get_type::<SceneError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    progress::add_module(m)?;
    // The sampler dimension of a thin lens's sample (`Scene.camera_rays`, `sampler_stream`).
    m.add("LENS_DIM", prism_core::camera::LENS_DIM)?;
    m.add_class::<load::Scene>()?;
    m.add_class::<render::Render>()?;
    m.add_class::<scene_params::Params>()?;
    m.add_class::<parts::Hits>()?;
    m.add_class::<dataset::Dataset>()?;
    m.add_function(wrap_pyfunction!(load::load_file, m)?)?;
    m.add_function(wrap_pyfunction!(load::load_string, m)?)?;
    m.add_function(wrap_pyfunction!(load::load_dict, m)?)?;
    m.add_function(wrap_pyfunction!(render::render, m)?)?;
    m.add_function(wrap_pyfunction!(dataset::run_dataset, m)?)?;
    m.add_function(wrap_pyfunction!(spectra::sample_wavelengths, m)?)?;
    m.add_function(wrap_pyfunction!(spectra::spectrum, m)?)?;
    m.add_function(wrap_pyfunction!(spectra::cie_xyz, m)?)?;
    m.add_function(wrap_pyfunction!(spectra::sampler_stream, m)?)?;
    Ok(())
}
