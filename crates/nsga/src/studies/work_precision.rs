//! Work-precision diagrams of the benchmark systems with closed-form answers: error
//! against solver time, NSGA at several ρ∞ beside Moreau–Jean; the rows of
//! `rollstack nsga work-precision` with their text and CSV cells, and the observed orders,
//! fitted where the runs follow a reference run's contact events ([`super::asymptotic`]).

use super::asymptotic::{
    fit_rows, ContactHistory, ContactReader, ContactTolerances, ConvergencePoint, ConvergenceRow,
    ObservedOrder,
};
use super::ball::{run_ball, Scheme};
use crate::error::StepError;
use crate::moreau::{MoreauOptions, MoreauStepper};
use crate::options::{Options, PolicyOptions, Prox};
use crate::stepper::Stepper;
use crate::system::System;
use crate::systems::ball::BallCase;
use std::fmt;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// The systems of the work-precision diagram.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum WorkPrecisionSystem {
    /// Ball case 2: error of x(1.5) against [`BallCase::exact_x`].
    Ball,
    /// Linear oscillator (ω = 2π): phase-plane error √(Δx² + (Δẋ/ω)²) at t = 1.
    Oscillator,
    /// Turning incline (β̇ = 0.5, μ = 0.3): error of x(1.5) against the closed form.
    Incline,
}

impl WorkPrecisionSystem {
    /// The system's name in files and JSON: `ball`, `oscillator` or `incline`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Ball => "ball",
            Self::Oscillator => "oscillator",
            Self::Incline => "incline",
        }
    }
}

/// The reference run that gives a study its sequence of contact events takes the
/// smallest Δt over this factor (the errors are measured against the closed forms).
pub const EVENTS_REFERENCE_FACTOR: f64 = 4.0;

/// The error of a run stopped by its `cancel` flag.
pub const CANCELLED: &str = "cancelled";

/// Why [`run_scheme`] stopped before its last step.
#[derive(Debug)]
pub enum SchemeStop {
    /// Its `cancel` flag was set.
    Cancelled,
    /// A step failed.
    Step(StepError),
}

impl fmt::Display for SchemeStop {
    /// [`CANCELLED`], or the step's error.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Cancelled => f.write_str(CANCELLED),
            Self::Step(e) => e.fmt(f),
        }
    }
}

impl From<StepError> for SchemeStop {
    fn from(e: StepError) -> Self {
        Self::Step(e)
    }
}

/// The end of a run of [`run_scheme`].
#[derive(Debug, Clone, PartialEq)]
pub struct SchemeEnd {
    /// The time reached.
    pub t: f64,
    /// Coordinates at the end.
    pub q: Vec<f64>,
    /// Velocities at the end.
    pub u: Vec<f64>,
    /// The time spent in the steps alone (solver time, without what `observe` does), s.
    pub wall_time_s: f64,
}

/// Takes `steps` steps of `scheme` on `system` from (0, q0, u0), generalized-α with
/// `options`, Moreau–Jean with the same Δt and Newton tolerance, and calls
/// `observe(t, q, u, P_N)` after each. Stops with [`SchemeStop::Cancelled`] before a step
/// once `cancel` is set.
///
/// # Errors
/// A bad start or the first step error; [`SchemeStop::Cancelled`].
#[allow(clippy::too_many_arguments)]
pub fn run_scheme<S: System>(
    system: S,
    scheme: Scheme,
    options: Options,
    (q0, u0): (&[f64], &[f64]),
    steps: usize,
    cancel: &AtomicBool,
    mut observe: impl FnMut(f64, &[f64], &[f64], &[f64]),
) -> Result<SchemeEnd, SchemeStop> {
    let mut wall_time_s = 0.0;
    let mut timed = |step: &mut dyn FnMut() -> Result<(), StepError>| {
        if cancel.load(Ordering::Relaxed) {
            return Err(SchemeStop::Cancelled);
        }
        let clock = Instant::now();
        step()?;
        wall_time_s += clock.elapsed().as_secs_f64();
        Ok(())
    };
    let (t, q, u) = match scheme {
        Scheme::Nsga => {
            let mut s = Stepper::new(system, 0.0, q0, u0, options)?;
            for _ in 0..steps {
                timed(&mut || s.step().map(drop))?;
                let st = s.state();
                observe(st.t, &st.q, &st.u, &st.p_n);
            }
            let st = s.state();
            (st.t, st.q.clone(), st.u.clone())
        }
        Scheme::Moreau => {
            let moreau = MoreauOptions {
                dt: options.dt,
                tol: options.tol,
                ..MoreauOptions::default()
            };
            let mut s = MoreauStepper::new(system, 0.0, q0, u0, moreau)?;
            for _ in 0..steps {
                timed(&mut || s.step().map(drop))?;
                let st = s.state();
                observe(st.t, &st.q, &st.u, &st.p_n);
            }
            let st = s.state();
            (st.t, st.q.clone(), st.u.clone())
        }
    };
    Ok(SchemeEnd {
        t,
        q,
        u,
        wall_time_s,
    })
}

/// One run of a work-precision diagram: its error against the closed form, its solver
/// time and its contact events.
struct PointRun {
    error: f64,
    wall_time_s: f64,
    history: ContactHistory,
}

/// One point of a work-precision diagram: the error against the closed form and the
/// solver wall time of one run.
///
/// # Errors
/// The first step error.
pub fn work_precision_point(
    system: WorkPrecisionSystem,
    scheme: Scheme,
    rho_inf: f64,
    dt: f64,
) -> Result<(f64, f64), StepError> {
    run_point(system, scheme, rho_inf, dt).map(|r| (r.error, r.wall_time_s))
}

/// One run of `system`, with its contact events.
fn run_point(
    system: WorkPrecisionSystem,
    scheme: Scheme,
    rho_inf: f64,
    dt: f64,
) -> Result<PointRun, StepError> {
    use crate::systems::incline::Incline;
    use crate::systems::oscillator::Oscillator;
    match system {
        WorkPrecisionSystem::Ball => {
            let c = BallCase::new(2).map_err(StepError::InvalidInput)?;
            let r = run_ball(&c, scheme, dt, rho_inf, Prox::Scaled(1.0))?;
            let ball = c.ball;
            let mut reader = ContactReader::new(
                ball.layout(),
                ContactTolerances::relative(ball.mass * ball.gravity, 1.0),
            );
            for s in &r.samples[1..] {
                reader.record(&ball, dt, (s.t, &s.q, &s.u), &[s.p_n]);
            }
            let last = r.samples.last().expect("t0 sample");
            let exact = c.exact_x(last.t).expect("case 2 has a closed form");
            Ok(PointRun {
                error: (last.q[0] - exact).abs(),
                wall_time_s: r.wall_time_s,
                history: reader.into_history(),
            })
        }
        WorkPrecisionSystem::Oscillator => {
            let sys = Oscillator {
                mass: 1.0,
                stiffness: 4.0 * std::f64::consts::PI.powi(2),
            };
            let n = (1.0 / dt).round() as usize;
            let start: (&[f64], &[f64]) = (&[1.0], &[0.0]);
            let (end, history) = run_generic(sys, scheme, rho_inf, dt, n, start, 1.0)?;
            let (xe, ve) = sys.exact(1.0, 0.0, end.t);
            // Phase-plane error: at a full period x alone hides the phase error.
            Ok(PointRun {
                error: (end.q[0] - xe).hypot((end.u[0] - ve) / sys.omega()),
                wall_time_s: end.wall_time_s,
                history,
            })
        }
        WorkPrecisionSystem::Incline => {
            let sys = Incline {
                mass: 1.0,
                gravity: 9.81,
                mu: 0.3,
                beta0: 0.0,
                beta_rate: 0.5,
            };
            let n = (1.5 / dt).round() as usize;
            let weight = sys.mass * sys.gravity;
            let start: (&[f64], &[f64]) = (&[0.0, 0.0], &[0.0, 0.0]);
            let (end, history) = run_generic(sys, scheme, rho_inf, dt, n, start, weight)?;
            Ok(PointRun {
                error: (end.q[0] - sys.turning_position(end.t)).abs(),
                wall_time_s: end.wall_time_s,
                history,
            })
        }
    }
}

/// Runs `n` steps of either scheme from (q0, u0), recording the contact events of a
/// system of weight `weight`; NSGA alone (a step it cannot resolve is an error, not a
/// Moreau–Jean step in disguise).
#[allow(clippy::too_many_arguments)]
fn run_generic<S: System + Copy>(
    sys: S,
    scheme: Scheme,
    rho_inf: f64,
    dt: f64,
    n: usize,
    start: (&[f64], &[f64]),
    weight: f64,
) -> Result<(SchemeEnd, ContactHistory), StepError> {
    let mut reader = ContactReader::new(sys.layout(), ContactTolerances::relative(weight, 1.0));
    let options = Options {
        dt,
        rho_inf,
        policy: PolicyOptions {
            last_resort: false,
            ..PolicyOptions::default()
        },
        ..Options::default()
    };
    let never = AtomicBool::new(false);
    let end = run_scheme(sys, scheme, options, start, n, &never, |t, q, u, p_n| {
        reader.record(&sys, dt, (t, q, u), p_n);
    })
    .map_err(|stop| match stop {
        SchemeStop::Step(e) => e,
        SchemeStop::Cancelled => unreachable!("never cancelled"),
    })?;
    Ok((end, reader.into_history()))
}

/// One point of a work-precision diagram.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct WorkPrecisionRow {
    /// The scheme.
    pub scheme: Scheme,
    /// ρ∞ (NSGA only).
    pub rho_inf: Option<f64>,
    /// Time step Δt (s).
    pub dt: f64,
    /// Error against the closed form (m).
    pub error: f64,
    /// The fastest solver wall time of the repetitions (s).
    pub wall_time_s: f64,
    /// The run's contact events (changes of a contact between open and closed, or of a
    /// friction law between stick and slip, lasting longer than a few steps:
    /// [`ContactHistory::events`]).
    pub contact_events: usize,
    /// Whether the run follows the reference's sequence of contact events
    /// ([`ContactHistory::follows`]).
    pub follows_reference: bool,
    /// Whether the order of its scheme and ρ∞ was fitted through this run.
    pub fitted: bool,
}

impl WorkPrecisionRow {
    /// The columns of work_precision.csv: the scheme (`nsga` or `moreau`), ρ∞ (empty for
    /// Moreau–Jean), Δt (s), the error against the closed form (m), the fastest wall
    /// time (s), the run's contact events, whether they follow the reference's (1 or 0)
    /// and whether the order was fitted through the run (1 or 0).
    pub const CSV_HEADER: [&'static str; 8] = [
        "scheme",
        "rho_inf",
        "dt",
        "error",
        "wall_time_s",
        "contact_events",
        "follows_reference",
        "fitted",
    ];

    /// The cells of this row under [`Self::CSV_HEADER`], numbers in shortest round-trip
    /// form.
    #[must_use]
    pub fn csv_cells(&self) -> Vec<String> {
        vec![
            self.scheme.name().to_owned(),
            self.rho_inf.map_or(String::new(), |x| x.to_string()),
            self.dt.to_string(),
            self.error.to_string(),
            self.wall_time_s.to_string(),
            self.contact_events.to_string(),
            u8::from(self.follows_reference).to_string(),
            u8::from(self.fitted).to_string(),
        ]
    }
}

impl fmt::Display for WorkPrecisionRow {
    /// One line: the scheme, ρ∞ (`-` for Moreau–Jean), Δt (s), the error (m), the wall
    /// time (s) and the contact events, marked `(other events)` when they do not follow
    /// the reference's.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{:>6} rho_inf={:>4} dt={:.1e}: error {:.3e}, {:.3e} s, {} contact events",
            self.scheme.name(),
            self.rho_inf.map_or("-".into(), |x| x.to_string()),
            self.dt,
            self.error,
            self.wall_time_s,
            self.contact_events
        )?;
        if !self.follows_reference {
            f.write_str(" (other events than the reference)")?;
        }
        Ok(())
    }
}

/// The observed order of one scheme and ρ∞.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ConfigOrder {
    /// The scheme.
    pub scheme: Scheme,
    /// ρ∞ (NSGA only).
    pub rho_inf: Option<f64>,
    /// Its order, fitted where its runs follow the reference's contact events.
    pub order: ObservedOrder,
}

impl fmt::Display for ConfigOrder {
    /// `observed order, nsga rho_inf=0.5: 2.00 (Δt 2.5e-4 to 8.0e-3)`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let rho = self
            .rho_inf
            .map_or(String::new(), |r| format!(" rho_inf={r}"));
        write!(
            f,
            "observed order, {}{rho}: {}",
            self.scheme.name(),
            self.order
        )
    }
}

/// A whole work-precision diagram.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct WorkPrecision {
    /// The step of the NSGA run (ρ∞ = 0.5) whose contact events the runs must follow:
    /// the smallest Δt over [`EVENTS_REFERENCE_FACTOR`].
    pub reference_dt: f64,
    /// The reference run's contact events.
    pub reference_events: usize,
    /// One row per scheme, ρ∞ and Δt: NSGA at each ρ∞, then Moreau–Jean.
    pub rows: Vec<WorkPrecisionRow>,
    /// The observed order of each scheme and ρ∞, in the order of the rows.
    pub orders: Vec<ConfigOrder>,
}

/// The work-precision diagram of `system`: for NSGA at each ρ∞ of `rho_infs`, then
/// Moreau–Jean, one point per Δt of `dts`; each point timed `repeat` times (at least
/// once), keeping the fastest; the orders fitted where the runs follow the contact
/// events of a run with Δt = min(dts)/[`EVENTS_REFERENCE_FACTOR`].
///
/// # Errors
/// [`StepError::InvalidInput`] for a Δt outside (0, 0.1] s or a ρ∞ outside [0, 1]; the
/// first step error.
pub fn work_precision(
    system: WorkPrecisionSystem,
    dts: &[f64],
    rho_infs: &[f64],
    repeat: usize,
) -> Result<WorkPrecision, StepError> {
    work_precision_until(system, dts, rho_infs, repeat, &AtomicBool::new(false))
}

/// [`work_precision`] that stops between two runs once `cancel` is set, with the rows
/// done so far (the Python module sets it on Ctrl-C).
///
/// # Errors
/// As [`work_precision`].
pub fn work_precision_until(
    system: WorkPrecisionSystem,
    dts: &[f64],
    rho_infs: &[f64],
    repeat: usize,
    cancel: &AtomicBool,
) -> Result<WorkPrecision, StepError> {
    if dts.iter().any(|&d| !(d > 0.0 && d <= 0.1)) {
        return Err(StepError::InvalidInput(
            "every dt must be in (0, 0.1] s".into(),
        ));
    }
    if rho_infs.iter().any(|r| !(0.0..=1.0).contains(r)) {
        return Err(StepError::InvalidInput(
            "every rho_inf must be in [0, 1]".into(),
        ));
    }
    let smallest = dts.iter().copied().fold(0.1, f64::min);
    let reference_dt = smallest / EVENTS_REFERENCE_FACTOR;
    let reference = run_point(system, Scheme::Nsga, 0.5, reference_dt)?.history;
    let mut configs: Vec<(Scheme, Option<f64>)> =
        rho_infs.iter().map(|&r| (Scheme::Nsga, Some(r))).collect();
    configs.push((Scheme::Moreau, None));
    let mut study = WorkPrecision {
        reference_dt,
        reference_events: reference.events(reference_dt),
        rows: Vec::new(),
        orders: Vec::new(),
    };
    'configs: for &(scheme, rho) in &configs {
        let first = study.rows.len();
        for &dt in dts {
            let mut best: Option<PointRun> = None;
            for _ in 0..repeat.max(1) {
                if cancel.load(Ordering::Relaxed) {
                    break 'configs;
                }
                let run = run_point(system, scheme, rho.unwrap_or(0.5), dt)?;
                let fastest = best.as_ref().map_or(f64::INFINITY, |b| b.wall_time_s);
                best = Some(PointRun {
                    wall_time_s: run.wall_time_s.min(fastest),
                    ..run
                });
            }
            let run = best.expect("at least one repetition");
            study.rows.push(WorkPrecisionRow {
                scheme,
                rho_inf: rho,
                dt,
                error: run.error,
                wall_time_s: run.wall_time_s,
                contact_events: run.history.events(dt),
                follows_reference: run.history.follows(&reference, dt),
                fitted: false,
            });
        }
        let order = fit_rows(&mut study.rows[first..]);
        study.orders.push(ConfigOrder {
            scheme,
            rho_inf: rho,
            order,
        });
    }
    Ok(study)
}

impl ConvergenceRow for WorkPrecisionRow {
    fn point(&self) -> ConvergencePoint {
        ConvergencePoint {
            dt: self.dt,
            error: Some(self.error).filter(|e| e.is_finite()),
            follows: self.follows_reference,
        }
    }

    fn mark_fitted(&mut self, fitted: bool) {
        self.fitted = fitted;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_oscillator_converges_at_second_order_with_both_schemes() {
        let study =
            work_precision(WorkPrecisionSystem::Oscillator, &[4e-3, 2e-3], &[0.5], 1).unwrap();
        assert_eq!(study.rows.len(), 4);
        // No contacts: every run follows the reference, and the order is the slope
        // through both errors.
        assert_eq!(study.reference_events, 0);
        for (pair, fitted) in study.rows.chunks(2).zip(&study.orders) {
            let order = (pair[0].error / pair[1].error).log2();
            assert!(
                (order - 2.0).abs() < 0.2,
                "{:?}: order {order}",
                pair[0].scheme
            );
            let reported = fitted.order.order().unwrap();
            assert!((reported - order).abs() < 1e-12, "{fitted}");
            assert!(pair.iter().all(|r| r.follows_reference && r.fitted));
        }
        assert!(work_precision(WorkPrecisionSystem::Oscillator, &[0.0], &[0.5], 1).is_err());
        assert!(work_precision(WorkPrecisionSystem::Oscillator, &[1e-3], &[1.5], 1).is_err());
    }

    /// The ball lands, slides and rolls: three contact events (the contact closes, its
    /// friction law slips, then sticks), in every run as in the reference, so its order
    /// is the slope through all its errors, whatever they are.
    #[test]
    fn the_ball_runs_follow_the_reference_landing_and_rolling() {
        let dts = [8e-3, 4e-3, 2e-3];
        let study = work_precision(WorkPrecisionSystem::Ball, &dts, &[0.5], 1).unwrap();
        assert_eq!(study.reference_events, 3);
        for (rows, fitted) in study.rows.chunks(3).zip(&study.orders) {
            assert!(
                rows.iter().all(|r| r.follows_reference && r.fitted),
                "{rows:?}"
            );
            let points: Vec<(f64, f64)> = rows.iter().map(|r| (r.dt, r.error)).collect();
            let slope = super::super::asymptotic::least_squares_slope(&points).unwrap();
            let order = fitted.order.order().unwrap();
            assert!((order - slope).abs() < 1e-12, "{fitted}: {slope}");
        }
    }

    #[test]
    fn text_and_csv_cells_of_a_row() {
        let nsga = WorkPrecisionRow {
            scheme: Scheme::Nsga,
            rho_inf: Some(0.5),
            dt: 4e-3,
            error: 4.955_710_870_921_851e-4,
            wall_time_s: 3.0e-4,
            contact_events: 2,
            follows_reference: true,
            fitted: true,
        };
        assert_eq!(
            nsga.to_string(),
            "  nsga rho_inf= 0.5 dt=4.0e-3: error 4.956e-4, 3.000e-4 s, 2 contact events"
        );
        let cells = nsga.csv_cells();
        assert_eq!(cells.len(), WorkPrecisionRow::CSV_HEADER.len());
        assert_eq!(
            cells,
            [
                "nsga",
                "0.5",
                "0.004",
                "0.0004955710870921851",
                "0.0003",
                "2",
                "1",
                "1"
            ]
        );
        let moreau = WorkPrecisionRow {
            scheme: Scheme::Moreau,
            rho_inf: None,
            ..nsga
        };
        assert!(moreau.to_string().starts_with("moreau rho_inf=   - dt="));
        assert_eq!(moreau.csv_cells()[..2], ["moreau", ""]);
        assert_eq!(WorkPrecisionSystem::Oscillator.name(), "oscillator");
        assert_eq!(
            serde_json::to_value(WorkPrecisionSystem::Incline).unwrap(),
            "incline"
        );
    }
}
