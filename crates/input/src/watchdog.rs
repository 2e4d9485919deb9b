//! The run-time watchdog, shared by every run loop that is bounded in time (the block
//! stack's `simulate_until`, the cylinder pair's steps): a run's wall time is projected
//! from the wall time spent and the model time reached (or any measure of progress, as
//! steps done), and a run projected past its bound is stopped with an [`Overrun`] that
//! says where and what it was projected to take.

use std::fmt;
use std::ops::ControlFlow;
use std::time::Instant;

/// The longest estimated wall time a run starts without being forced, s (ten minutes).
pub const TIME_BOUND_S: f64 = 600.0;

/// The bound of a watched run ([`Watchdog`]): [`TIME_BOUND_S`], or none when the run is
/// forced (`--force`, `force=True`, a merge or a task of a Slurm job array).
#[must_use]
pub fn time_bound(force: bool) -> Option<f64> {
    (!force).then_some(TIME_BOUND_S)
}

/// How the message of a stopped run starts ([`Overrun::message`]): a sweep's row error
/// that starts so was stopped, not failed.
pub const STOPPED_BY_WATCHDOG: &str = "stopped by the watchdog";

/// Seconds of a run before its [`Watchdog`] projects anything at the bound
/// [`TIME_BOUND_S`]: the solver's start and the first steps cost more per step than the
/// rest, and would stop runs that fit. A smaller bound has a grace of the same share of
/// it (a test's bound of a millisecond, a few microseconds).
pub const WATCHDOG_GRACE_S: f64 = 5.0;

/// The wall time since some start, s: the [`Watchdog`]'s clock.
pub trait Clock {
    /// Seconds since the start.
    fn seconds(&self) -> f64;
}

/// The wall clock, from its creation on.
#[derive(Debug, Clone, Copy)]
pub struct WallClock(Instant);

impl WallClock {
    /// A clock that starts now.
    #[must_use]
    pub fn start() -> Self {
        Self(Instant::now())
    }
}

impl Clock for WallClock {
    fn seconds(&self) -> f64 {
        self.0.elapsed().as_secs_f64()
    }
}

/// A clock one second further on at every reading: the checks of a watchdog on it come
/// one second apart whatever the machine, so that a test of a watched run loop knows
/// after which step the projection passes the bound.
#[derive(Debug, Default)]
pub struct TickingClock(std::cell::Cell<f64>);

impl Clock for TickingClock {
    fn seconds(&self) -> f64 {
        self.0.set(self.0.get() + 1.0);
        self.0.get()
    }
}

/// Where a watched run was stopped and what it was projected to take.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Overrun {
    /// The projected wall time of the whole run, s.
    pub projected_s: f64,
    /// The wall time spent when it was stopped, s.
    pub elapsed_s: f64,
    /// The model time reached.
    pub t: f64,
    /// The share of the run's model time done, t − t0 over t_end − t0.
    pub done: f64,
    /// The bound it was projected past, s.
    pub bound_s: f64,
}

impl fmt::Display for Overrun {
    /// `the run was projected to take about 2.1e3 s (6 s for 0.29 % of its model time),
    /// more than 600 s`, or, stopped before its model time moved, `the run spent 600 s
    /// without getting past t = 0 (its bound: 600 s)`
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.projected_s.is_infinite() {
            return write!(
                f,
                "the run spent {:.0} s without getting past t = {} (its bound: {} s)",
                self.elapsed_s, self.t, self.bound_s
            );
        }
        write!(
            f,
            "the run was projected to take about {:.1e} s ({:.0} s for {:.2} % of its model \
             time), more than {} s",
            self.projected_s,
            self.elapsed_s,
            100.0 * self.done,
            self.bound_s,
        )
    }
}

/// Watches a run as it goes: its projected wall time is the wall time spent over the
/// model time reached, times the model time of the whole run,
/// elapsed / (t − t0) × (t_end − t0), and once [`WATCHDOG_GRACE_S`] have passed, a
/// projection over the bound stops the run ([`Self::check`] breaks). A run's cost per
/// step only grows on average as a column collapses, so the projection errs short; but
/// it never errs past the bound itself, since it is at least the time spent. A step still
/// in progress at the bound is stopped within it ([`Self::deadline`]): no watched run goes
/// on for more than [`TIME_BOUND_S`] and one Newton update.
#[derive(Debug, Clone)]
pub struct Watchdog<C = WallClock> {
    clock: C,
    t0: f64,
    t_end: f64,
    bound_s: f64,
    grace_s: f64,
    overrun: Option<Overrun>,
    /// When it was made, on the wall clock: the start of [`Self::deadline`].
    made: Instant,
}

impl Watchdog {
    /// A watchdog of a run from `t0` to `t_end` starting now, at `bound_s`
    /// (a run's time bound), or one that never stops it when `None` (forced).
    #[must_use]
    pub fn for_run(bound_s: Option<f64>, t0: f64, t_end: f64) -> Self {
        Self::new(
            WallClock::start(),
            t0,
            t_end,
            bound_s.unwrap_or(f64::INFINITY),
        )
    }
}

impl<C: Clock> Watchdog<C> {
    /// A watchdog of a run from `t0` to `t_end` on `clock`, stopping it over `bound_s`.
    #[must_use]
    pub fn new(clock: C, t0: f64, t_end: f64, bound_s: f64) -> Self {
        Self {
            clock,
            t0,
            t_end,
            bound_s,
            grace_s: WATCHDOG_GRACE_S * (bound_s / TIME_BOUND_S).min(1.0),
            overrun: None,
            made: Instant::now(),
        }
    }

    /// The projected wall time of the whole run, s, once the run has reached model time
    /// `t` after `elapsed` s; infinite while the model time has not moved.
    #[must_use]
    pub fn projection(&self, t: f64, elapsed: f64) -> f64 {
        let done = t - self.t0;
        if done > 0.0 {
            elapsed / done * (self.t_end - self.t0)
        } else {
            f64::INFINITY
        }
    }

    /// Whether the run, now at model time `t`, may go on: `Break` (and [`Self::overrun`]
    /// set) when its projection passes the bound after the grace time.
    pub fn check(&mut self, t: f64) -> ControlFlow<()> {
        if self.overrun.is_some() {
            return ControlFlow::Break(());
        }
        if self.bound_s.is_infinite() {
            return ControlFlow::Continue(());
        }
        let elapsed = self.clock.seconds();
        if elapsed < self.grace_s {
            return ControlFlow::Continue(());
        }
        if self.projection(t, elapsed) > self.bound_s {
            self.stop_at(t, elapsed);
            return ControlFlow::Break(());
        }
        ControlFlow::Continue(())
    }

    /// The wall-clock instant the bound after the watchdog was made (None when
    /// unbounded; on the wall clock whatever the watchdog's own clock): a step still in
    /// progress then is stopped within it ([`Self::stop_within_step`]), since
    /// [`Self::check`] comes only between steps and one step can take hours.
    #[must_use]
    pub fn deadline(&self) -> Option<Instant> {
        let bound = std::time::Duration::try_from_secs_f64(self.bound_s).ok()?;
        self.made.checked_add(bound)
    }

    /// Records that the run was stopped at its [`Self::deadline`] within the step from
    /// model time `t`: its projection is that of the time spent for the model time
    /// reached (endless when no step was taken).
    pub fn stop_within_step(&mut self, t: f64) {
        let elapsed = self.clock.seconds();
        self.stop_at(t, elapsed);
    }

    /// Records the run stopped at model time `t` after `elapsed` s.
    fn stop_at(&mut self, t: f64, elapsed: f64) {
        self.overrun = Some(Overrun {
            projected_s: self.projection(t, elapsed),
            elapsed_s: elapsed,
            t,
            done: (t - self.t0) / (self.t_end - self.t0),
            bound_s: self.bound_s,
        });
    }

    /// Why the run was stopped, if it was.
    #[must_use]
    pub fn overrun(&self) -> Option<Overrun> {
        self.overrun
    }
}

impl Overrun {
    /// The error of a run stopped with this overrun, naming how to lift the bound.
    #[must_use]
    pub fn message(&self) -> String {
        format!("{STOPPED_BY_WATCHDOG}: {self}; a forced run is not watched (--force, force=True)")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_smaller_bound_has_a_shorter_grace() {
        let now = std::rc::Rc::new(std::cell::Cell::new(0.0));
        // At a bound of 6 s, the grace is 0.05 s: 0.1 s for a hundredth of the run is
        // projected at 10 s and stops it.
        let mut dog = Watchdog::new(FakeClock(now.clone()), 0.0, 1.0, 6.0);
        now.set(0.1);
        assert!(dog.check(0.01).is_break());
        let said = dog.overrun().unwrap().to_string();
        assert!(
            said.contains("1.0e1 s") && said.ends_with("more than 6 s"),
            "{said}"
        );
    }

    /// A clock the test sets.
    struct FakeClock(std::rc::Rc<std::cell::Cell<f64>>);

    impl Clock for FakeClock {
        fn seconds(&self) -> f64 {
            self.0.get()
        }
    }

    #[test]
    fn the_watchdog_projects_from_the_time_spent_and_reached() {
        let now = std::rc::Rc::new(std::cell::Cell::new(0.0));
        // A run from t = 2 to t = 12 (10 time units), watched at a 600 s bound.
        let mut dog = Watchdog::new(FakeClock(now.clone()), 2.0, 12.0, TIME_BOUND_S);
        // Before the grace time, even a projection of hours goes on.
        now.set(WATCHDOG_GRACE_S / 2.0);
        assert!(dog.check(2.0 + 1e-6).is_continue());
        // 60 s for a tenth of the run: 600 s in all, not over the bound.
        assert_eq!(dog.projection(3.0, 60.0), 600.0);
        now.set(60.0);
        assert!(dog.check(3.0).is_continue());
        assert!(dog.overrun().is_none());
        // After it, a projection over the bound stops the run, and it stays stopped.
        now.set(61.0);
        assert!(dog.check(3.0).is_break());
        let o = dog.overrun().unwrap();
        assert!((o.projected_s - 610.0).abs() < 1e-9, "{o:?}");
        assert_eq!((o.elapsed_s, o.t, o.done), (61.0, 3.0, 0.1));
        assert!(dog.check(12.0).is_break());
        let said = o.to_string();
        assert!(
            said.contains("6.1e2 s (61 s for 10.00 % of its model time), more than 600 s"),
            "{said}"
        );
        // A run that has not moved after the grace time is projected endless.
        let mut stuck = Watchdog::new(FakeClock(now.clone()), 0.0, 1.0, TIME_BOUND_S);
        assert!(stuck.check(0.0).is_break());
        assert_eq!(stuck.overrun().unwrap().projected_s, f64::INFINITY);
    }

    #[test]
    fn a_forced_watchdog_never_stops_a_run() {
        let mut dog = Watchdog::for_run(None, 0.0, 1e300);
        assert!(dog.check(1e-300).is_continue());
        assert!(dog.overrun().is_none());
    }
}
