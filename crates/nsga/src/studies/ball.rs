//! The paper's rotating bouncing ball (Capobianco et al. 2021, §5.1): whole runs with
//! both schemes, their headline numbers, the report of `rollstack nsga ball` and its
//! text, and the cells of the trajectory CSV.

use crate::error::StepError;
use crate::moreau::{MoreauOptions, MoreauStepper};
use crate::options::{Options, PolicyOptions, Prox};
use crate::stepper::Stepper;
use crate::systems::ball::BallCase;
use std::fmt;
use std::time::Instant;

/// Time-stepping scheme.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Scheme {
    /// Nonsmooth generalized-α (this crate's stepper).
    Nsga,
    /// Moreau–Jean midpoint baseline.
    Moreau,
}

impl Scheme {
    /// The scheme's name in files and JSON: `nsga` or `moreau`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Nsga => "nsga",
            Self::Moreau => "moreau",
        }
    }
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
    /// The columns of the trajectory CSV (trajectory.csv): t (s), x, y (m), φ (rad),
    /// ẋ, ẏ (m/s), φ̇ (rad/s), the normal percussion p_N of the step (N s) and its Newton
    /// iterations.
    pub const CSV_HEADER: [&'static str; 9] = [
        "t",
        "x",
        "y",
        "phi",
        "xdot",
        "ydot",
        "phidot",
        "p_n",
        "newton_iterations",
    ];

    /// The cells of this sample's row under [`Self::CSV_HEADER`], numbers in shortest
    /// round-trip form.
    #[must_use]
    pub fn csv_cells(&self) -> Vec<String> {
        let numbers = std::iter::once(self.t)
            .chain(self.q)
            .chain(self.u)
            .chain([self.p_n]);
        numbers
            .map(|v| v.to_string())
            .chain([self.iterations.to_string()])
            .collect()
    }

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

/// The most steps of one ball run: each keeps a sample (about 100 bytes), so two
/// million steps (Δt = 0.75 µs for a 1.5 s case) are about 200 MB.
pub const MAX_BALL_STEPS: usize = 2_000_000;

/// Runs a ball case with a scheme and Δt; `prox` and `rho_inf` apply to NSGA (the
/// thesis's constant r = 0.3 or the scaled default).
///
/// # Errors
/// A Δt that is not positive or needs more than [`MAX_BALL_STEPS`] steps; the first step
/// error.
pub fn run_ball(
    case: &BallCase,
    scheme: Scheme,
    dt: f64,
    rho_inf: f64,
    prox: Prox,
) -> Result<BallRun, StepError> {
    if !(dt > 0.0 && dt.is_finite()) {
        return Err(StepError::InvalidInput(format!(
            "dt = {dt:e} must be positive"
        )));
    }
    if case.t_end / dt > MAX_BALL_STEPS as f64 {
        return Err(StepError::InvalidInput(format!(
            "dt = {dt:e} s needs {:.1e} steps to reach t = {} s; at most {MAX_BALL_STEPS} (dt ≥ {:.1e} s)",
            case.t_end / dt,
            case.t_end,
            case.t_end / MAX_BALL_STEPS as f64
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
            // The scheme alone, as the comparison with Moreau–Jean needs: a step it
            // cannot resolve is an error, not a last-resort step.
            let opts = Options {
                dt,
                rho_inf,
                prox,
                policy: PolicyOptions {
                    last_resort: false,
                    ..PolicyOptions::default()
                },
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

/// The report of one ball run (`rollstack nsga ball --json`; docs/cli.md): the run's
/// headline numbers beside the exact first impact and final rolling velocity.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct BallReport {
    /// The case, 1–4.
    pub case: u8,
    /// The scheme.
    pub scheme: Scheme,
    /// Time step Δt (s).
    pub dt: f64,
    /// End time of the first step with a non-zero normal percussion (s).
    pub first_impact_time: Option<f64>,
    /// First time from which the ball rolls to the end (s).
    pub rolling_onset_time: Option<f64>,
    /// First time from which the bouncing has died out (s).
    pub rest_time: Option<f64>,
    /// Final (ẋ, φ̇) (m/s, rad/s).
    pub final_velocity: [f64; 2],
    /// Smallest gap y − R (m).
    pub min_gap: f64,
    /// Steps taken.
    pub steps: usize,
    /// Mean Newton iterations per step.
    pub newton_iterations_mean: f64,
    /// Solver wall time (s).
    pub wall_time_s: f64,
    /// The exact first impact time (s).
    pub first_impact_time_exact: f64,
    /// The exact final rolling velocity ẋ from the conserved m ẋ − (Θ/R) φ̇ (m/s), for
    /// the runs that end rolling.
    pub final_xdot_exact: Option<f64>,
}

impl fmt::Display for BallReport {
    /// One line: the case and scheme, the first impact (s) beside the exact one, the
    /// rolling onset (s), the final (ẋ, φ̇) (m/s, rad/s), the smallest gap (m), the mean
    /// Newton iterations per step and the wall time (ms). A time that does not exist
    /// (no impact, never rolling) shows as `none`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let time = |t: Option<f64>| t.map_or_else(|| "none".to_owned(), |t| format!("{t} s"));
        write!(
            f,
            "ball case {} ({}): first impact {} (exact {:.4} s), rolling from {}, final (xdot, phidot) = ({:.5}, {:.4}), min gap {:.2e}, {:.2} Newton iterations/step, {:.3} ms",
            self.case,
            self.scheme.name(),
            time(self.first_impact_time),
            self.first_impact_time_exact,
            time(self.rolling_onset_time),
            self.final_velocity[0],
            self.final_velocity[1],
            self.min_gap,
            self.newton_iterations_mean,
            self.wall_time_s * 1e3
        )
    }
}

/// Runs ball case `case` (1–4) with `scheme` and Δt, and reports it beside the closed
/// forms; also returns the run with its trajectory.
///
/// # Errors
/// [`StepError::InvalidInput`] for an unknown case or Δt outside (0, 0.1] s; the first
/// step error.
pub fn ball_report(
    case: u8,
    scheme: Scheme,
    dt: f64,
    rho_inf: f64,
    prox: Prox,
) -> Result<(BallReport, BallRun), StepError> {
    if !(dt > 0.0 && dt <= 0.1) {
        return Err(StepError::InvalidInput(format!(
            "dt must be in (0, 0.1] s, got {dt:e}"
        )));
    }
    let c = BallCase::new(case).map_err(StepError::InvalidInput)?;
    let r = run_ball(&c, scheme, dt, rho_inf, prox)?;
    let report = BallReport {
        case,
        scheme,
        dt,
        first_impact_time: r.first_impact_time,
        rolling_onset_time: r.rolling_onset_time,
        rest_time: r.rest_time,
        final_velocity: r.final_velocity,
        min_gap: r.min_gap,
        steps: r.steps,
        newton_iterations_mean: r.newton_iterations_mean,
        wall_time_s: r.wall_time_s,
        first_impact_time_exact: c.first_impact_time(),
        final_xdot_exact: r
            .rolling_onset_time
            .map(|_| c.ball.rolling_velocity(c.u0[0], c.u0[2])),
    };
    Ok((report, r))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_step_too_small_to_store_is_refused_before_any_work() {
        let err = ball_report(2, Scheme::Nsga, 1e-300, 0.5, Prox::Scaled(1.0)).unwrap_err();
        assert!(err.to_string().contains("at most 2000000"), "{err}");
        // Δt printed short, not as three hundred digits.
        assert!(err.to_string().contains("dt = 1e-300 s needs"), "{err}");
    }

    #[test]
    fn case_two_rolls_at_the_exact_velocity_and_bad_input_is_refused() {
        let (r, run) = ball_report(2, Scheme::Nsga, 2e-3, 0.5, Prox::Scaled(1.0)).unwrap();
        let exact = r.final_xdot_exact.expect("case 2 ends rolling");
        assert!((r.final_velocity[0] - exact).abs() < 1e-6, "{r:?}");
        assert!((r.first_impact_time.unwrap() - r.first_impact_time_exact).abs() < 2e-3);
        assert_eq!(run.samples.len(), r.steps + 1);
        assert_eq!(serde_json::to_value(r.scheme).unwrap(), "nsga");
        for dt in [0.0, -1.0, 0.2, f64::NAN] {
            assert!(ball_report(2, Scheme::Nsga, dt, 0.5, Prox::Scaled(1.0)).is_err());
        }
        assert!(ball_report(5, Scheme::Moreau, 2e-3, 0.5, Prox::Scaled(1.0)).is_err());
    }

    #[test]
    fn text_and_trajectory_cells_of_case_two() {
        let (r, run) = ball_report(2, Scheme::Nsga, 2e-3, 0.5, Prox::Scaled(1.0)).unwrap();
        let text = r.to_string();
        let impact = r.first_impact_time.unwrap();
        let rolling = r.rolling_onset_time.unwrap();
        assert!(
            text.starts_with(&format!(
                "ball case 2 (nsga): first impact {impact} s (exact 0.4284 s), rolling from {rolling} s, "
            )),
            "{text}"
        );
        // Case 1 bounces to rest and never rolls.
        let (r1, _) = ball_report(1, Scheme::Nsga, 2e-3, 0.5, Prox::Scaled(1.0)).unwrap();
        assert_eq!(r1.rolling_onset_time, None);
        let text1 = r1.to_string();
        assert!(text1.contains(", rolling from none, "), "{text1}");
        assert!(!text1.contains("Some(") && !text1.contains("None"));
        assert!(text.contains(&format!(
            "final (xdot, phidot) = ({:.5}, ",
            r.final_velocity[0]
        )));
        assert!(text.ends_with(" ms") && !text.contains('\n'));
        let first = run.samples[0].csv_cells();
        assert_eq!(first.len(), BallSample::CSV_HEADER.len());
        assert_eq!((first[0].as_str(), first[8].as_str()), ("0", "0"));
        let last = run.samples.last().unwrap();
        assert_eq!(last.csv_cells()[4], last.u[0].to_string());
    }
}
