//! `prism.render(scene, ...)` and the `Render` it returns: the film as numpy arrays, the sidecar
//! as a dict, and `write` for the files `prism render` writes.

use crate::glue::{self, Overrides, Rendered};
use crate::load::Scene;
use crate::progress::{Counter, Reporter};
use crate::to_py;
use numpy::{PyArray1, PyArrayMethods};
use prism_core::load::Job;
use prism_core::math::portable;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Duration;

/// How often the calling thread looks for Ctrl-C while the workers render.
pub(crate) const SIGNAL_POLL: Duration = Duration::from_millis(50);

/// A finished render.
#[pyclass(frozen, module = "prism")]
pub struct Render {
    job: Job,
    r: Rendered,
    file: PathBuf,
}

/// Renders `scene` as `prism render` does with the same flags (same bits): `spp`, `seed`
/// override the scene's sampler; `aovs` names the layers to render instead of the scene's
/// (empty: the scene's own); `sensor` is a sensor file replacing the scene's; `threads` the
/// workers (None: one per core); `progress` True (or None) for a bar in a terminal or notebook,
/// False for none, or a callable `f(done, total)` (progress.py). The GIL is released while
/// rendering, and Ctrl-C (or an exception from `progress`) stops the render and raises.
#[pyfunction]
#[pyo3(signature = (scene, spp=None, seed=None, threads=None, aovs=Vec::new(), sensor=None, progress=None))]
#[pyo3(
    text_signature = "(scene, spp=None, seed=None, threads=None, aovs=(), sensor=None, progress=True)"
)]
#[allow(clippy::too_many_arguments)]
pub fn render(
    py: Python<'_>,
    scene: &Scene,
    spp: Option<u32>,
    seed: Option<u64>,
    threads: Option<usize>,
    aovs: Vec<String>,
    sensor: Option<PathBuf>,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<Render> {
    if spp == Some(0) {
        return Err(to_py(
            prism_core::pipeline::workers::zero_spp(&scene.file).into(),
        ));
    }
    let o = Overrides {
        spp,
        seed,
        aovs: (!aovs.is_empty()).then_some(aovs),
        sensor,
        threads,
    };
    let mut reporter = Reporter::new(py, progress.as_ref())?;
    let counter = Counter::default();
    let cancel = AtomicBool::new(false);
    let result = std::thread::scope(|sc| -> PyResult<_> {
        let (tx, rx) = mpsc::channel();
        let (o, cancel, counter) = (&o, &cancel, &counter);
        // The scene is read (and rebuilt for the overrides) on this worker thread: it never
        // waits for a parameter change holding the GIL.
        sc.spawn(move || {
            let _ = tx.send(render_scene(scene, o, cancel, counter));
        });
        // The workers render without the GIL; this thread takes it back now and then only to
        // let Python run its signal handlers (Ctrl-C), which must run on the main thread, and
        // to draw the progress the workers counted.
        let mut rx = rx;
        loop {
            let (got, back) = py.detach(move || (rx.recv_timeout(SIGNAL_POLL), rx));
            rx = back;
            match got {
                Ok(r) => return Ok(r),
                Err(mpsc::RecvTimeoutError::Timeout) => {}
                Err(mpsc::RecvTimeoutError::Disconnected) => {
                    return Err(pyo3::exceptions::PyRuntimeError::new_err(
                        "the render thread stopped without a result",
                    ))
                }
            }
            let go_on = py.check_signals().and_then(|_| reporter.poll(py, counter));
            if let Err(e) = go_on {
                cancel.store(true, Ordering::Relaxed);
                // Wait for the workers to unwind before the scene they read can go.
                let _ = py.detach(move || rx.recv());
                return Err(e);
            }
        }
    });
    let finished = matches!(&result, Ok(Ok(Ok(_))));
    reporter.close(py, &counter, finished);
    let (r, job) = match result?.map_err(to_py)? {
        Ok(r) => r,
        Err(glue::Cancelled) => {
            return Err(pyo3::exceptions::PyKeyboardInterrupt::new_err(
                "render cancelled",
            ))
        }
    };
    Ok(Render {
        job,
        r,
        file: scene.file.clone(),
    })
}

type Outcome = Result<Result<(Rendered, Job), glue::Cancelled>, prism_core::error::Error>;

/// Renders the scene as it is now (its parameters, its exposure), rebuilt first when `o`
/// changes its config; the render with the job's shell (`glue::shell`) to write it by.
fn render_scene(scene: &Scene, o: &Overrides, cancel: &AtomicBool, counter: &Counter) -> Outcome {
    let st = scene.read();
    let scale = portable::exp2(st.exposure);
    let go = |job: &Job| -> Outcome {
        let s = &job.settings;
        counter.start(s.width as u64 * s.height as u64 * s.spp as u64);
        let r = glue::render(job, &scene.file, o.threads, scale, cancel, &|n| {
            counter.add(n)
        })?;
        Ok(r.map(|r| (r, glue::shell(job))))
    };
    if o.change_config() {
        let cfg = st.job.config.clone();
        drop(st);
        go(&glue::rebuild(&scene.source, &scene.file, o, &cfg)?)
    } else {
        go(&st.job)
    }
}

#[pymethods]
impl Render {
    /// Every EXR channel by name: float32 (uint32 for the id layers), height × width.
    #[getter]
    fn channels<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let f = &self.r.film;
        let shape = [f.height as usize, f.width as usize];
        let d = PyDict::new(py);
        for c in &f.channels {
            d.set_item(&c.name, PyArray1::from_slice(py, &c.data).reshape(shape)?)?;
        }
        for c in &f.uint_channels {
            d.set_item(&c.name, PyArray1::from_slice(py, &c.data).reshape(shape)?)?;
        }
        Ok(d)
    }

    /// The spectral bands as one float32 array, height × width × bands (None without bands).
    #[getter]
    fn spectral<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        let f = &self.r.film;
        let sensor = &self.job.channels.sensor;
        let Some(b) = sensor.bands() else {
            return Ok(None);
        };
        let bands: Vec<&[f32]> = (0..b.count)
            .filter_map(|k| f.channel(&sensor.band_name(k)))
            .collect();
        let n = (f.width * f.height) as usize;
        let mut cube = Vec::with_capacity(n * bands.len());
        for i in 0..n {
            cube.extend(bands.iter().map(|c| c[i]));
        }
        let shape = [f.height as usize, f.width as usize, bands.len()];
        Ok(Some(
            PyArray1::from_vec(py, cube).reshape(shape)?.into_any(),
        ))
    }

    /// The centre wavelength (nm) of each band of `spectral`.
    #[getter]
    fn wavelengths<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f32>> {
        let b = self.job.channels.sensor.bands();
        let centres: Vec<f32> =
            b.map_or(Vec::new(), |b| (0..b.count).map(|k| b.center(k)).collect());
        PyArray1::from_vec(py, centres)
    }

    /// The sidecar as a dict (its `image` is None until `write` names the file).
    #[getter]
    fn sidecar<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let v = glue::sidecar(&self.job, &self.r, &self.file, Path::new(""));
        py.import("json")?.call_method1("loads", (v.to_string(),))
    }

    /// Samples taken, invalid (NaN/inf) samples and render seconds.
    #[getter]
    fn stats(&self) -> (u64, u64, f64) {
        (
            self.r.stats.samples,
            self.r.stats.invalid_samples,
            self.r.seconds,
        )
    }

    /// Writes the EXR at `path`, its sidecar (`.json`) beside it and, with `preview`, an 8-bit
    /// PNG at `exposure` stops, exactly as `prism render -o path [--preview ...]` writes them.
    #[pyo3(signature = (path, preview=None, exposure=0.0))]
    fn write(
        &self,
        py: Python<'_>,
        path: PathBuf,
        preview: Option<PathBuf>,
        exposure: f32,
    ) -> PyResult<()> {
        py.detach(|| {
            glue::write(
                &self.job,
                &self.r,
                &self.file,
                &path,
                preview.as_deref(),
                exposure,
            )
        })
        .map_err(to_py)
    }

    fn __repr__(&self) -> String {
        let f = &self.r.film;
        format!(
            "<prism.Render {}x{}, {} channels>",
            f.width,
            f.height,
            f.channels.len() + f.uint_channels.len()
        )
    }
}
