//! `rollstack.sphere`: the rolling sphere of Ch. 2 (App. B, C) from `holonomy`: the
//! holonomy of a rectangle (2.4.2)–(2.4.6), the inverse planner (2.4.12) returning every
//! rectangle, the Euler three-rectangle planner (§2.5) and kinematic rolling along a
//! closed path (2.3.4)–(2.3.5).

use crate::rotations_py::target_rotation;
use crate::{guard, json_to_py, value_error};
use holonomy::studies::plan::{euler_plan_report, plan_report};
use holonomy::studies::report::holonomy_report;
use holonomy::studies::roll::{roll_report, ClosedPath, PathShape};
use holonomy::{euler_plan, Direction, Integrator, Rectangle};
use numpy::ndarray::{Array1, Array2};
use numpy::IntoPyArray;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rotations::EulerSet;

fn direction(cw: bool) -> Direction {
    if cw {
        Direction::Cw
    } else {
        Direction::Ccw
    }
}

/// The holonomy report of one rectangle (`studies::report::holonomy_report`), as the
/// CLI's `sphere holonomy --json`.
#[pyfunction]
#[pyo3(signature = (theta, phi1, phi2, cw = false))]
fn sphere_holonomy<'py>(
    py: Python<'py>,
    theta: f64,
    phi1: f64,
    phi2: f64,
    cw: bool,
) -> PyResult<Bound<'py, PyAny>> {
    guard(|| {
        let r = Rectangle::new(theta, phi1, phi2, direction(cw)).map_err(value_error)?;
        json_to_py(py, &holonomy_report(&r))
    })
}

/// Every rectangle whose holonomy is the rotation by `angle` about `axis`
/// (`studies::plan::plan_report`), as the CLI's `sphere plan --json`.
#[pyfunction]
fn sphere_plan<'py>(py: Python<'py>, angle: f64, axis: [f64; 3]) -> PyResult<Bound<'py, PyAny>> {
    guard(|| {
        let target = target_rotation(angle, axis)?;
        let report = plan_report(&target).map_err(value_error)?;
        json_to_py(py, &report)
    })
}

/// The Euler three-rectangle plan (`euler_plan`, `studies::plan::euler_plan_report`),
/// as the CLI's `sphere euler-plan --json`.
#[pyfunction]
fn sphere_euler_plan<'py>(
    py: Python<'py>,
    set: &str,
    angles: [f64; 3],
) -> PyResult<Bound<'py, PyAny>> {
    guard(|| {
        let set = EulerSet::from_name(set).map_err(value_error)?;
        let plan = euler_plan(set, angles).map_err(value_error)?;
        json_to_py(py, &euler_plan_report(&plan))
    })
}

/// Rolls once along a closed path (`studies::roll::roll_report`): returns the report
/// (the CLI's `sphere roll --json`) and the trajectory as arrays: s (N,), centre and
/// marked point (N, 3), orientation quaternions (N, 4), scalar first.
#[pyfunction]
#[pyo3(signature = (theta = None, phi1 = None, phi2 = None, cw = false, circle = None, polygon = None, steps = 400, integrator = "exact"))]
fn sphere_roll<'py>(
    py: Python<'py>,
    theta: Option<f64>,
    phi1: Option<f64>,
    phi2: Option<f64>,
    cw: bool,
    circle: Option<f64>,
    polygon: Option<Vec<[f64; 2]>>,
    steps: usize,
    integrator: &str,
) -> PyResult<Bound<'py, PyDict>> {
    guard(|| {
        let integrator = match integrator {
            "exact" => Integrator::Exact,
            "rk4" => Integrator::Rk4,
            other => {
                return Err(PyValueError::new_err(format!(
                    "integrator must be 'exact' or 'rk4', got {other:?}"
                )))
            }
        };
        let shape = match (circle, polygon, theta, phi1, phi2) {
            (Some(radius), None, None, None, None) => PathShape::Circle {
                radius,
                direction: direction(cw),
            },
            (None, Some(vertices), None, None, None) => PathShape::Polygon(vertices),
            (None, None, Some(theta), Some(phi1), Some(phi2)) => PathShape::Rectangle(
                Rectangle::new(theta, phi1, phi2, direction(cw)).map_err(value_error)?,
            ),
            _ => {
                return Err(PyValueError::new_err(
                    "give one path: theta, phi1 and phi2 (a rectangle), circle=radius, or polygon=[[x, y], ...]",
                ))
            }
        };
        let closed = ClosedPath::new(&shape).map_err(value_error)?;
        let (report, trajectory) = roll_report(&closed, integrator, steps).map_err(value_error)?;
        let n = trajectory.samples.len();
        let s: Vec<f64> = trajectory.samples.iter().map(|x| x.s).collect();
        let centre: Vec<f64> = trajectory.samples.iter().flat_map(|x| x.centre).collect();
        let marked: Vec<f64> = trajectory
            .samples
            .iter()
            .flat_map(|x| x.marked_point)
            .collect();
        let orientation: Vec<f64> = trajectory
            .samples
            .iter()
            .flat_map(|x| {
                let q = x.orientation.quaternion();
                [q.w, q.i, q.j, q.k]
            })
            .collect();
        let shape_err = |e: numpy::ndarray::ShapeError| value_error(e);
        let out = PyDict::new(py);
        out.set_item("report", json_to_py(py, &report)?)?;
        out.set_item("label", &closed.label)?;
        out.set_item("s", Array1::from_vec(s).into_pyarray(py))?;
        out.set_item(
            "centre",
            Array2::from_shape_vec((n, 3), centre)
                .map_err(shape_err)?
                .into_pyarray(py),
        )?;
        out.set_item(
            "marked_point",
            Array2::from_shape_vec((n, 3), marked)
                .map_err(shape_err)?
                .into_pyarray(py),
        )?;
        out.set_item(
            "orientation",
            Array2::from_shape_vec((n, 4), orientation)
                .map_err(shape_err)?
                .into_pyarray(py),
        )?;
        Ok(out)
    })
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(sphere_holonomy, m)?)?;
    m.add_function(wrap_pyfunction!(sphere_plan, m)?)?;
    m.add_function(wrap_pyfunction!(sphere_euler_plan, m)?)?;
    m.add_function(wrap_pyfunction!(sphere_roll, m)?)?;
    Ok(())
}
