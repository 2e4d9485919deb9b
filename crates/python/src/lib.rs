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
//! - long runs work on a thread of their own with the GIL released while the caller
//!   checks for Ctrl-C (`interruptible`), and end within the current step on it
//!   (`nsga::Interrupt`); sweeps run on rayon.

mod block_studies;
mod blocks;
mod cylinder_sweeps;
mod cylinders;
mod excitation;
mod fragility_py;
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
    match interruptible_keeping(py, cancel, work) {
        (_, Some(interrupt)) => Err(interrupt),
        (result, None) => result,
    }
}

/// [`interruptible`] that keeps what `work` returns after a Ctrl-C: its result, and the
/// `KeyboardInterrupt` for the caller to raise once it has kept that result (None when
/// `work` ended by itself).
pub(crate) fn interruptible_keeping<T: Send>(
    py: Python<'_>,
    cancel: &AtomicBool,
    work: impl FnOnce() -> PyResult<T> + Send,
) -> (PyResult<T>, Option<PyErr>) {
    std::thread::scope(|scope| {
        let worker = scope.spawn(|| guard(work));
        let mut interrupt = None;
        while !worker.is_finished() {
            if let Err(e) = py.check_signals() {
                cancel.store(true, Ordering::Relaxed);
                interrupt = Some(e);
                break;
            }
            py.detach(|| std::thread::sleep(SIGNAL_POLL));
        }
        let result = py
            .detach(|| worker.join())
            .unwrap_or_else(|_| Err(PyRuntimeError::new_err("the worker thread stopped")));
        (result, interrupt)
    })
}

/// Runs `row` over `items` in parallel on rayon, in input order, and returns the rows as
/// `json.loads` makes them of the CLI's JSON.
///
/// The rows run on a worker thread while this one checks for Ctrl-C ([`interruptible`]):
/// a `KeyboardInterrupt` sets `cancel`, which keeps rows from starting and which `row`
/// watches to end the runs already started after their current step.
pub(crate) fn parallel_rows<'py, P: Sync, R: Send + Serialize>(
    py: Python<'py>,
    items: &[P],
    cancel: &AtomicBool,
    row: impl Fn(&P) -> R + Sync + Send,
) -> PyResult<Bound<'py, PyAny>> {
    use rayon::prelude::*;
    let rows = interruptible(py, cancel, || {
        Ok(items
            .par_iter()
            .map(|p| (!cancel.load(Ordering::Relaxed)).then(|| row(p)))
            .collect::<Vec<_>>())
    })?;
    let rows: Vec<R> = rows.into_iter().flatten().collect();
    json_to_py(py, &rows)
}

/// The values of a sweep parameter `name`: the CLI's text (`"10deg:40deg:10deg"`,
/// `"0.1,0.2"`, `"pi/6"`; `input::text::parse_values`), one number, or a sequence of
/// numbers, each finite.
pub(crate) fn sweep_values(name: &str, given: &Bound<'_, PyAny>) -> PyResult<Vec<f64>> {
    let values = if let Ok(text) = given.extract::<String>() {
        input::text::parse_values(&text)
            .map_err(|e| PyValueError::new_err(format!("{name}: {e}")))?
    } else if let Ok(one) = given.extract::<f64>() {
        vec![one]
    } else {
        given.extract::<Vec<f64>>().map_err(|_| {
            PyValueError::new_err(format!(
                "{name} must be a number, a sequence of numbers or a text like \"0.1:0.5:0.1\", got {}",
                given.get_type().name().map_or_else(|_| "?".to_owned(), |n| n.to_string())
            ))
        })?
    };
    if values.is_empty() {
        return Err(PyValueError::new_err(format!("{name} holds no value")));
    }
    for &v in &values {
        input::finite(name, v).map_err(value_error)?;
    }
    Ok(values)
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
    excitation::register(m)?;
    block_studies::register(m)?;
    fragility_py::register(m)?;
    sphere::register(m)?;
    rotations_py::register(m)?;
    cylinders::register(m)?;
    cylinder_sweeps::register(m)?;
    nsga_py::register(m)?;
    Ok(())
}
