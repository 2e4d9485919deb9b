//! The time guard of the two-cylinder runs (`cylinder pair`, `cylinder sweep
//! pair|push`): the cost of a step measured on the first steps of a run, extrapolated
//! to every step of every run, refused over [`TIME_BOUND_S`] unless `--force` (as the
//! block commands' guard, [`crate::commands::blocks::check_time_bound`]).

use crate::commands::blocks::TIME_BOUND_S;
use anyhow::Result;
use cylinders::studies::pair::{run_pair, PairSettings};

/// Steps of the trial run that measures a step's cost (a few ms in a release build).
const TRIAL_STEPS: usize = 100;

/// Refuses `runs` runs of `settings` (each `settings.steps` steps, shared out over the
/// threads) estimated to take more than [`TIME_BOUND_S`], unless `force`. Nothing is
/// written before; a trial that fails is left to the run itself to report.
///
/// # Errors
/// When the estimate is over the bound and `force` is false.
pub fn check_time_bound(settings: &PairSettings, runs: usize, force: bool) -> Result<()> {
    if force || runs == 0 {
        return Ok(());
    }
    let trial = PairSettings {
        steps: settings.steps.min(TRIAL_STEPS),
        ..*settings
    };
    let Ok(report) = run_pair(&trial, false) else {
        return Ok(());
    };
    #[allow(clippy::cast_precision_loss)]
    let (per_step, steps, threads) = (
        report.wall_time_s / trial.steps as f64,
        settings.steps as f64 * runs as f64,
        rayon::current_num_threads().min(runs) as f64,
    );
    let seconds = per_step * steps / threads;
    anyhow::ensure!(
        seconds <= TIME_BOUND_S,
        "{runs} run(s) of {steps:.1e} steps in all would take about {seconds:.1e} s (at \
         {:.0} µs per step, measured on the first {} steps), more than {TIME_BOUND_S} s: \
         take fewer --steps or values, or pass --force",
        per_step * 1e6,
        trial.steps
    );
    Ok(())
}
