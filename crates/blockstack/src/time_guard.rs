//! The time guard: what a run will cost, known before it is started, so that a run of
//! hours (a large `t_end`, a tiny Δt, many blocks) is refused up front unless forced.
//!
//! Two estimates, both before any output is written:
//! - [`run_cost`], from the step count and the size alone at a typical
//!   [`SECONDS_PER_BLOCK_STEP`]: nothing is run, so an endless run is refused at once;
//! - [`Guard::check`] then runs the first steps of the costliest run (at most
//!   [`CALIBRATION_STEPS`] steps or [`CALIBRATION_WALL_S`] seconds, nothing recorded),
//!   measures its cost per block and step on this machine and in this build, and
//!   extrapolates: the typical rate alone underestimated a debug build, or a scene whose
//!   steps cost more than a standing column's, by ten times and more.
//!
//! The larger of the two estimates is the guard's.
//!
//! Both see only a run's start, and a column's later steps may cost many times its first
//! (a shaken column of 50 blocks, once collapsed, costs 20 times its standing steps). So a
//! run that starts is also watched: a [`Watchdog`], consulted by the run's `on_step`
//! callback, projects the run's wall time from the wall time spent and the model time
//! reached, and stops the run when the projection passes [`TIME_BOUND_S`]. The library
//! runs it: [`simulate_until`] watches every run whose [`RunOptions::time_bound`] is set
//! (the CLI's and Python's runs unless forced, so a sweep's rows and an exploration's root
//! run too) and ends a run it stops with [`crate::RunError::Stopped`].

use crate::scene::Scene;
use crate::simulation::{simulate_until, RunOptions};
use std::fmt;
use std::ops::ControlFlow;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{mpsc, Arc};
use std::time::{Duration, Instant};

/// A typical solver cost per block and step on one core of a release build, seconds:
/// the stack's runs measure 8–20 µs (`rollstack blocks shake --json`, `wall_time_s`
/// over `steps` and blocks), so this estimate errs on the slow side. Debug builds are
/// 10–30 times slower.
pub const SECONDS_PER_BLOCK_STEP: f64 = 2e-5;

pub use input::watchdog::{
    Clock, Overrun, WallClock, Watchdog, STOPPED_BY_WATCHDOG, TIME_BOUND_S, WATCHDOG_GRACE_S,
};

/// The most steps of a run's start that [`Guard::check`] runs to measure its cost.
pub const CALIBRATION_STEPS: usize = 20;

/// The calibration stops after the first step that ends this long (s) after its start.
pub const CALIBRATION_WALL_S: f64 = 1.0;

/// The longest the calibration waits for its first step, s ([`measured_rate`]).
pub const CALIBRATION_TIMEOUT_S: f64 = 10.0;

/// What a run will cost before it starts, from its step count and size alone.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct RunCost {
    /// Steps to the end time: t_end / Δt.
    pub steps: f64,
    /// The blocks of the scene.
    pub blocks: usize,
    /// A typical wall time, s: steps × blocks × [`SECONDS_PER_BLOCK_STEP`].
    pub seconds: f64,
}

impl RunCost {
    /// Block-steps of the run: what its wall time is proportional to.
    #[must_use]
    pub fn block_steps(&self) -> f64 {
        #[allow(clippy::cast_precision_loss)]
        let blocks = self.blocks as f64;
        self.steps * blocks
    }
}

/// The cost of running `scene` with `options`, before any step: nothing is run.
/// An end time or step that is not positive gives the cost of zero steps (the run
/// itself refuses it with its reason).
#[must_use]
pub fn run_cost(scene: &Scene, options: &RunOptions) -> RunCost {
    let t_end = options.t_end.unwrap_or(scene.solver.t_end);
    let steps = (t_end / scene.solver.dt).max(0.0);
    let steps = if steps.is_finite() {
        steps
    } else {
        f64::INFINITY
    };
    let blocks = scene.blocks().len();
    #[allow(clippy::cast_precision_loss)]
    let seconds = steps * blocks as f64 * SECONDS_PER_BLOCK_STEP;
    RunCost {
        steps,
        blocks,
        seconds,
    }
}

/// Seconds per block and step of the first steps of `scene`'s run with `options`
/// (the solver's start included, nothing recorded), or `None` when no step could be
/// taken (the run itself then reports why).
///
/// The trial runs on its own thread, watched for [`CALIBRATION_TIMEOUT_S`]: a scene
/// whose start and first step take longer is given that time as the cost of one step
/// (a lower bound) and its trial is cancelled, ending within its current step at its
/// next Newton update ([`nsga::Interrupt`]), so that the guard never waits on a step of
/// hours and the trial does not go on beside the run.
#[must_use]
pub fn measured_rate(scene: &Scene, options: &RunOptions) -> Option<f64> {
    let cancel = Arc::new(AtomicBool::new(false));
    let trial = RunOptions {
        cancel: Some(cancel.clone()),
        time_bound: None,
        ..options.clone()
    };
    let scene = scene.clone();
    #[allow(clippy::cast_precision_loss)]
    let blocks = scene.blocks().len() as f64;
    let clock = Instant::now();
    let (sender, steps) = mpsc::channel();
    std::thread::spawn(move || {
        let clock = Instant::now();
        // `on_step` sees the initial state first, then each step.
        let mut records = 0usize;
        let summary = simulate_until(&scene, &trial, |_| {
            records += 1;
            let steps = records - 1;
            let done = steps >= CALIBRATION_STEPS
                || (steps >= 1 && clock.elapsed().as_secs_f64() >= CALIBRATION_WALL_S);
            if done {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        });
        // The receiver is gone after a timeout: nothing to tell.
        let _ = sender.send(summary.map(|s| s.steps).unwrap_or(0));
    });
    let timeout = Duration::from_secs_f64(CALIBRATION_TIMEOUT_S);
    match steps.recv_timeout(timeout) {
        Ok(0) => None,
        #[allow(clippy::cast_precision_loss)]
        Ok(steps) => Some(clock.elapsed().as_secs_f64() / (steps as f64 * blocks)),
        Err(_) => {
            cancel.store(true, Ordering::Relaxed);
            Some(CALIBRATION_TIMEOUT_S / blocks)
        }
    }
}

/// The guard's estimate of a set of runs shared out over threads.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    /// The runs.
    pub runs: usize,
    /// Their steps in all.
    pub steps: f64,
    /// Their wall time shared out over the threads, s.
    pub seconds: f64,
    /// The cost per block and step it was estimated at, s.
    pub rate: f64,
    /// Whether `rate` was measured on the first steps (else it is
    /// [`SECONDS_PER_BLOCK_STEP`]).
    pub measured: bool,
}

impl Estimate {
    /// The estimate of `costs` at `rate` seconds per block and step on `threads` threads.
    #[must_use]
    pub fn new(costs: &[RunCost], threads: usize, rate: f64, measured: bool) -> Self {
        #[allow(clippy::cast_precision_loss)]
        let threads = threads.min(costs.len()).max(1) as f64;
        let block_steps: f64 = costs.iter().map(RunCost::block_steps).sum();
        Self {
            runs: costs.len(),
            steps: costs.iter().map(|c| c.steps).sum(),
            seconds: block_steps * rate / threads,
            rate,
            measured,
        }
    }

    /// Whether it is over [`TIME_BOUND_S`] (an endless run is).
    #[must_use]
    pub fn over_bound(&self) -> bool {
        self.seconds.is_nan() || self.seconds > TIME_BOUND_S
    }
}

impl fmt::Display for Estimate {
    /// `4 run(s) of 4.0e5 steps in all would take about 1.6e3 s (at 20 µs per block and
    /// step), more than 600 s`
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let how = if self.measured {
            format!(", measured on the first {CALIBRATION_STEPS} steps or fewer")
        } else {
            String::new()
        };
        write!(
            f,
            "{} run(s) of {:.1e} steps in all would take about {:.1e} s (at {:.0} µs per \
             block and step{how}), more than {TIME_BOUND_S} s",
            self.runs,
            self.steps,
            self.seconds,
            self.rate * 1e6
        )
    }
}

/// The time guard of a set of runs: their costs, and one of them (the costliest) to
/// calibrate on.
#[derive(Debug, Clone, Copy)]
pub struct Guard<'a> {
    /// The runs' costs ([`run_cost`]).
    pub costs: &'a [RunCost],
    /// The threads they are shared out over.
    pub threads: usize,
    /// The run whose first steps are measured, with its options.
    pub probe: Option<(&'a Scene, &'a RunOptions)>,
}

impl Guard<'_> {
    /// Refuses runs over [`TIME_BOUND_S`]: at the typical rate first (nothing run),
    /// then at the rate measured on the probe's first steps when that is slower.
    ///
    /// # Errors
    /// The estimate that is over the bound.
    pub fn check(&self) -> Result<(), Estimate> {
        let typical = Estimate::new(self.costs, self.threads, SECONDS_PER_BLOCK_STEP, false);
        if typical.over_bound() {
            return Err(typical);
        }
        let measured = self
            .probe
            .filter(|_| self.measures())
            .and_then(|(scene, options)| measured_rate(scene, options));
        match measured {
            Some(rate) if rate > SECONDS_PER_BLOCK_STEP => {
                let calibrated = Estimate::new(self.costs, self.threads, rate, true);
                if calibrated.over_bound() {
                    return Err(calibrated);
                }
                Ok(())
            }
            _ => Ok(()),
        }
    }

    /// Whether [`Guard::check`] measures the probe's first steps: only where the
    /// slowest rate a measurement can give, a first step (the solver's start included)
    /// that takes the whole [`CALIBRATION_TIMEOUT_S`], would put the runs over the
    /// bound. Elsewhere no measurement could refuse them, and it would only run their
    /// first steps twice: the ten steps of the 10 000-block column (docs/method.md
    /// §8.2) took 13 s with it and 8 s without.
    #[must_use]
    pub fn measures(&self) -> bool {
        self.probe.is_some_and(|(scene, _)| {
            #[allow(clippy::cast_precision_loss)]
            let slowest = CALIBRATION_TIMEOUT_S / scene.blocks().len().max(1) as f64;
            Estimate::new(self.costs, self.threads, slowest, true).over_bound()
        })
    }
}

/// A wall-time limit of `seconds` (≥ 0, as an exploration's `max_wall`), or `None` (no
/// limit) for a time too long for the clock to reach: 1e20 s is beyond what a
/// [`Duration`] or a deadline of [`Instant`] can hold, and beyond any run.
#[must_use]
pub fn wall_limit(seconds: f64) -> Option<Duration> {
    // With a day to spare: the deadline is taken a little later than now.
    const SPARE: Duration = Duration::from_secs(86_400);
    Duration::try_from_secs_f64(seconds).ok().filter(|&d| {
        d.checked_add(SPARE)
            .and_then(|d| Instant::now().checked_add(d))
            .is_some()
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenarios::{shaking_column, Shaking};

    #[test]
    fn an_endless_run_is_over_the_bound_without_a_step() {
        let scene = shaking_column(&Shaking::default()).unwrap();
        let endless = RunOptions {
            t_end: Some(1e300),
            ..RunOptions::default()
        };
        let costs = [run_cost(&scene, &endless)];
        let guard = Guard {
            costs: &costs,
            threads: 4,
            probe: Some((&scene, &endless)),
        };
        let clock = Instant::now();
        let e = guard.check().unwrap_err();
        assert!(clock.elapsed().as_secs_f64() < 0.5, "no step is run");
        assert!(e.over_bound() && !e.measured, "{e}");
        assert!(e.to_string().contains("more than 600 s"), "{e}");
    }

    #[test]
    fn the_first_steps_give_a_rate_and_a_slow_rate_refuses() {
        let scene = shaking_column(&Shaking::default()).unwrap();
        let options = RunOptions::default();
        let rate = measured_rate(&scene, &options).unwrap();
        assert!(rate > 0.0 && rate.is_finite(), "{rate}");
        // A run the typical rate lets through is refused at a rate ten times slower.
        let cost = run_cost(&scene, &options);
        let block_steps = TIME_BOUND_S / SECONDS_PER_BLOCK_STEP / 2.0;
        let runs = vec![cost; (block_steps / cost.block_steps()) as usize];
        assert!(!Estimate::new(&runs, 1, SECONDS_PER_BLOCK_STEP, false).over_bound());
        let slow = Estimate::new(&runs, 1, 10.0 * SECONDS_PER_BLOCK_STEP, true);
        assert!(slow.over_bound(), "{slow}");
        assert!(slow.to_string().contains("measured on the first"), "{slow}");
        // Shared out over threads.
        assert!(!Estimate::new(&runs, 10, 10.0 * SECONDS_PER_BLOCK_STEP, true).over_bound());
    }

    #[test]
    fn runs_no_measurement_could_refuse_are_not_measured() {
        let tall = shaking_column(&Shaking::tall_column(1000, true)).unwrap();
        let guard = |options: &RunOptions, threads| {
            let costs = [run_cost(&tall, options)];
            Guard {
                costs: &costs,
                threads,
                probe: Some((&tall, options)),
            }
            .measures()
        };
        let steps = |n: f64| RunOptions {
            t_end: Some(n * tall.solver.dt),
            ..RunOptions::default()
        };
        // 10 s a step at most: 60 steps fit in the bound, 61 do not.
        assert!(!guard(&steps(59.5), 1));
        assert!(guard(&steps(61.5), 1));
        // A long run of a small scene is measured.
        let small = shaking_column(&Shaking::default()).unwrap();
        let options = RunOptions::default();
        let costs = [run_cost(&small, &options)];
        let probe = Some((&small, &options));
        assert!(Guard {
            costs: &costs,
            threads: 1,
            probe
        }
        .measures());
        assert!(!Guard {
            costs: &costs,
            threads: 1,
            probe: None
        }
        .measures());
    }

    #[test]
    fn a_wall_limit_beyond_the_clock_is_no_limit() {
        assert_eq!(wall_limit(5.0), Some(Duration::from_secs(5)));
        assert_eq!(wall_limit(1e20), None);
        assert_eq!(wall_limit(f64::INFINITY), None);
    }
}
