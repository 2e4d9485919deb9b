//! `rollstack.cylinders.sweep_pair` and `sweep_push`: the transport of two touching
//! cylinders at each inclination (Figure 3.14) and the push at which a rim starts to
//! slip (`cylinders::studies::pair`, the library of `rollstack cylinder sweep
//! pair|push`), in parallel on rayon with the GIL released, rows in input order.

use crate::cylinders::{check_pair_theta, check_pair_time, check_steps};
use crate::{guard, sweep_values, value_error};
use cylinders::studies::pair::{pair_sweep_row_until, push_row_until, PairSettings, PushRow};
use cylinders::transport::SpinProfile;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::sync::atomic::AtomicBool;

/// The rows of `row` at each inclination of `thetas`, run with `settings(ϑ)`, in
/// parallel: every ϑ is checked first (its range, then the system the library builds,
/// naming the one refused), then the time guard of `runs_per_row` runs per ϑ unless
/// `force`. `row` ends its runs after their current step once its flag is set (Ctrl-C).
fn pair_rows<'py, R: Send + serde::Serialize>(
    py: Python<'py>,
    thetas: &[f64],
    settings: impl Fn(f64) -> PairSettings + Sync + Send,
    runs_per_row: usize,
    force: bool,
    row: impl Fn(&PairSettings, &AtomicBool) -> R + Sync + Send,
) -> PyResult<Bound<'py, PyAny>> {
    for &theta in thetas {
        let s = settings(theta);
        check_pair_theta(theta, &s.cylinder)?;
        s.system()
            .map_err(|e| value_error(format!("theta {}: {e}", input::Short(theta))))?;
    }
    check_pair_time(&settings(thetas[0]), thetas.len(), runs_per_row, force)?;
    let cancel = AtomicBool::new(false);
    crate::parallel_rows(py, thetas, &cancel, |&theta| row(&settings(theta), &cancel))
}

/// Rows of Figure 3.14 (`studies::pair::pair_sweep_row`), one per ϑ of `theta`; each
/// row as the CLI's `cylinder sweep pair --json`.
#[pyfunction]
#[pyo3(signature = (theta, dt = 2e-3, steps = 2000, spin = -6.0 * std::f64::consts::PI, force = false))]
fn cylinders_sweep_pair<'py>(
    py: Python<'py>,
    theta: &Bound<'py, PyAny>,
    dt: f64,
    steps: usize,
    spin: f64,
    force: bool,
) -> PyResult<Bound<'py, PyAny>> {
    guard(|| {
        let thetas = sweep_values("theta", theta)?;
        check_steps(dt, steps)?;
        input::finite("spin", spin).map_err(value_error)?;
        let settings = |theta| PairSettings {
            dt,
            steps,
            spin: SpinProfile::constant(spin),
            time_bound: input::watchdog::time_bound(force),
            ..PairSettings::thesis(theta)
        };
        pair_rows(py, &thetas, settings, 1, force, pair_sweep_row_until)
    })
}

/// Rows of the slip onset under a push (`studies::pair::push_row`), one per ϑ of
/// `theta`, the pushes of `push` tried in order; each row as the CLI's `cylinder sweep
/// push --json`.
#[pyfunction]
#[pyo3(signature = (theta, push, mu_floor = 0.2, dt = 2e-3, steps = 100, force = false))]
fn cylinders_sweep_push<'py>(
    py: Python<'py>,
    theta: &Bound<'py, PyAny>,
    push: &Bound<'py, PyAny>,
    mu_floor: f64,
    dt: f64,
    steps: usize,
    force: bool,
) -> PyResult<Bound<'py, PyAny>> {
    guard(|| {
        let thetas = sweep_values("theta", theta)?;
        let pushes = sweep_values("push", push)?;
        let away = |w: &[f64]| (w[0] >= 0.0 && w[1] > w[0]) || (w[0] <= 0.0 && w[1] < w[0]);
        if !pushes.windows(2).all(away) {
            return Err(PyValueError::new_err(
                "push must move away from 0: increasing from 0 or more, or decreasing from 0 or less",
            ));
        }
        input::non_negative("mu_floor", mu_floor).map_err(value_error)?;
        check_steps(dt, steps)?;
        let settings = |theta| PairSettings {
            dt,
            steps,
            mu_floor,
            time_bound: input::watchdog::time_bound(force),
            ..PairSettings::thesis(theta)
        };
        // Every push of a row may be run: a bound.
        pair_rows(py, &thetas, settings, pushes.len(), force, |s, cancel| {
            push_row_until(s, &pushes, cancel).unwrap_or_else(|e| PushRow {
                error: Some(e.to_string()),
                ..PushRow::failed(s.theta, mu_floor)
            })
        })
    })
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(cylinders_sweep_pair, m)?)?;
    m.add_function(wrap_pyfunction!(cylinders_sweep_push, m)?)?;
    Ok(())
}
