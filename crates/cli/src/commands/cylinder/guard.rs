//! The time guard of the two-cylinder runs (`cylinder pair`, `cylinder sweep
//! pair|push`): the cost of a step measured on the first steps of a run, extrapolated
//! to every step of every run ([`cylinders::studies::pair_cost`]), refused over
//! [`TIME_BOUND_S`] unless `--force` (as the block commands' guard,
//! [`crate::commands::blocks::check_time_bound`]).

use crate::commands::blocks::TIME_BOUND_S;
use anyhow::Result;
use cylinders::studies::pair::PairSettings;
use cylinders::studies::pair_cost::pair_cost;

/// Refuses `rows` rows of `runs_per_row` runs of `settings` (each `settings.steps`
/// steps; the rows share out the threads, a row's runs go one after another) estimated
/// to take more than [`TIME_BOUND_S`], unless `force`, saying what to change (`advice`).
/// Nothing is written before; a trial that fails is left to the run itself to report.
///
/// # Errors
/// When the estimate is over the bound and `force` is false.
pub fn check_time_bound(
    settings: &PairSettings,
    rows: usize,
    runs_per_row: usize,
    force: bool,
    advice: &str,
) -> Result<()> {
    if force {
        return Ok(());
    }
    let Some(cost) = pair_cost(settings, rows, runs_per_row, rayon::current_num_threads()) else {
        return Ok(());
    };
    anyhow::ensure!(
        cost.seconds <= TIME_BOUND_S,
        "{cost}, more than {TIME_BOUND_S} s: {advice}, or pass --force"
    );
    Ok(())
}

/// The advice of the pair's runs and sweeps.
pub const FEWER_STEPS: &str = "take fewer --steps or values";

pub use input::watchdog::time_bound;
