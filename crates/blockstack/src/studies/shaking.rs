//! The shaken column at one base frequency: its time to failure (§4.4, Figure 4.6).

use crate::exploration::{leaf_spread, LeafSpread};
use crate::record::{finite_text, optional_text};
use crate::scenarios::{shaking_column_in, ColumnUnits, Shaking};
use crate::simulation::{simulate, RunOptions};
use crate::studies::convergence::row::RowConvergence;
use crate::studies::convergence::Settings;

/// How one run of the frequency sweep ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FrequencyOutcome {
    /// The column lost support at the failure time T.
    Failed,
    /// No loss of support up to the horizon: T is only known to exceed it.
    NoFailureByHorizon,
    /// The run stopped early, or could not start (see the row's error).
    Stopped,
}

impl FrequencyOutcome {
    /// The name in the CSV and JSON.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Failed => "failed",
            Self::NoFailureByHorizon => "no_failure_by_horizon",
            Self::Stopped => "stopped",
        }
    }
}

/// One run of the frequency sweep (one point of Figure 4.6).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FrequencyRow {
    /// ω.
    pub omega: f64,
    /// The time simulated unless the column fails first, time units: the periods times
    /// 2π/ω, or the sweep's `t_max`.
    pub horizon: f64,
    /// How the run ended.
    pub outcome: FrequencyOutcome,
    /// Failure time T (loss of support), or null when the column survived.
    pub failure_time: Option<f64>,
    /// 1/T, 0 when the column survived to the horizon (outcome
    /// `no_failure_by_horizon`: T > horizon, not T = ∞).
    pub inv_failure_time: Option<f64>,
    /// First full opening of an interface, or null.
    pub opening_time: Option<f64>,
    /// Steps taken.
    pub steps: usize,
    /// Why the run stopped early (or could not start), or null.
    pub error: Option<String>,
    /// Steps whose first Newton attempt failed.
    pub failed_steps: usize,
    /// Branch points recorded.
    pub branch_points: usize,
    /// Solver time (s).
    pub wall_time_s: f64,
    /// Motions explored ([`RunOptions::spread_branches`]; 1: the plain run).
    pub branches: usize,
    /// How many of them failed by the horizon.
    pub failed_branches: usize,
    /// Smallest failure time over the explored motions that failed, or null.
    pub failure_time_min: Option<f64>,
    /// Their median failure time, or null.
    pub failure_time_median: Option<f64>,
    /// Their largest failure time, or null.
    pub failure_time_max: Option<f64>,
    /// With `--convergence K`: the row's verdicts over Δt/2^k, k = 0…K
    /// ([`crate::studies::convergence::row`]); absent otherwise, so that the row, its
    /// JSON and its line in the row log are those of a sweep without it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub convergence: Option<RowConvergence>,
}

impl FrequencyRow {
    /// The columns of `sweep_frequency.csv`, one per field, in order.
    pub const CSV_HEADER: [&'static str; 16] = [
        "omega",
        "horizon",
        "outcome",
        "failure_time",
        "inv_failure_time",
        "opening_time",
        "steps",
        "error",
        "failed_steps",
        "branch_points",
        "wall_time_s",
        "branches",
        "failed_branches",
        "failure_time_min",
        "failure_time_median",
        "failure_time_max",
    ];

    /// The row's cells under [`Self::CSV_HEADER`]: numbers in shortest round-trip form,
    /// an empty cell for a missing or non-finite value.
    #[must_use]
    pub fn csv_cells(&self) -> Vec<String> {
        vec![
            finite_text(self.omega),
            finite_text(self.horizon),
            self.outcome.name().to_owned(),
            optional_text(self.failure_time),
            optional_text(self.inv_failure_time),
            optional_text(self.opening_time),
            self.steps.to_string(),
            self.error.clone().unwrap_or_default(),
            self.failed_steps.to_string(),
            self.branch_points.to_string(),
            finite_text(self.wall_time_s),
            self.branches.to_string(),
            self.failed_branches.to_string(),
            optional_text(self.failure_time_min),
            optional_text(self.failure_time_median),
            optional_text(self.failure_time_max),
        ]
    }
}

/// One line: ω, the failure time (or "never") and the steps, with the error if any.
impl std::fmt::Display for FrequencyRow {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let failure = self.failure_time.map_or_else(
            || format!("none by t = {:.4}", self.horizon),
            |t| format!("at t = {t:.4}"),
        );
        write!(
            f,
            "omega = {:.4}: failure {failure}, {} steps",
            self.omega, self.steps
        )?;
        // The spread over the explored motions (`--branches`), so that the text says
        // what the band drawn shows: whenever it is more than the plain run's time.
        let plain = [self.failure_time; 2] == [self.failure_time_min, self.failure_time_max];
        if self.branches > 1 || !plain {
            let s = if self.branches == 1 { "" } else { "s" };
            write!(
                f,
                "; {} motion{s}, {} failed",
                self.branches, self.failed_branches
            )?;
            if let (Some(lo), Some(hi)) = (self.failure_time_min, self.failure_time_max) {
                write!(f, " between t = {lo:.4} and {hi:.4}")?;
            }
        }
        if let Some(c) = &self.convergence {
            f.write_str(&c.line())?;
        }
        if let Some(e) = &self.error {
            write!(f, ", error: {e}")?;
        }
        Ok(())
    }
}

/// Shakes the column `shaking` describes (its ω, amplitude, blocks, μ, steps per period
/// and periods) until its first loss of support or the end of its periods; every
/// failure (a bad parameter, a step that cannot be resolved) goes into the row.
#[must_use]
pub fn frequency_row(shaking: &Shaking, options: &RunOptions) -> FrequencyRow {
    frequency_row_in(shaking, &ColumnUnits::default(), options)
}

/// [`frequency_row`] for blocks of another size or in another gravity (`units`).
#[must_use]
pub fn frequency_row_in(
    shaking: &Shaking,
    units: &ColumnUnits,
    options: &RunOptions,
) -> FrequencyRow {
    let mut row = FrequencyRow {
        omega: shaking.omega,
        horizon: shaking.duration(),
        outcome: FrequencyOutcome::Stopped,
        failure_time: None,
        inv_failure_time: None,
        opening_time: None,
        steps: 0,
        error: None,
        failed_steps: 0,
        branch_points: 0,
        wall_time_s: 0.0,
        branches: 0,
        failed_branches: 0,
        failure_time_min: None,
        failure_time_median: None,
        failure_time_max: None,
        convergence: None,
    };
    let options = RunOptions {
        stop_at_failure: true,
        ..options.clone()
    };
    let scene = match shaking_column_in(shaking, units) {
        Ok(s) => s,
        Err(e) => {
            row.error = Some(one_line(&e.to_string()));
            return row;
        }
    };
    match simulate(&scene, &options, |_| {}) {
        Ok(s) => {
            row.failure_time = s.failure_time;
            // Survival over the whole run: 1/T = 0 (Figure 4.6's baseline), unless the run
            // stopped early, when nothing is known.
            row.inv_failure_time = match (s.failure_time, &s.error) {
                (Some(t), _) if t > 0.0 => Some(1.0 / t),
                (None, None) => Some(0.0),
                _ => None,
            };
            row.outcome = match (s.failure_time, &s.error) {
                (Some(_), _) => FrequencyOutcome::Failed,
                (None, None) => FrequencyOutcome::NoFailureByHorizon,
                (None, Some(_)) => FrequencyOutcome::Stopped,
            };
            row.opening_time = s.opening_time;
            row.steps = s.steps;
            row.error = s.error.map(|e| one_line(&e.to_string()));
            row.failed_steps = s.failed_steps;
            row.branch_points = s.branch_points.len();
            row.wall_time_s = s.wall_time_s;
            let spread = leaf_spread(&scene, &options, true, s.failure_time, |b| {
                b.outcome.failure_time
            });
            match spread {
                Ok(LeafSpread {
                    branches,
                    valued,
                    spread,
                }) => {
                    row.branches = branches;
                    row.failed_branches = valued;
                    row.failure_time_min = spread.map(|v| v[0]);
                    row.failure_time_median = spread.map(|v| v[1]);
                    row.failure_time_max = spread.map(|v| v[2]);
                }
                Err(e) => row.error = Some(one_line(&e.to_string())),
            }
        }
        Err(e) => row.error = Some(one_line(&e.to_string())),
    }
    row
}

/// [`frequency_row_in`] and, with `settings` (`--convergence K`), the row's verdicts
/// over Δt/2^k on its failure time ([`RowConvergence`]; each run stops at its failure).
#[must_use]
pub fn frequency_row_judged(
    shaking: &Shaking,
    units: &ColumnUnits,
    options: &RunOptions,
    settings: Option<Settings>,
) -> FrequencyRow {
    let mut row = frequency_row_in(shaking, units, options);
    if let (Some(settings), Ok(scene)) = (settings, shaking_column_in(shaking, units)) {
        let options = RunOptions {
            stop_at_failure: true,
            ..options.clone()
        };
        row.convergence = Some(RowConvergence::of(&scene, &options, settings, |r| {
            r.observed.failure_time
        }));
    }
    row
}

/// The periods that make a run at `omega` last `t_max` time units: the sweep's horizon
/// in time units, the same for every ω. (A fixed number of periods simulates a fast base
/// for a shorter time than a slow one: ten periods are 1.6 time units at ω = 40, while
/// shaken columns fail between t ≈ 3 and t ≈ 40.)
#[must_use]
pub fn periods_for_horizon(t_max: f64, omega: f64) -> f64 {
    t_max * omega / (2.0 * std::f64::consts::PI)
}

/// A message on one line (a CSV cell, a sweep's line of output).
#[must_use]
pub fn one_line(s: &str) -> String {
    s.replace(['\n', '\r'], " ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_cells_match_the_header_and_leave_missing_values_empty() {
        let row = frequency_row(
            &Shaking {
                omega: 0.5,
                periods: 0.2,
                ..Shaking::default()
            },
            &RunOptions::default(),
        );
        let cells = row.csv_cells();
        assert_eq!(cells.len(), FrequencyRow::CSV_HEADER.len());
        assert_eq!(cells[0], "0.5");
        assert_eq!(cells[2], "no_failure_by_horizon");
        assert_eq!((cells[3].as_str(), cells[4].as_str()), ("", "0.0"));
    }

    #[test]
    fn a_slowly_shaken_column_survives_and_a_bad_frequency_is_a_row_error() {
        let slow = Shaking {
            omega: 0.5,
            periods: 0.2,
            ..Shaking::default()
        };
        let row = frequency_row(&slow, &RunOptions::default());
        assert_eq!(row.failure_time, None);
        assert_eq!(row.outcome, FrequencyOutcome::NoFailureByHorizon);
        assert!((row.horizon - 0.2 * 2.0 * std::f64::consts::PI / 0.5).abs() < 1e-12);
        assert_eq!(row.inv_failure_time, Some(0.0));
        assert!(row.steps > 0 && row.error.is_none());
        let bad = Shaking {
            omega: -1.0,
            ..Shaking::default()
        };
        let row = frequency_row(&bad, &RunOptions::default());
        assert!(
            row.error.as_deref().is_some_and(|e| e.contains("omega")),
            "{row:?}"
        );
        assert_eq!(row.steps, 0);
        assert_eq!(row.outcome, FrequencyOutcome::Stopped);
    }

    /// Ten periods at ω = 8 are 7.9 time units, within which the tour's column survives;
    /// a horizon of 20 time units gives ω = 8 the time a slow base gets, and the column
    /// fails (at t ≈ 15: `rollstack blocks sweep frequency --omega 8 --t-max 20`).
    #[test]
    fn a_horizon_in_time_units_gives_a_fast_base_the_time_a_slow_one_gets() {
        let ten_periods = Shaking {
            omega: 8.0,
            ..Shaking::default()
        };
        let short = frequency_row(&ten_periods, &RunOptions::default());
        assert!((short.horizon - 2.5 * std::f64::consts::PI).abs() < 1e-12);
        assert_eq!(
            short.outcome,
            FrequencyOutcome::NoFailureByHorizon,
            "{short}"
        );
        let long = frequency_row(
            &Shaking {
                periods: periods_for_horizon(20.0, 8.0),
                ..ten_periods
            },
            &RunOptions::default(),
        );
        assert!((long.horizon - 20.0).abs() < 1e-12);
        assert_eq!(long.outcome, FrequencyOutcome::Failed, "{long}");
        assert!(long
            .failure_time
            .is_some_and(|t| t > short.horizon && t < 20.0));
    }

    #[test]
    fn a_fast_shaken_column_fails_and_reports_one_over_t() {
        let fast = Shaking {
            omega: 4.0,
            ..Shaking::default()
        };
        let row = frequency_row(&fast, &RunOptions::default());
        let t = row.failure_time.expect("the tour's shaken column fails");
        assert_eq!(row.inv_failure_time, Some(1.0 / t));
    }
}
