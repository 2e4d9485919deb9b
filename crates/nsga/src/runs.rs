//! Whole runs of the benchmark systems with their headline numbers (used by tests,
//! benches and the CLI).

use crate::error::StepError;
use crate::moreau::{MoreauOptions, MoreauStepper};
use crate::options::{Options, Prox};
use crate::stepper::Stepper;
use crate::systems::ball::BallCase;
use std::time::Instant;

/// Time-stepping scheme.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Scheme {
    /// Nonsmooth generalized-α (this crate's stepper).
    Nsga,
    /// Moreau–Jean midpoint baseline.
    Moreau,
}

/// One sample of a ball trajectory.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BallSample {
    /// Time.
    pub t: f64,
    /// x, y, φ.
    pub q: [f64; 3],
    /// ẋ, ẏ, φ̇.
    pub u: [f64; 3],
    /// Normal percussion of the step.
    pub p_n: f64,
    /// Newton iterations of the step.
    pub iterations: usize,
}

impl BallSample {
    fn new(t: f64, q: &[f64], u: &[f64], p_n: f64, iterations: usize) -> Self {
        Self {
            t,
            q: [q[0], q[1], q[2]],
            u: [u[0], u[1], u[2]],
            p_n,
            iterations,
        }
    }
}

/// Headline numbers of a ball run (the keys of `rollstack nsga ball --json`).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BallRun {
    /// End time of the first step with a non-zero normal percussion.
    pub first_impact_time: Option<f64>,
    /// First time from which the ball stays in contact with slip |ẋ + Rφ̇| ≤ 1e-8 and
    /// |φ̇| > 1e-6 to the end (None when it never rolls, e.g. case 1 comes to rest).
    pub rolling_onset_time: Option<f64>,
    /// First time from which |ẏ| stays below 2gΔt (the end of the impact accumulation).
    pub rest_time: Option<f64>,
    /// Final (ẋ, φ̇).
    pub final_velocity: [f64; 2],
    /// Smallest gap y − R over the run.
    pub min_gap: f64,
    /// Steps taken.
    pub steps: usize,
    /// Mean Newton iterations per step.
    pub newton_iterations_mean: f64,
    /// Solver wall time (s).
    pub wall_time_s: f64,
    /// The trajectory, one sample per step (including t0).
    pub samples: Vec<BallSample>,
}

/// Runs a ball case with a scheme and Δt; `prox` and `rho_inf` apply to NSGA (the
/// thesis's constant r = 0.3 or the scaled default).
///
/// # Errors
/// The first step error.
pub fn run_ball(
    case: &BallCase,
    scheme: Scheme,
    dt: f64,
    rho_inf: f64,
    prox: Prox,
) -> Result<BallRun, StepError> {
    if !(dt > 0.0 && dt.is_finite()) {
        return Err(StepError::InvalidInput(format!(
            "dt = {dt} must be positive"
        )));
    }
    let steps = (case.t_end / dt).round() as usize;
    let mut samples = Vec::with_capacity(steps + 1);
    samples.push(BallSample {
        t: 0.0,
        q: case.q0,
        u: case.u0,
        p_n: 0.0,
        iterations: 0,
    });
    let mut total_iter = 0usize;
    let start = Instant::now();
    match scheme {
        Scheme::Nsga => {
            let opts = Options {
                dt,
                rho_inf,
                prox,
                ..Options::default()
            };
            let mut s = Stepper::new(case.ball, 0.0, &case.q0, &case.u0, opts)?;
            for _ in 0..steps {
                let it = s.step()?.iterations;
                total_iter += it;
                let st = s.state();
                samples.push(BallSample::new(st.t, &st.q, &st.u, st.p_n[0], it));
            }
        }
        Scheme::Moreau => {
            let opts = MoreauOptions {
                dt,
                prox,
                ..MoreauOptions::default()
            };
            let mut s = MoreauStepper::new(case.ball, 0.0, &case.q0, &case.u0, opts)?;
            for _ in 0..steps {
                let it = s.step()?;
                total_iter += it;
                let st = s.state();
                samples.push(BallSample::new(st.t, &st.q, &st.u, st.p_n[0], it));
            }
        }
    }
    let wall_time_s = start.elapsed().as_secs_f64();
    let r = case.ball.radius;
    let first_impact_time = samples.iter().find(|s| s.p_n > 0.0).map(|s| s.t);
    // Rolling: in contact, no slip, and actually turning (a ball at rest does not roll).
    let in_contact_rolling = |s: &BallSample| {
        s.q[1] - r <= 1e-6 && (s.u[0] + r * s.u[2]).abs() <= 1e-8 && s.u[2].abs() > 1e-6
    };
    let rolling_onset_time = last_run_start(&samples, in_contact_rolling);
    let v_rest = 2.0 * case.ball.gravity * dt;
    let rest_time = last_run_start(&samples, |s| s.u[1].abs() < v_rest && s.q[1] - r <= 1e-3);
    let last = samples.last().expect("at least t0");
    Ok(BallRun {
        first_impact_time,
        rolling_onset_time,
        rest_time,
        final_velocity: [last.u[0], last.u[2]],
        min_gap: samples
            .iter()
            .map(|s| s.q[1] - r)
            .fold(f64::INFINITY, f64::min),
        steps,
        newton_iterations_mean: if steps == 0 {
            0.0
        } else {
            total_iter as f64 / steps as f64
        },
        wall_time_s,
        samples,
    })
}

/// Time of the first sample of the final run of samples satisfying `pred` (None when
/// the last sample does not satisfy it).
fn last_run_start(samples: &[BallSample], pred: impl Fn(&BallSample) -> bool) -> Option<f64> {
    let mut start = None;
    for s in samples {
        if pred(s) {
            if start.is_none() {
                start = Some(s.t);
            }
        } else {
            start = None;
        }
    }
    start
}

/// The systems of the work-precision diagram.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum WorkPrecisionSystem {
    /// Ball case 2: error of x(1.5) against [`BallCase::exact_x`].
    Ball,
    /// Linear oscillator (ω = 2π): phase-plane error √(Δx² + (Δẋ/ω)²) at t = 1.
    Oscillator,
    /// Turning incline (β̇ = 0.5, μ = 0.3): error of x(1.5) against the closed form.
    Incline,
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
                Options {
                    dt,
                    rho_inf,
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
