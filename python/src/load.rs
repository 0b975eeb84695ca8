//! `prism.load_file`, `load_string`, `load_dict` and the `Scene` they return: a built scene (its
//! geometry and acceleration structure), kept for any number of renders.

use crate::glue::{self, Overrides, Source};
use crate::params;
use crate::scene_params::Params;
use crate::to_py;
use prism_core::config::SceneConfig;
use prism_core::error::InputError;
use prism_core::load::Job;
use pyo3::prelude::*;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::sync::{RwLock, RwLockReadGuard};

/// A scene ready to render. `config` is its parsed configuration as a dict (the form
/// `load_dict` takes); `warnings` what prism would print before rendering it; `params` its
/// changeable values.
#[pyclass(frozen, module = "prism")]
pub struct Scene {
    /// The built scene. Renders read it from their own (non-Python) thread and a parameter
    /// change writes it with the GIL released, so no thread waits for it holding the GIL.
    pub(crate) state: RwLock<State>,
    pub(crate) source: Source,
    /// The file named in errors, the sidecar and the EXR header (`<string>`/`<dict>` in the
    /// current directory for text and dicts, which anchors their relative paths there).
    pub(crate) file: PathBuf,
}

/// A scene's built job and what `params` set beside its config.
pub(crate) struct State {
    pub job: Job,
    /// `sensor.exposure`, stops.
    pub exposure: f32,
    /// How many times geometry was built (loaded and put into an accelerator) for this scene.
    pub builds: u32,
}

impl Scene {
    pub(crate) fn read(&self) -> RwLockReadGuard<'_, State> {
        // A panic while writing is caught before it could leave the job half changed.
        self.state.read().unwrap_or_else(|e| e.into_inner())
    }

    /// Sets parameters `(name, value)` in order, then rebuilds the scene once: everything but
    /// its geometry, unless the scene is a glTF one (its geometry comes with its file). On an
    /// error nothing changes.
    pub(crate) fn set_params(&self, py: Python<'_>, edits: Vec<(String, Value)>) -> PyResult<()> {
        let (source, file) = (&self.source, &self.file);
        py.detach(|| {
            let mut st = self.state.write().unwrap_or_else(|e| e.into_inner());
            let mut cfg = st.job.config.clone();
            let mut exposure = st.exposure;
            for (name, v) in edits {
                params::set(&mut cfg, &mut exposure, &name, v, file)?;
            }
            if glue::has_gltf(source, &cfg) {
                st.job = glue::rebuild(source, file, &Overrides::default(), &cfg)?;
                st.builds += 1;
            } else {
                glue::relight(&mut st.job, cfg, file)?;
            }
            st.exposure = exposure;
            Ok(())
        })
        .map_err(to_py)
    }
}

#[pymethods]
impl Scene {
    /// The parsed configuration as nested dicts and lists (serde's JSON form of the RON schema).
    #[getter]
    fn config<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let text = serde_json::to_string(&self.read().job.config)
            .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
        py.import("json")?.call_method1("loads", (text,))
    }

    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.read().job.warnings.clone()
    }

    #[getter]
    fn file(&self) -> PathBuf {
        self.file.clone()
    }

    /// (width, height) of the film in pixels.
    #[getter]
    fn size(&self) -> (u32, u32) {
        let s = &self.read().job.settings;
        (s.width, s.height)
    }

    /// The changeable values by name (`scene.params["materials.red.reflectance"] = ...`).
    #[getter]
    fn params(slf: Py<Self>) -> Params {
        Params { scene: slf }
    }

    /// How many times this scene's geometry was built: 1 after loading, and still 1 after any
    /// change of `params` (but in glTF scenes).
    #[getter]
    fn geometry_builds(&self) -> u32 {
        self.read().builds
    }

    fn __repr__(&self) -> String {
        let st = self.read();
        let s = &st.job.settings;
        format!(
            "<prism.Scene {} {}x{} at {} spp, {} shapes>",
            self.file.display(),
            s.width,
            s.height,
            s.spp,
            st.job.scene.shapes.len()
        )
    }
}

fn scene(job: Job, source: Source, file: PathBuf) -> Scene {
    let state = State {
        job,
        exposure: 0.0,
        builds: 1,
    };
    Scene {
        state: RwLock::new(state),
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
    let job = py
        .detach(|| glue::build(cfg, &file, &Overrides::default()))
        .map_err(to_py)?;
    Ok(scene(job, Source::Config, file))
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
    let text = to_json(py, d, &file, "the scene")?;
    let cfg = parse_json(&text, &file).map_err(|e| to_py(e.into()))?;
    from_config(py, cfg, file)
}

/// `v` as JSON text, numpy scalars and arrays as their Python values; an error naming `file`
/// for what JSON cannot hold.
pub(crate) fn to_json(
    py: Python<'_>,
    v: &Bound<'_, PyAny>,
    file: &Path,
    what: &str,
) -> PyResult<String> {
    // allow_nan=False: JSON has no NaN, and serde would read one as an error far from its place.
    let kwargs = pyo3::types::PyDict::new(py);
    kwargs.set_item("allow_nan", false)?;
    let tolist = py
        .import("operator")?
        .call_method1("methodcaller", ("tolist",))?;
    kwargs.set_item("default", tolist)?;
    match py.import("json")?.call_method("dumps", (v,), Some(&kwargs)) {
        Ok(t) => t.extract(),
        Err(e) => {
            let msg = format!("{what} is not plain data: {}", e.value(py));
            Err(to_py(
                InputError::new(file, msg)
                    .hint("give dicts, lists, strings, finite numbers and booleans only")
                    .into(),
            ))
        }
    }
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
