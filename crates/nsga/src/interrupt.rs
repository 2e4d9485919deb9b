//! A request to stop the step in progress.
//!
//! A run is bounded between its steps (the caller looks at the wall time after each
//! one), but one step can itself last hours: a 10 000-block column that starts to tip
//! within its first step walks through tens of thousands of Newton updates of a quarter
//! of a second each (docs/method.md §8.2, tall columns). An [`Interrupt`] lets the caller
//! end such a step: the stepper asks it before every stage of its policy and before every
//! Newton update, and a step it stops ends with [`StepError::Interrupted`], the state left
//! where the step started.
//!
//! Two sources, either of which stops the step: a flag the caller sets from another
//! thread (a cancelled calibration run), and a wall-clock deadline (a run's time bound).
//!
//! [`StepError::Interrupted`]: crate::StepError::Interrupted

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

/// When the step in progress should stop: never (the default), once a flag is set, or
/// once a deadline has passed.
#[derive(Debug, Clone, Default)]
pub struct Interrupt {
    flag: Option<Arc<AtomicBool>>,
    deadline: Option<Instant>,
}

impl Interrupt {
    /// Stops the step once `flag` is set (if any) or `deadline` has passed (if any).
    #[must_use]
    pub fn new(flag: Option<Arc<AtomicBool>>, deadline: Option<Instant>) -> Self {
        Self { flag, deadline }
    }

    /// Whether the step in progress should stop now. Reading the clock costs tens of
    /// nanoseconds, against microseconds for a Newton update.
    #[must_use]
    pub fn requested(&self) -> bool {
        self.flag
            .as_ref()
            .is_some_and(|f| f.load(Ordering::Relaxed))
            || self.deadline.is_some_and(|d| Instant::now() >= d)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn an_interrupt_follows_its_flag_and_its_deadline() {
        assert!(!Interrupt::default().requested());
        let flag = Arc::new(AtomicBool::new(false));
        let on_flag = Interrupt::new(Some(flag.clone()), None);
        assert!(!on_flag.requested());
        flag.store(true, Ordering::Relaxed);
        assert!(on_flag.requested());
        let now = Instant::now();
        assert!(Interrupt::new(None, Some(now)).requested());
        let later = now + Duration::from_secs(3600);
        assert!(!Interrupt::new(None, Some(later)).requested());
    }
}
