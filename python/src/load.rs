//! `prism.load_file`, `load_string`, `load_dict` and the `Scene` they return: a built scene (its
//! geometry and acceleration structure), kept for any number of renders.

use crate::glue::{self, Overrides, Source};
use crate::to_py;
use prism_core::config::SceneConfig;
use prism_core::error::InputError;
use prism_core::load::Job;
use pyo3::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A scene ready to render. `config` is its parsed configuration as a dict (the form
/// `load_dict` takes); `warnings` what prism would print before rendering it.
#[pyclass(frozen, module = "prism")]
pub struct Scene {
    pub(crate) job: Arc<Job>,
    pub(crate) source: Source,
    /// The file named in errors, the sidecar and the EXR header (`<string>`/`<dict>` in the
    /// current directory for text and dicts, which anchors their relative paths there).
    pub(crate) file: PathBuf,
}

impl Scene {
    /// The job to render with `o`: this one, or rebuilt when `o` changes the config.
    pub(crate) fn job_for(&self, py: Python<'_>, o: &Overrides) -> PyResult<Arc<Job>> {
        if !o.change_config() {
            return Ok(self.job.clone());
        }
        let (source, file) = (&self.source, &self.file);
        let job = py
            .detach(|| glue::rebuild(source, file, o))
            .map_err(to_py)?;
        Ok(Arc::new(job))
    }
}

#[pymethods]
impl Scene {
    /// The parsed configuration as nested dicts and lists (serde's JSON form of the RON schema).
    #[getter]
    fn config<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let text = serde_json::to_string(&self.job.config)
            .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
        py.import("json")?.call_method1("loads", (text,))
    }

    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.job.warnings.clone()
    }

    #[getter]
    fn file(&self) -> PathBuf {
        self.file.clone()
    }

    /// (width, height) of the film in pixels.
    #[getter]
    fn size(&self) -> (u32, u32) {
        (self.job.settings.width, self.job.settings.height)
    }

    fn __repr__(&self) -> String {
        let s = &self.job.settings;
        format!(
            "<prism.Scene {} {}x{} at {} spp, {} shapes>",
            self.file.display(),
            s.width,
            s.height,
            s.spp,
            self.job.scene.shapes.len()
        )
    }
}

fn scene(job: Job, source: Source, file: PathBuf) -> Scene {
    Scene {
        job: Arc::new(job),
        source,
        file,
    }
}

/// Loads a scene file, RON or glTF (by its extension), as `prism render` does.
#[pyfunction]
pub fn load_file(py: Python<'_>, path: PathBuf) -> PyResult<Scene> {
    let job = py
        .detach(|| glue::load_file(&path, &Overrides::default()))
        .map_err(to_py)?;
    Ok(scene(job, Source::File(path.clone()), path))
}

/// Builds `cfg` (parsed from `file`) into a scene.
fn from_config(py: Python<'_>, cfg: SceneConfig, file: PathBuf) -> PyResult<Scene> {
    let keep = cfg.clone();
    let job = py
        .detach(|| glue::build(cfg, &file, &Overrides::default()))
        .map_err(to_py)?;
    Ok(scene(job, Source::Config(Box::new(keep)), file))
}

/// Loads a scene from RON text; relative paths in it are taken from the current directory.
#[pyfunction]
pub fn load_string(py: Python<'_>, ron: &str) -> PyResult<Scene> {
    let file = PathBuf::from("<string>");
    let cfg = prism_core::config::parse_str(ron, &file).map_err(|e| to_py(e.into()))?;
    from_config(py, cfg, file)
}

/// Loads a scene from nested dicts and lists: the RON schema in serde's JSON form (enum
/// variants as `{"LookAt": {...}}`, `{"Rgb": [r, g, b]}`, `{"Named": "D65"}`; unit variants
/// as their name). Relative paths are taken from the current directory.
#[pyfunction]
pub fn load_dict(py: Python<'_>, d: &Bound<'_, PyAny>) -> PyResult<Scene> {
    let file = PathBuf::from("<dict>");
    // allow_nan=False: JSON has no NaN, and serde would read one as an error far from its place.
    let kwargs = pyo3::types::PyDict::new(py);
    kwargs.set_item("allow_nan", false)?;
    let text: String = match py.import("json")?.call_method("dumps", (d,), Some(&kwargs)) {
        Ok(t) => t.extract()?,
        Err(e) => {
            let msg = format!("the scene is not plain data: {}", e.value(py));
            return Err(to_py(
                InputError::new(&file, msg)
                    .hint("give dicts, lists, strings, finite numbers and booleans only")
                    .into(),
            ));
        }
    };
    let cfg = parse_json(&text, &file).map_err(|e| to_py(e.into()))?;
    from_config(py, cfg, file)
}

/// The config from its JSON form, an error naming the field where it failed.
fn parse_json(text: &str, file: &Path) -> Result<SceneConfig, InputError> {
    let mut de = serde_json::Deserializer::from_str(text);
    serde_path_to_error::deserialize(&mut de).map_err(|e| {
        let field = e.path().to_string();
        let inner = e.into_inner();
        // serde_json appends " at line L column C" of the JSON text, which the user never saw.
        let msg = inner.to_string();
        let msg = msg.split(" at line ").next().unwrap_or(&msg).to_string();
        let err = InputError::new(file, msg)
            .hint("check the spelling and nesting; scenes/README.md lists every field, and enum variants are written {\"Variant\": value}");
        if field == "." {
            err
        } else {
            err.field(field)
        }
    })
}
