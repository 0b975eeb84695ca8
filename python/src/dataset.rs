//! `prism.Dataset(path)`: the finished frames of a `prism dataset` output, read lazily (only
//! `ds[i]` reads frame i), picklable by its path for a PyTorch `DataLoader`'s workers; and
//! `prism.run_dataset`, which runs `prism dataset` in this process.

use crate::render::SIGNAL_POLL;
use crate::to_py;
use numpy::{PyArray1, PyArrayMethods};
use prism_core::dataset::cli::DatasetArgs;
use prism_core::io::input_file::{self, Kind};
use prism_core::pipeline::WorkerArgs;
use pyo3::exceptions::PyOSError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;

#[pyclass(frozen, module = "prism")]
pub struct Dataset {
    root: PathBuf,
    /// The frames the manifest lists as finished, in increasing order.
    frames: Vec<u32>,
}

/// The frame numbers of every manifest line that parses (a torn last line after a crash is
/// skipped, as prism_tools does; so is a frame number no dataset has, past u32, which would
/// otherwise wrap onto another frame's files).
fn finished_frames(root: &Path) -> Result<Vec<u32>, String> {
    // A regular file only: a FIFO or /dev/zero as the manifest would be read forever.
    let bytes = input_file::read(&root.join("manifest.jsonl"), Kind::Manifest)?;
    let text = String::from_utf8_lossy(&bytes);
    let set: BTreeSet<u32> = text
        .lines()
        .filter_map(|l| serde_json::from_str::<serde_json::Value>(l).ok())
        .filter_map(|v| u32::try_from(v.get("frame")?.as_u64()?).ok())
        .collect();
    Ok(set.into_iter().collect())
}

/// A frame's file as text (its sidecar), read as the manifest is; errors name the file.
fn read_text(path: &Path) -> PyResult<String> {
    let bytes = input_file::read(path, Kind::Asset).map_err(PyOSError::new_err)?;
    String::from_utf8(bytes).map_err(|e| {
        PyOSError::new_err(format!(
            "{}: the frame's sidecar is not UTF-8 text ({e}); rerun `prism dataset` on the folder to redo the frame",
            path.display()
        ))
    })
}

#[pymethods]
impl Dataset {
    #[new]
    fn new(path: PathBuf) -> PyResult<Self> {
        let frames = finished_frames(&path).map_err(|e| {
            PyOSError::new_err(format!(
                "{}: no dataset here ({e}); `prism dataset CONFIG -o {}` makes one",
                path.join("manifest.jsonl").display(),
                path.display()
            ))
        })?;
        Ok(Dataset { root: path, frames })
    }

    fn __len__(&self) -> usize {
        self.frames.len()
    }

    /// Frame `i` of the finished ones: every EXR channel by name (float32, uint32 for ids,
    /// height × width), `spectral` (height × width × bands) with `wavelengths`, `frame` (its
    /// number) and `metadata` (its sidecar, the sampled parameters under `frame`).
    fn __getitem__<'py>(&self, py: Python<'py>, i: isize) -> PyResult<Bound<'py, PyDict>> {
        let n = self.frames.len() as isize;
        let k = if i < 0 { i + n } else { i };
        if !(0..n).contains(&k) {
            return Err(pyo3::exceptions::PyIndexError::new_err(format!(
                "frame index {i} out of range for {n} finished frames"
            )));
        }
        let frame = self.frames[k as usize];
        let base = self.root.join(format!("frames/{frame:06}"));
        let exr = base.with_extension("exr");
        let channels = py
            .detach(|| read_exr(&exr))
            .map_err(|e| PyOSError::new_err(format!("{}: {e}", exr.display())))?;
        let side_path = base.with_extension("json");
        let side = read_text(&side_path)?;
        let metadata = py
            .import("json")?
            .call_method1("loads", (side,))
            .map_err(|e| {
                PyOSError::new_err(format!(
                    "{}: the frame's sidecar is not valid JSON ({}); rerun `prism dataset` on the folder to redo the frame",
                    side_path.display(),
                    e.value(py)
                ))
            })?;
        let d = PyDict::new(py);
        let mut bands: Vec<(f32, Vec<f32>)> = Vec::new();
        let mut shape = [0usize; 2];
        for (name, w, h, data) in channels {
            shape = [h, w];
            match data {
                Samples::F32(v) => {
                    if let Some(nm) = spectral_nm(&name) {
                        bands.push((nm, v.clone()));
                    }
                    d.set_item(&name, PyArray1::from_vec(py, v).reshape(shape)?)?;
                }
                Samples::U32(v) => d.set_item(&name, PyArray1::from_vec(py, v).reshape(shape)?)?,
            }
        }
        bands.sort_by(|a, b| a.0.total_cmp(&b.0));
        let px = shape[0] * shape[1];
        // prism writes one layer size; another file's layers of other sizes would index past
        // a band's samples.
        if bands.iter().any(|b| b.1.len() != px) {
            return Err(PyOSError::new_err(format!(
                "{}: the spectral channels differ in size, which prism never writes; rerun `prism dataset` on the folder to redo the frame",
                exr.display()
            )));
        }
        let mut cube = Vec::with_capacity(px * bands.len());
        for p in 0..px {
            cube.extend(bands.iter().map(|b| b.1[p]));
        }
        let wl: Vec<f32> = bands.iter().map(|b| b.0).collect();
        let cube = PyArray1::from_vec(py, cube).reshape([shape[0], shape[1], bands.len()])?;
        d.set_item("spectral", cube)?;
        d.set_item("wavelengths", PyArray1::from_vec(py, wl))?;
        d.set_item("frame", frame)?;
        d.set_item("metadata", metadata)?;
        Ok(d)
    }

    /// Pickled as its path: a `DataLoader` worker opens its own.
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<(Bound<'py, PyAny>, (PathBuf,))> {
        Ok((slf.get_type().into_any(), (slf.get().root.clone(),)))
    }

    fn __repr__(&self) -> String {
        format!(
            "<prism.Dataset {} ({} frames)>",
            self.root.display(),
            self.frames.len()
        )
    }
}

/// `S0.550,000000nm` (Fichet et al. 2021, zero-padded or not) → 550.
fn spectral_nm(name: &str) -> Option<f32> {
    let v = name.strip_prefix("S0.")?.strip_suffix("nm")?;
    v.replace(',', ".").parse().ok()
}

enum Samples {
    F32(Vec<f32>),
    U32(Vec<u32>),
}

/// Every channel of the EXR as (full name, width, height, samples); half floats widened.
fn read_exr(path: &Path) -> Result<Vec<(String, usize, usize, Samples)>, String> {
    use exr::prelude::*;
    let img = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .all_layers()
        .all_attributes()
        // No rayon: a DataLoader's workers are forked from a process whose rayon threads (its
        // renders') do not exist in the child, where a parallel read would wait for them forever.
        .non_parallel()
        // Opened as an input file: a FIFO or device in its place is refused, not read forever.
        .from_buffered(std::io::BufReader::new(input_file::open(
            path,
            Kind::Asset,
        )?))
        .map_err(|e| e.to_string())?;
    let mut out = Vec::new();
    for layer in img.layer_data {
        let (w, h) = (layer.size.width(), layer.size.height());
        let prefix = layer.attributes.layer_name.map(|n| format!("{n}."));
        for ch in layer.channel_data.list {
            let name = format!("{}{}", prefix.as_deref().unwrap_or(""), ch.name);
            let s = match ch.sample_data {
                FlatSamples::F32(v) => Samples::F32(v),
                FlatSamples::F16(v) => Samples::F32(v.iter().map(|x| x.to_f32()).collect()),
                FlatSamples::U32(v) => Samples::U32(v),
            };
            out.push((name, w, h, s));
        }
    }
    Ok(out)
}

/// Runs `prism dataset CONFIG -o OUT [--shard S --num-shards N --threads T]` in this process
/// (resumable, as the command); raises `SceneError` for a bad config and `RuntimeError` when
/// a frame failed.
#[pyfunction]
#[pyo3(signature = (config, out, shard=None, num_shards=None, threads=None, progress=true))]
pub fn run_dataset(
    py: Python<'_>,
    config: PathBuf,
    out: PathBuf,
    shard: Option<u32>,
    num_shards: Option<u32>,
    threads: Option<usize>,
    progress: bool,
) -> PyResult<()> {
    let args = DatasetArgs {
        config,
        output: out,
        frames: None,
        export_frame: None,
        shard,
        num_shards,
        check: false,
        force: false,
        verify: false,
        workers: WorkerArgs {
            threads,
            quiet: !progress,
        },
    };
    // The run goes on a worker thread without the GIL; this thread takes the GIL back now
    // and then to run Python's signal handlers (Ctrl-C), which stop the run before its next
    // frame: the frames done are listed, so a rerun resumes.
    let stop = AtomicBool::new(false);
    let (summary, interrupted) = std::thread::scope(|sc| {
        let (tx, rx) = mpsc::channel();
        let (args, stop) = (&args, &stop);
        sc.spawn(move || {
            let _ = tx.send(prism_core::dataset::cli::main(args, Some(stop)));
        });
        let mut rx = rx;
        let mut interrupted = None;
        loop {
            let (got, back) = py.detach(move || (rx.recv_timeout(SIGNAL_POLL), rx));
            rx = back;
            match got {
                Ok(r) => return (r, interrupted),
                Err(mpsc::RecvTimeoutError::Timeout) => {}
                Err(mpsc::RecvTimeoutError::Disconnected) => {
                    let e = pyo3::exceptions::PyRuntimeError::new_err(
                        "the dataset thread stopped without a result",
                    );
                    return (Ok(Default::default()), Some(e));
                }
            }
            if interrupted.is_none() {
                if let Err(e) = py.check_signals() {
                    stop.store(true, Ordering::Relaxed);
                    interrupted = Some(e);
                }
            }
        }
    });
    let summary = summary.map_err(to_py)?;
    if let Some(e) = interrupted {
        return Err(e);
    }
    if summary.failed > 0 {
        return Err(pyo3::exceptions::PyRuntimeError::new_err(format!(
            "some frames of {} failed (see the messages above); a rerun retries them",
            args.config.display()
        )));
    }
    Ok(())
}
