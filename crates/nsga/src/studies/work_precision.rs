//! Work-precision diagrams of the benchmark systems with closed-form answers: error
//! against solver time, NSGA at several ρ∞ beside Moreau–Jean; the rows of
//! `rollstack nsga work-precision` with their text and CSV cells.

use super::ball::{run_ball, Scheme};
use crate::error::StepError;
use crate::moreau::{MoreauOptions, MoreauStepper};
use crate::options::{Options, PolicyOptions, Prox};
use crate::stepper::Stepper;
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
    use crate::systems::incline::Incline;
    use crate::systems::oscillator::Oscillator;
    match system {
        WorkPrecisionSystem::Ball => {
            let c = BallCase::new(2).map_err(StepError::InvalidInput)?;
            let r = run_ball(&c, scheme, dt, rho_inf, Prox::Scaled(1.0))?;
            let last = r.samples.last().expect("t0 sample");
            let exact = c.exact_x(last.t).expect("case 2 has a closed form");
            Ok(((last.q[0] - exact).abs(), r.wall_time_s))
        }
        WorkPrecisionSystem::Oscillator => {
            let sys = Oscillator {
                mass: 1.0,
                stiffness: 4.0 * std::f64::consts::PI.powi(2),
            };
            let n = (1.0 / dt).round() as usize;
            let (x, u, t, wall) = run_generic(sys, scheme, rho_inf, dt, n, &[1.0], &[0.0])?;
            let (xe, ve) = sys.exact(1.0, 0.0, t);
            // Phase-plane error: at a full period x alone hides the phase error.
            Ok(((x[0] - xe).hypot((u[0] - ve) / sys.omega()), wall))
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
            let (x, _, t, wall) =
                run_generic(sys, scheme, rho_inf, dt, n, &[0.0, 0.0], &[0.0, 0.0])?;
            Ok(((x[0] - sys.turning_position(t)).abs(), wall))
        }
    }
}

/// Runs `n` steps of either scheme; returns (q, u, t, wall time).
fn run_generic<S: crate::system::System>(
    sys: S,
    scheme: Scheme,
    rho_inf: f64,
    dt: f64,
    n: usize,
    q0: &[f64],
    u0: &[f64],
) -> Result<(Vec<f64>, Vec<f64>, f64, f64), StepError> {
    let start = Instant::now();
    match scheme {
        Scheme::Nsga => {
            let mut s = Stepper::new(
                sys,
                0.0,
                q0,
                u0,
                // The scheme alone: a step it cannot resolve is an error, not a
                // Moreau–Jean step in disguise.
                Options {
                    dt,
                    rho_inf,
                    policy: PolicyOptions {
                        last_resort: false,
                        ..PolicyOptions::default()
                    },
                    ..Options::default()
                },
            )?;
            s.run(n, |_, _| {})?;
            Ok((
                s.state().q.clone(),
                s.state().u.clone(),
                s.state().t,
                start.elapsed().as_secs_f64(),
            ))
        }
        Scheme::Moreau => {
            let mut s = MoreauStepper::new(
                sys,
                0.0,
                q0,
                u0,
                MoreauOptions {
                    dt,
                    ..MoreauOptions::default()
                },
            )?;
            for _ in 0..n {
                s.step()?;
            }
            Ok((
                s.state().q.clone(),
                s.state().u.clone(),
                s.state().t,
                start.elapsed().as_secs_f64(),
            ))
        }
    }
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
}

impl WorkPrecisionRow {
    /// The columns of work_precision.csv: the scheme (`nsga` or `moreau`), ρ∞ (empty for
    /// Moreau–Jean), Δt (s), the error against the closed form (m) and the fastest wall
    /// time (s).
    pub const CSV_HEADER: [&'static str; 5] = ["scheme", "rho_inf", "dt", "error", "wall_time_s"];

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
        ]
    }
}

impl fmt::Display for WorkPrecisionRow {
    /// One line: the scheme, ρ∞ (`-` for Moreau–Jean), Δt (s), the error (m) and the wall
    /// time (s).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{:>6} rho_inf={:>4} dt={:.1e}: error {:.3e}, {:.3e} s",
            self.scheme.name(),
            self.rho_inf.map_or("-".into(), |x| x.to_string()),
            self.dt,
            self.error,
            self.wall_time_s
        )
    }
}

/// The work-precision diagram of `system`: for NSGA at each ρ∞ of `rho_infs`, then
/// Moreau–Jean, one point per Δt of `dts`; each point timed `repeat` times (at least
/// once), keeping the fastest.
///
/// # Errors
/// [`StepError::InvalidInput`] for a Δt outside (0, 0.1] s or a ρ∞ outside [0, 1]; the
/// first step error.
pub fn work_precision(
    system: WorkPrecisionSystem,
    dts: &[f64],
    rho_infs: &[f64],
    repeat: usize,
) -> Result<Vec<WorkPrecisionRow>, StepError> {
    work_precision_until(system, dts, rho_infs, repeat, &AtomicBool::new(false))
}

/// [`work_precision`] that stops between two runs once `cancel` is set, returning the
/// rows done so far (the Python module sets it on Ctrl-C).
///
/// # Errors
/// As [`work_precision`].
pub fn work_precision_until(
    system: WorkPrecisionSystem,
    dts: &[f64],
    rho_infs: &[f64],
    repeat: usize,
    cancel: &AtomicBool,
) -> Result<Vec<WorkPrecisionRow>, StepError> {
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
    let mut configs: Vec<(Scheme, Option<f64>)> =
        rho_infs.iter().map(|&r| (Scheme::Nsga, Some(r))).collect();
    configs.push((Scheme::Moreau, None));
    let mut rows = Vec::new();
    for &(scheme, rho) in &configs {
        for &dt in dts {
            let mut best = f64::INFINITY;
            let mut error = f64::NAN;
            for _ in 0..repeat.max(1) {
                if cancel.load(Ordering::Relaxed) {
                    return Ok(rows);
                }
                let (e, w) = work_precision_point(system, scheme, rho.unwrap_or(0.5), dt)?;
                error = e;
                best = best.min(w);
            }
            rows.push(WorkPrecisionRow {
                scheme,
                rho_inf: rho,
                dt,
                error,
                wall_time_s: best,
            });
        }
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_oscillator_converges_at_second_order_with_both_schemes() {
        let rows =
            work_precision(WorkPrecisionSystem::Oscillator, &[4e-3, 2e-3], &[0.5], 1).unwrap();
        assert_eq!(rows.len(), 4);
        for pair in rows.chunks(2) {
            let order = (pair[0].error / pair[1].error).log2();
            assert!(
                (order - 2.0).abs() < 0.2,
                "{:?}: order {order}",
                pair[0].scheme
            );
        }
        assert!(work_precision(WorkPrecisionSystem::Oscillator, &[0.0], &[0.5], 1).is_err());
        assert!(work_precision(WorkPrecisionSystem::Oscillator, &[1e-3], &[1.5], 1).is_err());
    }

    #[test]
    fn text_and_csv_cells_of_a_row() {
        let nsga = WorkPrecisionRow {
            scheme: Scheme::Nsga,
            rho_inf: Some(0.5),
            dt: 4e-3,
            error: 4.955_710_870_921_851e-4,
            wall_time_s: 3.0e-4,
        };
        assert_eq!(
            nsga.to_string(),
            "  nsga rho_inf= 0.5 dt=4.0e-3: error 4.956e-4, 3.000e-4 s"
        );
        let cells = nsga.csv_cells();
        assert_eq!(cells.len(), WorkPrecisionRow::CSV_HEADER.len());
        assert_eq!(
            cells,
            ["nsga", "0.5", "0.004", "0.0004955710870921851", "0.0003"]
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
