//! A render's progress as Python sees it: the workers add finished samples to an atomic counter
//! (no GIL, nothing else), and the thread that called `prism.render`, which wakes every 50 ms
//! for Ctrl-C anyway, reads it and hands `(done, total)` to a reporter written in Python
//! (`progress.py`, module `prism._progress`: tqdm, ipywidgets or a text line, in a terminal or a
//! notebook, or the caller's own function). Drawing in Python is what reaches a notebook: its
//! cells show Python's `sys.stdout`/`sys.stderr`, never the process's stderr.

use pyo3::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};

/// The reporters' source, compiled into the extension (no Python files to install beside it).
const SOURCE: &std::ffi::CStr = pyo3::ffi::c_str!(include_str!("progress.py"));

/// Adds `prism._progress` to `sys.modules` (and as the attribute `_progress` of `m`).
pub fn add_module(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let code = PyModule::from_code(m.py(), SOURCE, c"prism/_progress.py", c"prism._progress")?;
    m.add("_progress", code)
}

/// The render's count, written by its workers and read by the polling thread.
#[derive(Default)]
pub struct Counter {
    done: AtomicU64,
    total: AtomicU64,
}

impl Counter {
    /// The render's total (pixels × spp), known once its scene is built.
    pub fn start(&self, total: u64) {
        self.total.store(total, Ordering::Relaxed);
    }

    /// `n` more samples finished (a worker, at the end of a tile).
    pub fn add(&self, n: u64) {
        self.done.fetch_add(n, Ordering::Relaxed);
    }

    fn read(&self) -> (u64, u64) {
        let total = self.total.load(Ordering::Relaxed);
        (self.done.load(Ordering::Relaxed), total)
    }
}

/// The Python reporter for `prism.render`'s `progress` argument, and what it last saw.
pub struct Reporter {
    obj: Option<Py<PyAny>>,
    shown: (u64, u64),
}

impl Reporter {
    /// The reporter for `progress` (True, False, None or a callable; see progress.py).
    pub fn new(py: Python<'_>, progress: Option<&Bound<'_, PyAny>>) -> PyResult<Reporter> {
        let arg = match progress {
            Some(p) => p.clone(),
            None => pyo3::types::PyBool::new(py, true).to_owned().into_any(),
        };
        let r = py
            .import("prism._progress")?
            .call_method1("reporter", (arg,))?;
        Ok(Reporter {
            obj: (!r.is_none()).then(|| r.unbind()),
            shown: (0, 0),
        })
    }

    /// Hands the count to the reporter when it moved (and once the total is known); an
    /// exception the reporter raises is the caller's to stop the render with.
    pub fn poll(&mut self, py: Python<'_>, c: &Counter) -> PyResult<()> {
        let now = c.read();
        if now == self.shown || now.1 == 0 {
            return Ok(());
        }
        self.shown = now;
        match &self.obj {
            Some(o) => o.call_method1(py, "update", now).map(drop),
            None => Ok(()),
        }
    }

    /// Ends the bar: filled when the render `finished`, left where it stopped otherwise. An
    /// error here cannot undo a finished render, so it is reported as unraisable and dropped.
    pub fn close(&mut self, py: Python<'_>, c: &Counter, finished: bool) {
        let last = if finished { self.poll(py, c) } else { Ok(()) };
        if let Some(o) = self.obj.take() {
            let closed = last.and_then(|_| o.call_method1(py, "close", (finished,)).map(drop));
            if let Err(e) = closed {
                e.write_unraisable(py, None);
            }
        }
    }
}
