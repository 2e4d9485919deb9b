//! Python bindings of rollstack: the compiled module `rollstack._rollstack`, which the
//! Python package `rollstack` (crates/python/python/rollstack) re-exports with docstrings,
//! result objects and type stubs.
//!
//! Every function here calls a library function of the workspace and converts its input
//! and output; none computes physics of its own. The conventions:
//!
//! - bad input is a `ValueError` carrying the library's message (`value_error`);
//! - a Rust panic never crosses into Python: every entry point runs inside `guard`,
//!   which turns it into a `RuntimeError`;
//! - reports are handed over as the JSON the command line prints (`--json`), parsed by
//!   Python's `json` (`json_to_py`), so that a Python result equals the CLI's to the
//!   last printed digit; trajectories are numpy arrays;
//! - long runs check for Ctrl-C between steps (`Python::check_signals`) and
//!   sweeps run on rayon with the GIL released.

mod blocks;
mod cylinders;
mod nsga_py;
mod rotations_py;
mod sphere;

use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use serde::Serialize;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, Ordering};

/// Runs `f`, turning a panic into a Python `RuntimeError` instead of letting it cross
/// into Python.
pub(crate) fn guard<T>(f: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(result) => result,
        Err(payload) => {
            let message = payload
                .downcast_ref::<&str>()
                .map(|s| (*s).to_owned())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".to_owned());
            Err(PyRuntimeError::new_err(format!(
                "internal error in rollstack (please report it): {message}"
            )))
        }
    }
}

/// How often a caller checks for Ctrl-C while its worker runs ([`interruptible`]).
pub(crate) const SIGNAL_POLL: std::time::Duration = std::time::Duration::from_millis(20);

/// Runs `work` on a scoped worker thread while this thread, which holds the GIL between
/// naps without it, checks for Ctrl-C every [`SIGNAL_POLL`]. A `KeyboardInterrupt` sets
/// `cancel` (which `work` watches, ending soon after) and is raised once the worker has
/// stopped. A panic does not cross into Python: its message comes back as a
/// `RuntimeError`.
pub(crate) fn interruptible<T: Send>(
    py: Python<'_>,
    cancel: &AtomicBool,
    work: impl FnOnce() -> PyResult<T> + Send,
) -> PyResult<T> {
    std::thread::scope(|scope| {
        let worker = scope.spawn(|| guard(work));
        while !worker.is_finished() {
            if let Err(interrupt) = py.check_signals() {
                cancel.store(true, Ordering::Relaxed);
                py.detach(|| worker.join()).ok();
                return Err(interrupt);
            }
            py.detach(|| std::thread::sleep(SIGNAL_POLL));
        }
        py.detach(|| worker.join())
            .unwrap_or_else(|_| Err(PyRuntimeError::new_err("the worker thread stopped")))
    })
}

pyo3::create_exception!(
    rollstack,
    SolverError,
    pyo3::exceptions::PyRuntimeError,
    "A run the solver stopped before its end: the message is the library's; `result` \
     (when set) holds everything computed up to the failing step."
);

/// A solver failure as a `rollstack.SolverError`.
pub(crate) fn solver_error(message: String) -> PyErr {
    SolverError::new_err(message)
}

/// A library error as a Python `ValueError` with the library's message.
pub(crate) fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// A serializable report as the Python object `json.loads` makes of the JSON the
/// command line prints for it.
pub(crate) fn json_to_py<'py>(
    py: Python<'py>,
    value: &impl Serialize,
) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(value).map_err(value_error)?;
    py.import("json")?.call_method1("loads", (text,))
}

/// The compiled part of the `rollstack` Python package.
#[pymodule]
fn _rollstack(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("SolverError", m.py().get_type::<SolverError>())?;
    blocks::register(m)?;
    sphere::register(m)?;
    rotations_py::register(m)?;
    cylinders::register(m)?;
    nsga_py::register(m)?;
    Ok(())
}
