//! What the two-cylinder runs of [`super::pair`] will cost, before they start: a step's
//! cost measured on the first steps of one run, extrapolated to every step of every
//! run. The time guards of `rollstack cylinder pair|sweep pair|sweep push` and of the
//! Python module refuse runs estimated over their bound with it.

use super::pair::{run_pair, PairSettings};
use std::fmt;

/// Steps of the trial run that measures a step's cost (a few ms in a release build).
pub const TRIAL_STEPS: usize = 100;

/// The estimated wall time of a set of transport runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairCost {
    /// The runs.
    pub runs: usize,
    /// Their steps in all.
    pub steps: f64,
    /// Their wall time shared out over the threads, s.
    pub seconds: f64,
    /// The cost of one step, measured, s.
    pub per_step: f64,
    /// The steps of the trial run it was measured on.
    pub trial_steps: usize,
}

impl fmt::Display for PairCost {
    /// `4 run(s) of 8.0e9 steps in all would take about 1.6e4 s (at 8 µs per step,
    /// measured on the first 100 steps)`
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} run(s) of {:.1e} steps in all would take about {:.1e} s (at {:.0} µs per \
             step, measured on the first {} steps)",
            self.runs,
            self.steps,
            self.seconds,
            self.per_step * 1e6,
            self.trial_steps
        )
    }
}

/// The cost of `rows` rows of `runs_per_row` runs of `settings` (each `settings.steps`
/// steps), the rows shared out over `threads` threads and a row's runs one after another
/// (a push sweep's pushes), measured on the first [`TRIAL_STEPS`] steps of one run;
/// `None` when there is no run or the trial fails (the run itself then reports why).
#[must_use]
pub fn pair_cost(
    settings: &PairSettings,
    rows: usize,
    runs_per_row: usize,
    threads: usize,
) -> Option<PairCost> {
    let runs = rows.saturating_mul(runs_per_row);
    if runs == 0 {
        return None;
    }
    let trial = PairSettings {
        steps: settings.steps.min(TRIAL_STEPS),
        ..*settings
    };
    let report = run_pair(&trial, false).ok()?;
    #[allow(clippy::cast_precision_loss)]
    let (per_step, steps, threads) = (
        report.wall_time_s / trial.steps as f64,
        settings.steps as f64 * runs as f64,
        threads.clamp(1, rows) as f64,
    );
    Some(PairCost {
        runs,
        steps,
        seconds: per_step * steps / threads,
        per_step,
        trial_steps: trial.steps,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_billion_steps_cost_more_than_a_hundred() {
        let short = PairSettings {
            steps: 200,
            ..PairSettings::thesis(0.5)
        };
        let long = PairSettings {
            steps: 1_000_000_000,
            ..short
        };
        let (a, b) = (
            pair_cost(&short, 1, 1, 1).unwrap(),
            pair_cost(&long, 4, 1, 2).unwrap(),
        );
        assert_eq!((a.trial_steps, b.trial_steps), (TRIAL_STEPS, TRIAL_STEPS));
        assert_eq!(b.steps, 4e9);
        assert!(
            (b.seconds - b.per_step * 2e9).abs() <= 1e-9 * b.seconds,
            "{b}"
        );
        assert!(
            b.to_string().starts_with("4 run(s) of 4.0e9 steps in all"),
            "{b}"
        );
        assert!(pair_cost(&short, 0, 1, 1).is_none());
        let bad = PairSettings { dt: -1.0, ..short };
        assert!(pair_cost(&bad, 1, 1, 1).is_none());
        // A row's runs go one after another: one row of four runs takes one thread.
        let row = pair_cost(&long, 1, 4, 2).unwrap();
        assert_eq!(row.runs, 4);
        assert!(
            (row.seconds - row.per_step * 4e9).abs() <= 1e-9 * row.seconds,
            "{row}"
        );
    }
}
