//! `rollstack.blocks.painleve`, `rollstack.blocks.work_precision` and
//! `rollstack.blocks.converge`: Painlevé's paradoxes for one block (App. I, ERRATA 18),
//! speed against error for block stacks, NSGA beside Moreau–Jean, and a scene's
//! convergence verdicts, from `blockstack::studies` (the library functions of
//! `rollstack blocks painleve`, `blocks work-precision` and `blocks converge`).

use crate::blocks::{check_time_bound, PyScene};
use crate::{guard, json_to_py, value_error};
use blockstack::painleve::b_grid;
use blockstack::simulation::RunOptions;
use blockstack::studies::convergence::{Job, Reference, Settings, Study};
use blockstack::studies::painleve::painleve_report;
use blockstack::studies::work_precision::{stack_work_precision_until, StackBenchmark};
use numpy::ndarray::{Array1, Array2};
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

/// The Painlevé analysis of a block of aspect w/h (`studies::painleve::painleve_report`,
/// the CLI's `blocks painleve --json`) and the b-sign grid of Figure I.2(b)
/// (`painleve::b_grid`, the CLI's painleve_b_grid.csv): `theta` (grid,) rad, `mu`
/// (grid,), `b_slip_positive` and `b_slip_negative` (grid of μ, grid of ϑ), and
/// `admissible` (grid,) bool.
#[pyfunction]
#[pyo3(signature = (aspect, mu = 0.2, mu_max = 3.0, grid = 121))]
fn blocks_painleve<'py>(
    py: Python<'py>,
    aspect: f64,
    mu: f64,
    mu_max: f64,
    grid: usize,
) -> PyResult<Bound<'py, PyDict>> {
    guard(|| {
        input::positive("aspect", aspect).map_err(value_error)?;
        input::non_negative("mu", mu).map_err(value_error)?;
        input::positive("mu_max", mu_max).map_err(value_error)?;
        if grid < 2 {
            return Err(value_error(format!("grid must be at least 2, got {grid}")));
        }
        let report = painleve_report(aspect, mu).map_err(value_error)?;
        let samples =
            b_grid(aspect, mu_max, grid, grid).map_err(|e| value_error(format!("grid: {e}")))?;
        // Samples run over ϑ fastest, then over μ: row j of the arrays is μ_j.
        let column = |f: fn(&blockstack::painleve::BSample) -> f64| {
            Array2::from_shape_vec((grid, grid), samples.iter().map(f).collect())
                .map_err(value_error)
        };
        let out = PyDict::new(py);
        out.set_item("report", json_to_py(py, &report)?)?;
        let first_row = &samples[..grid];
        let theta: Vec<f64> = first_row.iter().map(|s| s.theta).collect();
        let admissible: Vec<bool> = first_row.iter().map(|s| s.admissible).collect();
        let mu_axis: Vec<f64> = samples.iter().step_by(grid).map(|s| s.mu).collect();
        out.set_item("theta", Array1::from_vec(theta).into_pyarray(py))?;
        out.set_item("mu", Array1::from_vec(mu_axis).into_pyarray(py))?;
        out.set_item("b_slip_positive", column(|s| s.b_plus)?.into_pyarray(py))?;
        out.set_item("b_slip_negative", column(|s| s.b_minus)?.into_pyarray(py))?;
        out.set_item("admissible", Array1::from_vec(admissible).into_pyarray(py))?;
        Ok(out)
    })
}

/// Speed against error for a block-stack benchmark
/// (`studies::work_precision::stack_work_precision`), with the GIL released and Ctrl-C
/// checked; the CLI's `blocks work-precision --json`. The reference run is checked
/// against the ten-minute time guard first, unless `force`.
#[pyfunction]
#[pyo3(signature = (system = "block", dts = vec![1e-2, 5e-3, 2e-3, 1e-3, 5e-4], reference_factor = 16.0, repeat = 3, force = false))]
fn blocks_work_precision<'py>(
    py: Python<'py>,
    system: &str,
    dts: Vec<f64>,
    reference_factor: f64,
    repeat: usize,
    force: bool,
) -> PyResult<Bound<'py, PyAny>> {
    guard(|| {
        let bench = StackBenchmark::ALL
            .into_iter()
            .find(|b| b.name() == system)
            .ok_or_else(|| {
                value_error(format!(
                    "system must be 'block', 'column' or 'lire', got {system:?}"
                ))
            })?;
        check_study_input(&dts, reference_factor, repeat)?;
        let smallest = dts.iter().copied().fold(f64::INFINITY, f64::min);
        let reference = bench
            .scene(smallest / reference_factor)
            .map_err(|e| value_error(format!("dts: {e}")))?;
        check_time_bound(
            std::slice::from_ref(&reference),
            &RunOptions::default(),
            force,
            "take a smaller reference_factor or larger dts",
        )?;
        let cancel = AtomicBool::new(false);
        let study = crate::interruptible(py, &cancel, || {
            stack_work_precision_until(bench, &dts, reference_factor, repeat, &cancel)
                .map_err(|e| crate::solver_error(e.to_string()))
        })?;
        json_to_py(py, &study)
    })
}

/// A convergence study of `scene` (`studies::convergence::Study`): the runs at Δt/2^k,
/// k = 0…`levels`, and `ensemble` perturbed runs per magnitude at the finest Δt, in
/// parallel on rayon with the GIL released and Ctrl-C checked; the report as the CLI's
/// `blocks converge --json` (without `files` and `notes`). Refused up front when
/// estimated to take more than ten minutes, and each run watched, unless `force`.
#[pyfunction]
#[pyo3(signature = (scene, levels = 2, ensemble = 2, t_end = None, force = false))]
fn blocks_converge<'py>(
    py: Python<'py>,
    scene: &PyScene,
    levels: usize,
    ensemble: usize,
    t_end: Option<f64>,
    force: bool,
) -> PyResult<Bound<'py, PyAny>> {
    use rayon::prelude::*;
    guard(|| {
        if let Some(t) = t_end {
            input::positive("t_end", t).map_err(value_error)?;
        }
        let cancel = Arc::new(AtomicBool::new(false));
        let options = RunOptions {
            t_end,
            time_bound: input::watchdog::time_bound(force),
            cancel: Some(cancel.clone()),
            ..RunOptions::default()
        };
        let settings = Settings { levels, ensemble };
        let study = Study::new(scene.scene(), &options, settings, ["levels", "ensemble"])
            .map_err(value_error)?;
        let scenes: Vec<blockstack::Scene> = study
            .levels()
            .iter()
            .chain(study.members())
            .map(|j| j.scene.clone())
            .collect();
        let advice = "take fewer levels or a smaller ensemble, shorten t_end";
        check_time_bound(&scenes, study.options(), force, advice)?;
        let report = crate::interruptible(py, &cancel, || {
            let run = |jobs: &[Job], reference: Option<&Reference>| {
                jobs.par_iter()
                    .map(|j| study.run(j, reference, |_| {}))
                    .collect::<Result<Vec<_>, _>>()
                    .map_err(value_error)
            };
            let levels = run(study.levels(), None)?;
            let reference = study.reference(&levels).cloned();
            let members = run(study.members(), reference.as_ref())?;
            Ok(study.report(levels, members))
        })?;
        json_to_py(py, &report)
    })
}

/// Refuses the inputs of a work-precision study that no run can take, naming the
/// parameter: no `dts` or one that is not positive and finite, a `reference_factor`
/// under 1, a `repeat` outside 1..=1000 (`blocks.work_precision`,
/// `cylinders.work_precision`).
///
/// # Errors
/// The first bad input.
pub(crate) fn check_study_input(dts: &[f64], reference_factor: f64, repeat: usize) -> PyResult<()> {
    if dts.is_empty() {
        return Err(value_error("dts must hold at least one time step"));
    }
    for &dt in dts {
        input::positive("dts", dt).map_err(value_error)?;
    }
    input::finite("reference_factor", reference_factor).map_err(value_error)?;
    if reference_factor < 1.0 {
        return Err(value_error(format!(
            "reference_factor must be at least 1, got {}",
            input::Short(reference_factor)
        )));
    }
    if !(1..=1000).contains(&repeat) {
        return Err(value_error(format!(
            "repeat must be in 1..=1000, got {repeat}"
        )));
    }
    Ok(())
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(blocks_converge, m)?)?;
    m.add_function(wrap_pyfunction!(blocks_painleve, m)?)?;
    m.add_function(wrap_pyfunction!(blocks_work_precision, m)?)?;
    Ok(())
}
