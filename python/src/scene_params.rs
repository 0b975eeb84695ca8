//! `scene.params`: a mapping of the scene's changeable values (names in `params`). Setting one
//! rebuilds the scene's materials, lights, camera and sensor at once, never its geometry, so
//! the next render shows it; `update` sets several with one rebuild.

use crate::load::{to_json, Scene};
use crate::params;
use crate::to_py;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use serde_json::Value;

#[pyclass(frozen, module = "prism", mapping)]
pub struct Params {
    pub(crate) scene: Py<Scene>,
}

impl Params {
    fn value(py: Python<'_>, s: &Scene, name: &str) -> PyResult<Py<PyAny>> {
        let st = s.read();
        let v =
            params::get(&st.job.config, st.exposure, name, &s.file).map_err(|e| to_py(e.into()))?;
        drop(st);
        Ok(py
            .import("json")?
            .call_method1("loads", (v.to_string(),))?
            .unbind())
    }

    fn json(py: Python<'_>, s: &Scene, name: &str, v: &Bound<'_, PyAny>) -> PyResult<Value> {
        let text = to_json(py, v, &s.file, &format!("the value of \"{name}\""))?;
        Ok(serde_json::from_str(&text).expect("json.dumps writes JSON"))
    }
}

#[pymethods]
impl Params {
    fn __getitem__(&self, py: Python<'_>, name: &str) -> PyResult<Py<PyAny>> {
        Self::value(py, self.scene.get(), name)
    }

    fn __setitem__(&self, py: Python<'_>, name: String, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let s = self.scene.get();
        let v = Self::json(py, s, &name, value)?;
        s.set_params(py, vec![(name, v)])
    }

    /// Sets every `name: value` of `values`, then rebuilds once (all or none are set).
    fn update(&self, py: Python<'_>, values: &Bound<'_, PyDict>) -> PyResult<()> {
        let s = self.scene.get();
        let mut edits = Vec::new();
        for (k, v) in values.iter() {
            let name: String = k.extract()?;
            let v = Self::json(py, s, &name, &v)?;
            edits.push((name, v));
        }
        s.set_params(py, edits)
    }

    fn keys(&self) -> Vec<String> {
        params::names(&self.scene.get().read().job.config)
    }

    fn items(&self, py: Python<'_>) -> PyResult<Vec<(String, Py<PyAny>)>> {
        let s = self.scene.get();
        self.keys()
            .into_iter()
            .map(|k| Ok((k.clone(), Self::value(py, s, &k)?)))
            .collect()
    }

    fn __iter__(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        Ok(self
            .keys()
            .into_pyobject(py)?
            .try_iter()?
            .into_any()
            .unbind())
    }

    fn __len__(&self) -> usize {
        self.keys().len()
    }

    fn __contains__(&self, name: &str) -> bool {
        self.keys().iter().any(|k| k == name)
    }

    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        let d = PyDict::new(py);
        for (k, v) in self.items(py)? {
            d.set_item(k, v)?;
        }
        Ok(format!("<prism.Params {}>", d.repr()?))
    }
}
