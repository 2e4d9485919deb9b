//! Speed against error for the transport of two touching cylinders (§3.6): what
//! `rollstack cylinder work-precision` reports.
//!
//! The thesis's transport starts at its steady motion, which both schemes reproduce to
//! round-off at any Δt (its coordinates change linearly in time). So the study spins the
//! pair up: φ̇10 ramps smoothly from 1 % of −6π rad/s to −6π rad/s over
//! [`SPIN_UP_S`] ([`SpinProfile::ramp`]); the rims slip on the floor, the cylinders press
//! on each other, then part and roll on, and by [`T_END_S`] the transport is steady
//! again. Each Δt is run by the nonsmooth generalized-α scheme and by Moreau–Jean and
//! measured by
//! - its error against a generalized-α run with a much smaller step: the largest
//!   difference of any coordinate at [`T_END_S`] (m and rad), with the observed order
//!   fitted only where the runs follow the reference's contact events
//!   ([`nsga::studies::asymptotic`]);
//! - its error against the statics: the largest |N/mg − (3.3.10)| of both rims at the
//!   end, N the floor's normal percussion over the last step divided by Δt;
//! - the drift of the constraints that hold the pair: the largest |g| of the top heights
//!   and headings over the run (m, rad), and the rims' floor slip at the end, where the
//!   rolling constraint holds again (m/s);
//! - the solver time of its steps.

use super::pair::PairSettings;
use crate::error::CylinderError;
use crate::statics::{FrictionLimit, SupportProblem};
use crate::transport::{PairTransport, SpinProfile};
use nsga::studies::asymptotic::{
    fit_rows, ContactHistory, ContactReader, ContactTolerances, ConvergencePoint, ConvergenceRow,
    ObservedOrder,
};
use nsga::studies::ball::Scheme;
use nsga::studies::work_precision::run_scheme;
use nsga::{Evaluation, Options, PolicyOptions, System};
use serde::Serialize;
use std::f64::consts::PI;
use std::fmt;
use std::sync::atomic::AtomicBool;

/// How long the spin-up lasts, s.
pub const SPIN_UP_S: f64 = 0.5;

/// The end time of every run, s: the transport is steady again from about 1.1 s on.
pub const T_END_S: f64 = 1.2;

/// The largest Δt of the study, s: a tenth of its runs' length.
pub const MAX_DT: f64 = 0.1;

/// The spin rate the pair is brought to, rad/s (the thesis's).
pub const TARGET_SPIN: f64 = -6.0 * PI;

/// The settings of the study's runs at inclination ϑ with step `dt`: the thesis's pair
/// spun up over [`SPIN_UP_S`], run to [`T_END_S`].
#[must_use]
pub fn study_settings(theta: f64, dt: f64) -> PairSettings {
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    let steps = (T_END_S / dt).round() as usize;
    PairSettings {
        dt,
        steps,
        spin: SpinProfile::ramp(TARGET_SPIN, SPIN_UP_S),
        ..PairSettings::thesis(theta)
    }
}

/// Settings of one run as long as the whole study at inclination `theta` (the
/// reference's steps, and both schemes' at each Δt of `dts` `repeat` times, all at the
/// reference's Δt), for its time guard ([`super::pair_cost::pair_cost`]).
#[must_use]
pub fn study_cost_settings(
    theta: f64,
    dts: &[f64],
    reference_factor: f64,
    repeat: usize,
) -> PairSettings {
    let smallest = dts.iter().copied().fold(f64::INFINITY, f64::min);
    let reference = study_settings(theta, smallest / reference_factor);
    let runs = 2 * repeat.max(1);
    let steps = dts
        .iter()
        .map(|&dt| study_settings(theta, dt).steps.saturating_mul(runs))
        .fold(reference.steps, usize::saturating_add);
    PairSettings { steps, ..reference }
}

/// One run of the study.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PairWorkPrecisionRow {
    /// The scheme: `nsga` or `moreau`.
    pub scheme: Scheme,
    /// Δt, s.
    pub dt: f64,
    /// Largest difference of any coordinate from the reference at the end (m, rad), or
    /// null when the run failed.
    pub error: Option<f64>,
    /// Largest |N/mg − (3.3.10)| of both rims at the end, or null.
    pub static_error: Option<f64>,
    /// Largest |g| of the top heights and headings over the run (m, rad), or null.
    pub drift: Option<f64>,
    /// The larger floor slip speed of the two rims at the end, m/s, or null.
    pub final_floor_slip: Option<f64>,
    /// Solver time of the steps, s (the fastest of the repetitions).
    pub wall_time_s: f64,
    /// The run's contact events ([`ContactHistory::events`]; 0 when it failed).
    pub contact_events: usize,
    /// Whether they follow the reference's ([`ContactHistory::follows`]).
    pub follows_reference: bool,
    /// Whether the order of its scheme was fitted through this run.
    pub fitted: bool,
    /// Why the run stopped, or null.
    pub error_message: Option<String>,
}

impl PairWorkPrecisionRow {
    /// The columns of `work_precision.csv`.
    pub const CSV_HEADER: [&'static str; 11] = [
        "scheme",
        "dt",
        "error",
        "static_error",
        "drift",
        "final_floor_slip",
        "wall_time_s",
        "contact_events",
        "follows_reference",
        "fitted",
        "error_message",
    ];

    /// The row's cells under [`Self::CSV_HEADER`] (null: an empty cell).
    #[must_use]
    pub fn csv_cells(&self) -> Vec<String> {
        let opt = |x: Option<f64>| x.map_or(String::new(), |v| v.to_string());
        vec![
            self.scheme.name().to_owned(),
            self.dt.to_string(),
            opt(self.error),
            opt(self.static_error),
            opt(self.drift),
            opt(self.final_floor_slip),
            self.wall_time_s.to_string(),
            self.contact_events.to_string(),
            u8::from(self.follows_reference).to_string(),
            u8::from(self.fitted).to_string(),
            self.error_message.clone().unwrap_or_default(),
        ]
    }

    fn failed(scheme: Scheme, dt: f64, message: String) -> Self {
        Self {
            scheme,
            dt,
            error: None,
            static_error: None,
            drift: None,
            final_floor_slip: None,
            wall_time_s: 0.0,
            contact_events: 0,
            follows_reference: false,
            fitted: false,
            error_message: Some(message),
        }
    }
}

impl fmt::Display for PairWorkPrecisionRow {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let e = |v: Option<f64>| v.map_or_else(|| "-".to_owned(), |v| format!("{v:.2e}"));
        write!(
            f,
            "{:<6} dt = {:.1e}: error {}, static error {}, drift {}, floor slip {}, {:.2e} s, \
             {} contact events",
            self.scheme.name(),
            self.dt,
            e(self.error),
            e(self.static_error),
            e(self.drift),
            e(self.final_floor_slip),
            self.wall_time_s,
            self.contact_events
        )?;
        if let Some(m) = &self.error_message {
            write!(f, ", stopped: {m}")
        } else if self.follows_reference {
            Ok(())
        } else {
            f.write_str(" (other events than the reference)")
        }
    }
}

impl ConvergenceRow for PairWorkPrecisionRow {
    fn point(&self) -> ConvergencePoint {
        ConvergencePoint {
            dt: self.dt,
            error: self.error,
            follows: self.follows_reference,
        }
    }

    fn mark_fitted(&mut self, fitted: bool) {
        self.fitted = fitted;
    }
}

/// The observed orders of the error against the reference.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PairOrders {
    /// Nonsmooth generalized-α.
    pub nsga: ObservedOrder,
    /// Moreau–Jean.
    pub moreau: ObservedOrder,
}

/// The whole study.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PairWorkPrecision {
    /// Inclination ϑ, rad.
    pub theta: f64,
    /// N/mg of the smooth-floor statics (3.3.10).
    pub n_over_mg_static: f64,
    /// The reference run's Δt, s.
    pub reference_dt: f64,
    /// Its solver time, s.
    pub reference_wall_time_s: f64,
    /// Its contact events.
    pub reference_events: usize,
    /// NSGA's runs, then Moreau–Jean's, Δt in the order given.
    pub rows: Vec<PairWorkPrecisionRow>,
    /// The observed orders.
    pub orders: PairOrders,
}

/// What one run ends with.
struct RunEnd {
    q: Vec<f64>,
    n_over_mg: [f64; 2],
    drift: f64,
    floor_slip: f64,
    wall_time_s: f64,
    history: ContactHistory,
}

/// Runs the study at inclination `theta`: each Δt of `dts` by both schemes, against an
/// NSGA run with Δt = min(dts)/`reference_factor`, each point `repeat` times (at least
/// once) keeping the fastest solver time.
///
/// # Errors
/// A bad ϑ, an empty `dts`, a Δt outside (0, [`MAX_DT`]], a factor that is not
/// positive, or a reference run that fails (the rows' own failures are in their `error_message`).
pub fn pair_work_precision(
    theta: f64,
    dts: &[f64],
    reference_factor: f64,
    repeat: usize,
) -> Result<PairWorkPrecision, CylinderError> {
    pair_work_precision_until(
        theta,
        dts,
        reference_factor,
        repeat,
        &AtomicBool::new(false),
    )
}

/// [`pair_work_precision`] whose runs stop before their next step once `cancel` is set
/// (the Python module sets it on Ctrl-C): the reference then fails, or the rows left
/// carry the error [`nsga::studies::work_precision::CANCELLED`].
///
/// # Errors
/// As [`pair_work_precision`].
pub fn pair_work_precision_until(
    theta: f64,
    dts: &[f64],
    reference_factor: f64,
    repeat: usize,
    cancel: &AtomicBool,
) -> Result<PairWorkPrecision, CylinderError> {
    input::positive("reference factor", reference_factor)?;
    if dts.is_empty() {
        return Err(input::InputError::OutOfRange {
            name: "dts".into(),
            range: "at least one time step",
            value: 0.0,
        }
        .into());
    }
    for &dt in dts {
        input::positive("time step Δt", dt)?;
        input::in_range("time step Δt", dt, 0.0..=MAX_DT, "(0, 0.1] s")?;
    }
    let smallest = dts.iter().copied().fold(f64::INFINITY, f64::min);
    let reference_dt = smallest / reference_factor;
    let reference = run(theta, Scheme::Nsga, reference_dt, cancel)
        .map_err(|e| CylinderError::Solver(format!("the reference run failed: {e}")))?;
    let settings = study_settings(theta, reference_dt);
    let statics =
        SupportProblem::new(settings.cylinder.radius() / settings.cylinder.height(), 0.0)?;
    let n_static = statics
        .normal_force(theta, FrictionLimit::Smooth)?
        .unwrap_or(f64::NAN);
    let mut rows = Vec::new();
    for scheme in [Scheme::Nsga, Scheme::Moreau] {
        for &dt in dts {
            rows.push(match fastest_run(theta, scheme, dt, repeat, cancel) {
                Ok(end) => PairWorkPrecisionRow {
                    scheme,
                    dt,
                    error: Some(max_difference(&end.q, &reference.q)),
                    static_error: Some(
                        end.n_over_mg
                            .iter()
                            .fold(0.0, |m, n| f64::max(m, (n - n_static).abs())),
                    ),
                    drift: Some(end.drift),
                    final_floor_slip: Some(end.floor_slip),
                    wall_time_s: end.wall_time_s,
                    contact_events: end.history.events(dt),
                    follows_reference: end.history.follows(&reference.history, dt),
                    fitted: false,
                    error_message: None,
                },
                Err(e) => PairWorkPrecisionRow::failed(scheme, dt, e),
            });
        }
    }
    // NSGA's rows first, then Moreau–Jean's, one per Δt each.
    let (nsga, moreau) = rows.split_at_mut(dts.len());
    let orders = PairOrders {
        nsga: fit_rows(nsga),
        moreau: fit_rows(moreau),
    };
    Ok(PairWorkPrecision {
        theta,
        n_over_mg_static: n_static,
        reference_dt,
        reference_wall_time_s: reference.wall_time_s,
        reference_events: reference.history.events(reference_dt),
        rows,
        orders,
    })
}

/// [`run`] `repeat` times (at least once), with the fastest solver time.
fn fastest_run(
    theta: f64,
    scheme: Scheme,
    dt: f64,
    repeat: usize,
    cancel: &AtomicBool,
) -> Result<RunEnd, String> {
    let mut end = run(theta, scheme, dt, cancel)?;
    for _ in 1..repeat {
        end.wall_time_s = end
            .wall_time_s
            .min(run(theta, scheme, dt, cancel)?.wall_time_s);
    }
    Ok(end)
}

/// What a run watches after each step: the constraints' drift, the contact events, and
/// at the end the floor's normal forces and the rims' slip.
struct Watch {
    mg: f64,
    eval: Evaluation<f64>,
    contacts: ContactReader,
    drift: f64,
    n_over_mg: [f64; 2],
    floor_slip: f64,
}

impl Watch {
    fn new(sys: &PairTransport) -> Self {
        let layout = sys.layout();
        let mg = sys.mass * sys.gravity;
        let speed = sys.cylinder.radius() * TARGET_SPIN.abs();
        Self {
            mg,
            eval: Evaluation::new(&layout),
            contacts: ContactReader::new(layout, ContactTolerances::relative(mg, speed)),
            drift: 0.0,
            n_over_mg: [f64::NAN; 2],
            floor_slip: f64::NAN,
        }
    }

    /// After a step of length `dt` ending at (t, q, u) with normal percussions `p_n`.
    fn observe(
        &mut self,
        sys: &PairTransport,
        dt: f64,
        (t, q, u): (f64, &[f64], &[f64]),
        p_n: &[f64],
    ) {
        self.eval.reset();
        sys.evaluate(t, q, u, &mut self.eval);
        let held = &self.eval.position[..sys.layout().n_bilateral_position];
        self.drift = held.iter().fold(self.drift, |m, g| m.max(g.abs()));
        let mut v = self.eval.velocity_chi.clone();
        for &(r, c, w) in &self.eval.velocity_w.entries {
            v[c] += w * u[r];
        }
        // v = (Π10, floor slip I (2), floor slip II (2), mutual slip (2)).
        self.floor_slip = v[1].hypot(v[2]).max(v[3].hypot(v[4]));
        self.n_over_mg = [p_n[0] / dt / self.mg, p_n[1] / dt / self.mg];
        self.contacts.record(sys, dt, (t, q, u), p_n);
    }
}

/// One run of the study at inclination `theta` by `scheme` with step `dt`; NSGA alone
/// (a step it cannot resolve is an error, not a Moreau–Jean step in disguise).
fn run(theta: f64, scheme: Scheme, dt: f64, cancel: &AtomicBool) -> Result<RunEnd, String> {
    let settings = study_settings(theta, dt);
    let sys = settings.system().map_err(|e| e.to_string())?;
    let (q0, u0) = sys.initial_state(theta).map_err(|e| e.to_string())?;
    let mut watch = Watch::new(&sys);
    let base = settings.stepper_options();
    let options = Options {
        policy: PolicyOptions {
            last_resort: false,
            ..base.policy
        },
        ..base
    };
    let observe = |t: f64, q: &[f64], u: &[f64], p_n: &[f64]| {
        watch.observe(&sys, dt, (t, q, u), p_n);
    };
    let end = run_scheme(
        sys,
        scheme,
        options,
        (&q0, &u0),
        settings.steps,
        cancel,
        observe,
    )
    .map_err(|e| e.to_string())?;
    Ok(RunEnd {
        q: end.q,
        n_over_mg: watch.n_over_mg,
        drift: watch.drift,
        floor_slip: watch.floor_slip,
        wall_time_s: end.wall_time_s,
        history: watch.contacts.into_history(),
    })
}

fn max_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Spun up at ϑ = 30°, both schemes converge to the reference: the error falls with
    /// every halving of Δt. The pair is steady again at the end, so both meet the
    /// statics (3.3.10) and hold their constraints; NSGA's runs all follow the
    /// reference's contact events and its order is the slope of their errors.
    #[test]
    fn the_spun_up_pair_converges_under_both_schemes() {
        let dts = [8e-3, 4e-3, 2e-3];
        let study = pair_work_precision(PI / 6.0, &dts, 4.0, 1).unwrap();
        assert!(study.reference_events > 0, "{study:?}");
        for rows in study.rows.chunks(dts.len()) {
            for r in rows {
                assert!(r.error_message.is_none(), "{r}");
                assert!(r.static_error.unwrap() < 1e-8, "{r}");
                assert!(r.drift.unwrap() < 1e-12, "{r}");
                assert!(r.final_floor_slip.unwrap() < 1e-10, "{r}");
            }
            let e: Vec<f64> = rows.iter().map(|r| r.error.unwrap()).collect();
            assert!(e[1] < e[0] && e[2] < e[1], "{rows:?}");
        }
        let nsga = &study.rows[..dts.len()];
        assert!(
            nsga.iter().all(|r| r.follows_reference && r.fitted),
            "{nsga:?}"
        );
        let points: Vec<(f64, f64)> = nsga.iter().map(|r| (r.dt, r.error.unwrap())).collect();
        let slope = nsga::studies::asymptotic::least_squares_slope(&points).unwrap();
        let order = study.orders.nsga.order().unwrap();
        assert!((order - slope).abs() < 1e-12, "{order} against {slope}");
    }

    #[test]
    fn bad_input_is_refused_before_any_run() {
        assert!(pair_work_precision(PI / 6.0, &[], 4.0, 1).is_err());
        assert!(pair_work_precision(PI / 6.0, &[0.0], 4.0, 1).is_err());
        assert!(pair_work_precision(PI / 6.0, &[2.0], 4.0, 1).is_err());
        assert!(pair_work_precision(PI / 6.0, &[1e-2], 0.0, 1).is_err());
        assert!(pair_work_precision(0.05, &[1e-2], 4.0, 1).is_err());
    }

    #[test]
    fn a_row_has_a_cell_per_column() {
        let row = PairWorkPrecisionRow::failed(Scheme::Moreau, 1e-3, "stopped".into());
        assert_eq!(
            row.csv_cells().len(),
            PairWorkPrecisionRow::CSV_HEADER.len()
        );
        assert!(row.to_string().ends_with("stopped: stopped"), "{row}");
    }
}
