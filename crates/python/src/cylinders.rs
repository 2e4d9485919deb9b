//! `rollstack.cylinders`: inclined rolling cylinders (Ch. 3, App. D–F) from `cylinders`:
//! the support statics (3.3.8)–(3.3.20), the holonomy of §3.4 (rectangles and circles
//! traced by the contact point), the Frobenius test (App. D) on the bundled
//! constraint systems (App. F) and on a Pfaffian system the user gives as a Python
//! callable q ↦ W(q).

use crate::{guard, json_to_py, value_error};
use blockstack::time_guard::TIME_BOUND_S;
use cylinders::frobenius::{
    report_from, skew_matrices_central_difference, PfaffianSystem, INTEGRABILITY_TOLERANCE,
    RANK_TOLERANCE,
};
use cylinders::holonomy::{CirclePath, Direction, PathCase, RectanglePath};
use cylinders::kinematics::{check_point_contact, Cylinder};
use cylinders::rolling::RollingTrace;
use cylinders::studies::frobenius::{
    integrability_report, ConstraintSystem, FrobeniusCase, PairConfiguration,
};
use cylinders::studies::holonomy::{circle_report, rectangle_report, RollSettings};
use cylinders::studies::pair::PairSettings;
use cylinders::studies::pair_cost::pair_cost;
use cylinders::studies::statics::statics_figures;
use cylinders::studies::support::support_report;
use cylinders::CylinderError;
use nalgebra::{DMatrix, RealField};
use numpy::ndarray::{Array1, Array2};
use numpy::{IntoPyArray, PyReadonlyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::cell::RefCell;

/// The support report (`studies::support::support_report`, with the weight when `mass`
/// is given), as the CLI's `cylinder support --json`.
#[pyfunction]
#[pyo3(signature = (theta, r_over_h = 0.1, mu = 0.2, mass = None, gravity = 9.81))]
fn cylinders_support<'py>(
    py: Python<'py>,
    theta: f64,
    r_over_h: f64,
    mu: f64,
    mass: Option<f64>,
    gravity: f64,
) -> PyResult<Bound<'py, PyAny>> {
    guard(|| {
        let theta = check_inclination(theta)?;
        input::non_negative("r_over_h", r_over_h).map_err(value_error)?;
        input::non_negative("mu", mu).map_err(value_error)?;
        let mut report = support_report(theta, r_over_h, mu).map_err(value_error)?;
        if let Some(mass) = mass {
            report = report.with_weight(mass, gravity).map_err(value_error)?;
        }
        json_to_py(py, &report)
    })
}

/// The support-force curves of Figures 3.3, 3.4, 3.5, 3.7 and 3.8
/// (`studies::statics::statics_figures`): what `cylinder statics` writes to its CSV
/// files, as one dict.
#[pyfunction]
#[pyo3(signature = (r_over_h = 0.1, mu = 0.2, points = 721))]
fn cylinders_statics<'py>(
    py: Python<'py>,
    r_over_h: f64,
    mu: f64,
    points: usize,
) -> PyResult<Bound<'py, PyAny>> {
    guard(|| {
        input::non_negative("r_over_h", r_over_h).map_err(value_error)?;
        input::non_negative("mu", mu).map_err(value_error)?;
        let figures = statics_figures(r_over_h, mu, points).map_err(value_error)?;
        json_to_py(py, &figures)
    })
}

/// Refuses a time step or step count of the pair's runs under their Python names,
/// before the runs of each inclination would refuse them under the library's.
pub(crate) fn check_steps(dt: f64, steps: usize) -> PyResult<()> {
    input::positive("dt", dt).map_err(value_error)?;
    if steps == 0 {
        return Err(PyValueError::new_err("steps must be at least 1, got 0"));
    }
    Ok(())
}

/// Refuses an inclination `theta` (rad) outside (0, π/2), where the cylinder touches the
/// plane at one rim point (§3.2), naming the parameter (the library names its ϑ).
fn check_inclination(theta: f64) -> PyResult<f64> {
    input::finite("theta", theta).map_err(value_error)?;
    if theta > 0.0 && theta < std::f64::consts::FRAC_PI_2 {
        return Ok(theta);
    }
    Err(PyValueError::new_err(format!(
        "theta = {} rad is outside (0, π/2): the point-contact assumption of §3.2 fails \
         (at 0 the base lies flat, at π/2 the side does)",
        input::Short(theta)
    )))
}

/// The library's refusals of a rolled path that name its own parameters, under the
/// function's: a path too long for `max_step` (the library names its max_step, but the
/// path's length comes from `path_params` as much) and a trace that overflows at a
/// `theta` a few ulps from 0 or π/2 (the library names its ϑ).
fn name_roll_params(e: CylinderError, path_params: &str) -> PyErr {
    match e {
        CylinderError::Input(input::InputError::TooLarge {
            value,
            needed,
            what,
            limit,
            ..
        }) => PyValueError::new_err(format!(
            "{path_params} with max_step = {} need {needed:.1e} {what}, more than the \
             {limit:.0e} allowed: take a shorter path or a larger max_step",
            input::Short(value)
        )),
        CylinderError::NotFinite(theta) => PyValueError::new_err(format!(
            "theta = {} rad is too close to 0 or π/2 for double precision: the rolled trace \
             is not finite",
            input::Short(theta)
        )),
        e => value_error(e),
    }
}

/// Refuses an inclination `theta` (rad) of the pair outside (arctan(2r/h), π/2), naming
/// the parameter (the library names it "inclination ϑ").
pub(crate) fn check_pair_theta(theta: f64, cylinder: &Cylinder) -> PyResult<()> {
    let (lo, hi) = cylinders::transport::inclination_range(cylinder);
    input::finite("theta", theta).map_err(value_error)?;
    if theta > lo && theta < hi {
        return Ok(());
    }
    Err(PyValueError::new_err(format!(
        "theta {} rad is outside ({lo:.4}, {hi:.4}) = (arctan(2r/h), π/2), the inclinations of the pair",
        input::Short(theta)
    )))
}

/// Refuses `rows` rows of `runs_per_row` runs of `settings` (a row's runs one after
/// another) estimated to take longer than the ten-minute time guard
/// (`studies::pair_cost`, measured on the first steps), unless `force`.
pub(crate) fn check_pair_time(
    settings: &PairSettings,
    rows: usize,
    runs_per_row: usize,
    force: bool,
) -> PyResult<()> {
    if force {
        return Ok(());
    }
    match pair_cost(settings, rows, runs_per_row, rayon::current_num_threads()) {
        Some(cost) if cost.seconds > TIME_BOUND_S => Err(PyValueError::new_err(format!(
            "{cost}, more than {TIME_BOUND_S} s: take fewer steps or values, or pass force=True"
        ))),
        _ => Ok(()),
    }
}

/// The Frobenius test of a bundled constraint system
/// (`studies::frobenius::integrability_report`), as the CLI's `cylinder frobenius --json`.
#[pyfunction]
#[pyo3(signature = (system = "single", config = "generic", theta = 0.4, heading = 0.5, contact_at = None, r = 0.1143, h = 1.2954))]
fn cylinders_frobenius<'py>(
    py: Python<'py>,
    system: &str,
    config: &str,
    theta: f64,
    heading: f64,
    contact_at: Option<f64>,
    r: f64,
    h: f64,
) -> PyResult<Bound<'py, PyAny>> {
    guard(|| {
        let system = match system {
            "single" => ConstraintSystem::Single,
            "pair7" => ConstraintSystem::Pair7,
            "pair9" => ConstraintSystem::Pair9,
            other => {
                return Err(PyValueError::new_err(format!(
                    "system must be 'single', 'pair7' or 'pair9', got {other:?}"
                )))
            }
        };
        let configuration = match config {
            "generic" => PairConfiguration::Generic,
            "touching" => PairConfiguration::Touching,
            other => {
                return Err(PyValueError::new_err(format!(
                    "config must be 'generic' or 'touching', got {other:?}"
                )))
            }
        };
        // Checked here so that the errors name the parameters, not the library's ϑ, r,
        // h and contact position.
        let theta = check_inclination(theta)?;
        input::positive("r", r).map_err(value_error)?;
        input::positive("h", h).map_err(value_error)?;
        if let (Some(at), false) = (contact_at, system == ConstraintSystem::Single) {
            if input::finite("contact_at", at).map_err(value_error)?.abs() >= 0.5 * h {
                return Err(PyValueError::new_err(format!(
                    "contact_at = {} is outside (−h/2, h/2) = ({}, {}): the cylinders touch \
                     along their length",
                    input::Short(at),
                    input::Short(-0.5 * h),
                    input::Short(0.5 * h)
                )));
            }
        }
        let report = integrability_report(&FrobeniusCase {
            system,
            configuration,
            cylinder: Cylinder::new(r, h).map_err(value_error)?,
            theta,
            heading,
            contact_at,
        })
        .map_err(|e| match e {
            CylinderError::ContactOfSingle => PyValueError::new_err(
                "contact_at is where the two cylinders of system='pair7' or 'pair9' touch; \
                 system='single' has one cylinder: leave contact_at out",
            ),
            e => value_error(e),
        })?;
        json_to_py(py, &report)
    })
}

/// A Pfaffian system whose W(q) a Python callable computes (real scalars only: the
/// test then differentiates by central differences).
struct CallableSystem<'py> {
    py: Python<'py>,
    function: Bound<'py, PyAny>,
    n: usize,
    m: usize,
    error: RefCell<Option<PyErr>>,
}

impl CallableSystem<'_> {
    fn evaluate(&self, q: &[f64]) -> PyResult<DMatrix<f64>> {
        let result = self.function.call1((q.to_vec(),))?;
        let numpy = self.py.import("numpy")?;
        let array = numpy.call_method1("asarray", (result, "float64"))?;
        let w: PyReadonlyArray2<'_, f64> = array.extract().map_err(|_| {
            PyValueError::new_err("the Pfaffian system must return a 2-D array W(q)")
        })?;
        let w = w.as_array();
        if w.shape() != [self.m, self.n] {
            return Err(PyValueError::new_err(format!(
                "W(q) has the shape {:?}, expected ({}, {})",
                w.shape(),
                self.m,
                self.n
            )));
        }
        Ok(DMatrix::from_fn(self.m, self.n, |i, j| w[[i, j]]))
    }
}

impl PfaffianSystem for CallableSystem<'_> {
    fn coordinate_count(&self) -> usize {
        self.n
    }

    fn constraint_count(&self) -> usize {
        self.m
    }

    fn constraint_matrix<T: RealField + Copy>(&self, q: &[T]) -> DMatrix<T> {
        let q: Vec<f64> = q
            .iter()
            .map(|v| v.to_subset().unwrap_or(f64::NAN))
            .collect();
        let w = match self.evaluate(&q) {
            Ok(w) => w,
            Err(e) => {
                self.error.borrow_mut().get_or_insert(e);
                DMatrix::from_element(self.m, self.n, f64::NAN)
            }
        };
        w.map(|v| T::from_subset(&v))
    }
}

/// The Frobenius test (App. D, (D.1.5)) of the Pfaffian system W(q) q̇ = 0 that
/// `function` computes, at `q` (`frobenius::report_from` on
/// `skew_matrices_central_difference` with step `step`).
#[pyfunction]
#[pyo3(signature = (function, q, step = 1e-6))]
fn cylinders_frobenius_callable<'py>(
    py: Python<'py>,
    function: Bound<'py, PyAny>,
    q: Vec<f64>,
    step: f64,
) -> PyResult<Bound<'py, PyAny>> {
    guard(|| {
        input::positive("step", step).map_err(value_error)?;
        let probe = CallableSystem {
            py,
            function: function.clone(),
            n: q.len(),
            m: 0,
            error: RefCell::new(None),
        };
        let first = probe.function.call1((q.clone(),))?;
        let shape: Vec<usize> = py
            .import("numpy")?
            .call_method1("shape", (first,))?
            .extract()?;
        if shape.len() != 2 || shape[1] != q.len() {
            return Err(PyValueError::new_err(format!(
                "W(q) must have one column per coordinate ({}), got the shape {shape:?}",
                q.len()
            )));
        }
        let system = CallableSystem {
            m: shape[0],
            ..probe
        };
        let skew = skew_matrices_central_difference(&system, &q, step);
        // An exception of the function comes first: it left NaN in W, which the test
        // then refuses.
        if let Some(e) = system.error.borrow_mut().take() {
            return Err(e);
        }
        let skew = skew.map_err(value_error)?;
        json_to_py(
            py,
            &report_from(&skew, RANK_TOLERANCE, INTEGRABILITY_TOLERANCE),
        )
    })
}

fn path_case(case: &str) -> PyResult<PathCase> {
    match case {
        "I" | "i" | "1" => Ok(PathCase::I),
        "II" | "ii" | "2" => Ok(PathCase::II),
        other => Err(PyValueError::new_err(format!(
            "case must be 'I' or 'II', got {other:?}"
        ))),
    }
}

fn path_direction(cw: bool) -> Direction {
    if cw {
        Direction::Clockwise
    } else {
        Direction::CounterClockwise
    }
}

/// The CLI's rolled-check settings: `max_step`, a sample every 20 steps.
fn roll_settings(max_step: f64) -> RollSettings {
    RollSettings {
        max_step,
        record_every: 20,
    }
}

/// `{"report": ..., "t", "center", "contact", "rim_point", "phi"}` of a report and its
/// rolled trace (arrays (N,) and (N, 3)).
fn report_and_trace<'py>(
    py: Python<'py>,
    report: &impl serde::Serialize,
    trace: &RollingTrace,
) -> PyResult<Bound<'py, PyDict>> {
    let n = trace.samples.len();
    let vectors = |f: fn(&cylinders::rolling::Sample) -> [f64; 3]| {
        let flat: Vec<f64> = trace.samples.iter().flat_map(f).collect();
        Array2::from_shape_vec((n, 3), flat).map_err(value_error)
    };
    let out = PyDict::new(py);
    out.set_item("report", json_to_py(py, report)?)?;
    let t: Vec<f64> = trace.samples.iter().map(|s| s.t).collect();
    let phi: Vec<f64> = trace.samples.iter().map(|s| s.phi).collect();
    out.set_item("t", Array1::from_vec(t).into_pyarray(py))?;
    out.set_item("center", vectors(|s| s.center.into())?.into_pyarray(py))?;
    out.set_item("contact", vectors(|s| s.contact.into())?.into_pyarray(py))?;
    out.set_item(
        "rim_point",
        vectors(|s| s.rim_point.into())?.into_pyarray(py),
    )?;
    out.set_item("phi", Array1::from_vec(phi).into_pyarray(py))?;
    Ok(out)
}

/// Δφ when the contact point P traces a rectangle (the nine-rotation product (3.4.3),
/// Figure 3.10; `studies::holonomy::rectangle_report`), as the CLI's `cylinder holonomy
/// rectangle --json`, with the rolled trace.
#[pyfunction]
#[pyo3(signature = (theta, phi1, phi2, s = 0.0, case = "I", cw = false, psi0 = 0.0, r_over_h = 0.12, max_step = 1e-3))]
fn cylinders_holonomy_rectangle<'py>(
    py: Python<'py>,
    theta: f64,
    phi1: f64,
    phi2: f64,
    s: f64,
    case: &str,
    cw: bool,
    psi0: f64,
    r_over_h: f64,
    max_step: f64,
) -> PyResult<Bound<'py, PyDict>> {
    guard(|| {
        // Checked here so that the errors name the parameters, not the library's ϑ, φ1,
        // φ2, s, max_angle_step and h.
        let theta = check_point_contact(check_inclination(theta)?).map_err(value_error)?;
        let phi1 = input::positive("phi1", phi1).map_err(value_error)?;
        let phi2 = input::positive("phi2", phi2).map_err(value_error)?;
        let s = input::in_range("s", s, 0.0..=1.0, "[0, 1]").map_err(value_error)?;
        let max_step = input::positive("max_step", max_step).map_err(value_error)?;
        let path = RectanglePath::new(phi1, phi2, s, path_case(case)?, path_direction(cw))
            .map_err(value_error)?;
        let ratio = input::positive("r_over_h", r_over_h).map_err(value_error)?;
        if !(1.0 / ratio).is_finite() {
            return Err(PyValueError::new_err(format!(
                "r_over_h = {} makes the height 1/(r/h) overflow",
                input::Short(ratio)
            )));
        }
        let cylinder = Cylinder::new(1.0, 1.0 / ratio).map_err(value_error)?;
        let (report, trace) =
            rectangle_report(&cylinder, theta, &path, psi0, roll_settings(max_step))
                .map_err(|e| name_roll_params(e, "phi1 and phi2"))?;
        report_and_trace(py, &report, &trace)
    })
}

/// Δφ when P traces a circle of radius ℓ ((3.4.10)–(3.4.16), Figure 3.12;
/// `studies::holonomy::circle_report`), as the CLI's `cylinder holonomy circle --json`,
/// with the rolled trace. Give the height as `h` or `r_over_h`.
#[pyfunction]
#[pyo3(signature = (ell, theta, h = None, r_over_h = None, r = 1.0, case = "I", cw = false, max_step = 1e-3))]
fn cylinders_holonomy_circle<'py>(
    py: Python<'py>,
    ell: f64,
    theta: f64,
    h: Option<f64>,
    r_over_h: Option<f64>,
    r: f64,
    case: &str,
    cw: bool,
    max_step: f64,
) -> PyResult<Bound<'py, PyDict>> {
    guard(|| {
        let h = match (h, r_over_h) {
            (Some(h), None) => h,
            (None, Some(ratio)) => r / input::positive("r_over_h", ratio).map_err(value_error)?,
            _ => {
                return Err(PyValueError::new_err(
                    "give the height as h or as r_over_h (one of them)",
                ))
            }
        };
        let cylinder = Cylinder::new(r, h).map_err(value_error)?;
        let theta = check_inclination(theta)?;
        let ell = input::positive("ell", ell).map_err(value_error)?;
        let max_step = input::positive("max_step", max_step).map_err(value_error)?;
        let path =
            CirclePath::new(ell, path_case(case)?, path_direction(cw)).map_err(value_error)?;
        let (report, trace) = circle_report(&cylinder, theta, &path, roll_settings(max_step))
            .map_err(|e| name_roll_params(e, "ell"))?;
        report_and_trace(py, &report, &trace)
    })
}

/// The two-cylinder transport of §3.5–3.6 (`studies::pair::run_pair`, recording every
/// step), with the GIL released: the report as `cylinder pair --json` and the trajectory
/// as numpy arrays. A failing step raises `SolverError`.
#[pyfunction]
#[pyo3(signature = (theta, dt = 2e-3, steps = 2000, spin = -6.0 * std::f64::consts::PI, ramp = None, mu_floor = 1.0, mu_mutual = 0.4, push_over_mg = 0.0, rho_inf = 0.5, force = false))]
#[allow(clippy::too_many_arguments)]
fn cylinders_pair<'py>(
    py: Python<'py>,
    theta: f64,
    dt: f64,
    steps: usize,
    spin: f64,
    ramp: Option<f64>,
    mu_floor: f64,
    mu_mutual: f64,
    push_over_mg: f64,
    rho_inf: f64,
    force: bool,
) -> PyResult<Bound<'py, PyDict>> {
    use cylinders::studies::pair::run_pair_until;
    use cylinders::transport::SpinProfile;
    use cylinders::CylinderError;
    use std::sync::atomic::AtomicBool;
    guard(|| {
        if !spin.is_finite() {
            return Err(PyValueError::new_err(format!(
                "spin must be finite, got {spin}"
            )));
        }
        if let Some(d) = ramp {
            if !(d > 0.0 && d.is_finite()) {
                return Err(PyValueError::new_err(format!(
                    "ramp must be a positive duration in s, got {d}"
                )));
            }
        }
        // Checked here so that the errors name the parameters, not the library's ρ∞, μ_s,
        // μ_k and P/mg.
        input::in_range("rho_inf", rho_inf, 0.0..=1.0, "[0, 1]").map_err(value_error)?;
        input::non_negative("mu_floor", mu_floor).map_err(value_error)?;
        input::non_negative("mu_mutual", mu_mutual).map_err(value_error)?;
        input::finite("push_over_mg", push_over_mg).map_err(value_error)?;
        let settings = PairSettings {
            dt,
            steps,
            rho_inf,
            spin: ramp.map_or(SpinProfile::constant(spin), |d| SpinProfile::ramp(spin, d)),
            mu_floor,
            mu_mutual,
            push_over_mg,
            // The watchdog of the run, as the command line's: unless forced.
            time_bound: input::watchdog::time_bound(force),
            ..PairSettings::thesis(theta)
        };
        check_steps(dt, steps)?;
        check_pair_theta(theta, &settings.cylinder)?;
        check_pair_time(&settings, 1, 1, force)?;
        // On a worker thread, so that Ctrl-C is seen while it runs: the run stops
        // after its current step.
        let cancel = AtomicBool::new(false);
        let mut report =
            crate::interruptible(py, &cancel, || Ok(run_pair_until(&settings, true, &cancel)))?
                .map_err(|e| match e {
                    CylinderError::Solver(m) => crate::solver_error(m),
                    e => value_error(e),
                })?;
        let samples = report.trajectory.take().unwrap_or_default();
        let n = samples.len();
        let column = |f: &dyn Fn(&cylinders::studies::pair::PairSample) -> Vec<f64>,
                      width: usize| {
            let flat: Vec<f64> = samples.iter().flat_map(f).collect();
            Array2::from_shape_vec((n, width), flat).map_err(value_error)
        };
        let out = PyDict::new(py);
        out.set_item("report", json_to_py(py, &report)?)?;
        let t: Vec<f64> = samples.iter().map(|x| x.t).collect();
        out.set_item("t", Array1::from_vec(t).into_pyarray(py))?;
        out.set_item("q", column(&|x| x.q.clone(), 12)?.into_pyarray(py))?;
        out.set_item(
            "spin_rates",
            column(&|x| x.spin_rates.to_vec(), 2)?.into_pyarray(py),
        )?;
        out.set_item(
            "n_over_mg",
            column(&|x| x.n_over_mg.to_vec(), 2)?.into_pyarray(py),
        )?;
        out.set_item(
            "f3_over_mg",
            column(&|x| x.f3_over_mg.to_vec(), 2)?.into_pyarray(py),
        )?;
        let normal: Vec<f64> = samples.iter().map(|x| x.contact_normal_force).collect();
        out.set_item(
            "contact_normal_force",
            Array1::from_vec(normal).into_pyarray(py),
        )?;
        out.set_item("gaps", column(&|x| x.gaps.to_vec(), 3)?.into_pyarray(py))?;
        Ok(out)
    })
}

/// Speed against error for the pair spun up (`studies::work_precision::pair_work_precision`),
/// with the GIL released and Ctrl-C checked; the CLI's `cylinder work-precision --json`.
/// The study is checked against the ten-minute time guard first, unless `force`.
#[pyfunction]
#[pyo3(signature = (theta = std::f64::consts::PI / 6.0, dts = vec![8e-3, 4e-3, 2e-3, 1e-3], reference_factor = 4.0, repeat = 3, force = false))]
fn cylinders_work_precision<'py>(
    py: Python<'py>,
    theta: f64,
    dts: Vec<f64>,
    reference_factor: f64,
    repeat: usize,
    force: bool,
) -> PyResult<Bound<'py, PyAny>> {
    use cylinders::studies::work_precision::{
        pair_work_precision_until, study_cost_settings, study_settings, MAX_DT,
    };
    use std::sync::atomic::AtomicBool;
    guard(|| {
        crate::block_studies::check_study_input(&dts, reference_factor, repeat)?;
        for &dt in &dts {
            input::in_range("dts", dt, 0.0..=MAX_DT, "(0, 0.1] s").map_err(value_error)?;
        }
        check_pair_theta(theta, &study_settings(theta, dts[0]).cylinder)?;
        let cost = study_cost_settings(theta, &dts, reference_factor, repeat);
        check_pair_time(&cost, 1, 1, force)?;
        let cancel = AtomicBool::new(false);
        let study = crate::interruptible(py, &cancel, || {
            pair_work_precision_until(theta, &dts, reference_factor, repeat, &cancel)
                .map_err(|e| crate::solver_error(e.to_string()))
        })?;
        json_to_py(py, &study)
    })
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(cylinders_pair, m)?)?;
    m.add_function(wrap_pyfunction!(cylinders_work_precision, m)?)?;
    m.add_function(wrap_pyfunction!(cylinders_support, m)?)?;
    m.add_function(wrap_pyfunction!(cylinders_statics, m)?)?;
    m.add_function(wrap_pyfunction!(cylinders_frobenius, m)?)?;
    m.add_function(wrap_pyfunction!(cylinders_frobenius_callable, m)?)?;
    m.add_function(wrap_pyfunction!(cylinders_holonomy_rectangle, m)?)?;
    m.add_function(wrap_pyfunction!(cylinders_holonomy_circle, m)?)?;
    Ok(())
}
