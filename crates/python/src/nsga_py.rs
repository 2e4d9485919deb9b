//! `rollstack.nsga`: the benchmark systems with known answers (the paper's rotating
//! bouncing ball, cases 1–4) and the work-precision runs (§4.2, App. H), from
//! `nsga::studies`.

use crate::{guard, json_to_py, value_error};
use nsga::studies::ball::{ball_report, Scheme};
use nsga::studies::work_precision::{work_precision_until, WorkPrecisionSystem};
use nsga::Prox;
use numpy::ndarray::{Array1, Array2};
use numpy::IntoPyArray;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::atomic::AtomicBool;

fn check_dt(dt: f64) -> PyResult<()> {
    if !(dt.is_finite() && dt > 0.0 && dt <= 0.1) {
        return Err(PyValueError::new_err(format!(
            "dt must be in (0, 0.1] s, got {dt}"
        )));
    }
    Ok(())
}

fn check_rho_inf(rho_inf: f64) -> PyResult<()> {
    if !(0.0..=1.0).contains(&rho_inf) {
        return Err(PyValueError::new_err(format!(
            "rho_inf must be in [0, 1], got {rho_inf}"
        )));
    }
    Ok(())
}

/// The rotating bouncing ball (`studies::ball::ball_report`): the report (the CLI's
/// `nsga ball --json`) and the trajectory: t (N,), q and u (N, 3), p_n (N,),
/// iterations (N,).
#[pyfunction]
#[pyo3(signature = (case, dt = 2e-3, scheme = "nsga", rho_inf = 0.5, prox_constant = None))]
fn nsga_ball<'py>(
    py: Python<'py>,
    case: u8,
    dt: f64,
    scheme: &str,
    rho_inf: f64,
    prox_constant: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    guard(|| {
        check_dt(dt)?;
        check_rho_inf(rho_inf)?;
        let scheme = match scheme {
            "nsga" => Scheme::Nsga,
            "moreau" => Scheme::Moreau,
            other => {
                return Err(PyValueError::new_err(format!(
                    "scheme must be 'nsga' or 'moreau', got {other:?}"
                )))
            }
        };
        let prox = match prox_constant {
            Some(r) => Prox::Constant(input::positive("prox_constant", r).map_err(value_error)?),
            None => Prox::Scaled(1.0),
        };
        let (report, run) = ball_report(case, scheme, dt, rho_inf, prox).map_err(|e| match e {
            nsga::StepError::InvalidInput(m) => PyValueError::new_err(m),
            e => crate::solver_error(e.to_string()),
        })?;
        let n = run.samples.len();
        let shape_err = |e: numpy::ndarray::ShapeError| value_error(e);
        let out = PyDict::new(py);
        out.set_item("report", json_to_py(py, &report)?)?;
        let t: Vec<f64> = run.samples.iter().map(|s| s.t).collect();
        let q: Vec<f64> = run.samples.iter().flat_map(|s| s.q).collect();
        let u: Vec<f64> = run.samples.iter().flat_map(|s| s.u).collect();
        let p_n: Vec<f64> = run.samples.iter().map(|s| s.p_n).collect();
        let its: Vec<i64> = run
            .samples
            .iter()
            .map(|s| i64::try_from(s.iterations).unwrap_or(i64::MAX))
            .collect();
        out.set_item("t", Array1::from_vec(t).into_pyarray(py))?;
        out.set_item(
            "q",
            Array2::from_shape_vec((n, 3), q)
                .map_err(shape_err)?
                .into_pyarray(py),
        )?;
        out.set_item(
            "u",
            Array2::from_shape_vec((n, 3), u)
                .map_err(shape_err)?
                .into_pyarray(py),
        )?;
        out.set_item("p_n", Array1::from_vec(p_n).into_pyarray(py))?;
        out.set_item("iterations", Array1::from_vec(its).into_pyarray(py))?;
        Ok(out)
    })
}

/// Error against CPU time (`studies::work_precision::work_precision`) for one benchmark
/// system, NSGA for each ρ∞ beside Moreau–Jean, with the GIL released: rows, orders and
/// reference as the CLI's `nsga work-precision --json`.
#[pyfunction]
#[pyo3(signature = (system, dts = vec![0.008, 0.004, 0.002, 0.001, 0.0005, 0.00025], rho_inf = vec![0.0, 0.5, 0.8, 1.0], repeat = 3))]
fn nsga_work_precision<'py>(
    py: Python<'py>,
    system: &str,
    dts: Vec<f64>,
    rho_inf: Vec<f64>,
    repeat: usize,
) -> PyResult<Bound<'py, PyAny>> {
    guard(|| {
        let system = match system {
            "ball" => WorkPrecisionSystem::Ball,
            "oscillator" => WorkPrecisionSystem::Oscillator,
            "incline" => WorkPrecisionSystem::Incline,
            other => {
                return Err(PyValueError::new_err(format!(
                    "system must be 'ball', 'oscillator' or 'incline', got {other:?}"
                )))
            }
        };
        for &dt in &dts {
            check_dt(dt)?;
        }
        for &r in &rho_inf {
            check_rho_inf(r)?;
        }
        if !(1..=1000).contains(&repeat) {
            return Err(PyValueError::new_err(format!(
                "repeat must be in 1..=1000, got {repeat}"
            )));
        }
        // On a worker thread, so that Ctrl-C is seen while it runs: the study stops
        // between two of its runs (each a fraction of a second).
        let cancel = AtomicBool::new(false);
        let study = crate::interruptible(py, &cancel, || {
            Ok(work_precision_until(
                system, &dts, &rho_inf, repeat, &cancel,
            ))
        })?
        .map_err(|e| match e {
            nsga::StepError::InvalidInput(m) => PyValueError::new_err(m),
            e => crate::solver_error(e.to_string()),
        })?;
        json_to_py(py, &study)
    })
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(nsga_ball, m)?)?;
    m.add_function(wrap_pyfunction!(nsga_work_precision, m)?)?;
    Ok(())
}
