//! A step taken as substeps of Δt/parts ([`Stepper::split_step`]), and the halves of the
//! policy's [`Stage::Halving`](super::policy::Stage): what a split saves to restore when
//! a substep fails, the substeps' statistics merged, and the state put back on the
//! step's time grid.

use super::Stepper;
use crate::error::StepError;
use crate::options::Options;
use crate::report::{RunStats, StepStats};
use crate::state::State;
use crate::system::System;

/// A step under way as substeps: what it restores when one fails, how many are left,
/// and the statistics of those taken.
#[derive(Debug)]
pub(super) struct Halves {
    state: State,
    options: Options,
    base: (f64, u64),
    stats: RunStats,
    last: Option<StepStats>,
    /// Substeps left to take.
    pub(super) left: usize,
    merged: Option<StepStats>,
}

impl<S: System> Stepper<S> {
    /// Takes the step t_n → t_n + Δt as `parts` substeps of Δt/`parts`, each committed
    /// by `substep` (for example `|s| s.step().map(|_| ())`, or a caller's own policy),
    /// then puts the state back on the time grid: k advances by one and t = t₀ + kΔt
    /// exactly. The generalized-α auxiliary variables (ā, λ̄) carry over between step
    /// sizes unchanged, since their recursion (eqs. 71, 73) does not involve Δt.
    ///
    /// The substeps' statistics are merged into one [`StepStats`]: iterations and retries
    /// summed (plus one retry for the failed whole step), `substeps` counted, the first
    /// branch point kept; [`RunStats`] counts one step.
    ///
    /// # Errors
    /// [`StepError::InvalidInput`] for `parts` = 0; otherwise the first substep error,
    /// after which the stepper is back at the state, options and statistics it had.
    pub fn split_step(
        &mut self,
        parts: usize,
        mut substep: impl FnMut(&mut Self) -> Result<(), StepError>,
    ) -> Result<&StepStats, StepError> {
        let mut split = self.begin_split(parts)?;
        while split.left > 0 {
            if let Err(e) = substep(self) {
                self.abort_split(split);
                return Err(e);
            }
            self.substep_done(&mut split);
        }
        self.finish_split(split);
        Ok(self.committed())
    }

    /// Starts the step as `parts` substeps: Δt/`parts` from here on.
    pub(super) fn begin_split(&mut self, parts: usize) -> Result<Halves, StepError> {
        if parts == 0 {
            return Err(StepError::InvalidInput(
                "a step splits into at least one part".into(),
            ));
        }
        let split = Halves {
            state: self.state.clone(),
            options: self.options.clone(),
            base: self.time_base,
            stats: self.stats.clone(),
            last: self.last.clone(),
            left: parts,
            merged: None,
        };
        // Substeps are not on the step's grid: their solutions predict nothing for it
        // (nor the step's for them).
        self.forget_solutions();
        let mut sub = split.options.clone();
        sub.dt = split.options.dt / parts as f64;
        self.set_options(sub)?;
        Ok(split)
    }

    /// A substep was committed: its statistics join the step's.
    pub(super) fn substep_done(&mut self, split: &mut Halves) {
        let last = self.committed().clone();
        split.merged = Some(match split.merged.take() {
            None => last,
            Some(m) => StepStats {
                t: last.t,
                iterations: m.iterations + last.iterations,
                residual: m.residual.max(last.residual),
                retries: m.retries + last.retries,
                converged: m.converged && last.converged,
                branch: m.branch.or(last.branch),
                unshifted: m.unshifted || last.unshifted,
                substeps: m.substeps + last.substeps,
                ..last
            },
        });
        split.left -= 1;
    }

    /// A substep failed: back to the state, options and statistics before the split.
    pub(super) fn abort_split(&mut self, split: Halves) {
        self.options = split.options;
        self.time_base = split.base;
        self.state = split.state;
        self.forget_solutions();
        self.stats = split.stats;
        self.last = split.last;
    }

    /// Every substep was committed: the state back on the step's grid, and the step's
    /// merged statistics committed as one step.
    pub(super) fn finish_split(&mut self, split: Halves) {
        let mut merged = split.merged.expect("a split takes at least one substep");
        merged.retries += 1;
        self.options = split.options;
        self.time_base = split.base;
        self.state.k = split.state.k + 1;
        self.state.t = self.grid_time(self.state.k);
        merged.t = self.state.t;
        self.forget_solutions();
        self.stats = split.stats;
        self.stats.split_steps += 1;
        self.account(&merged);
        self.last = Some(merged);
    }
}
