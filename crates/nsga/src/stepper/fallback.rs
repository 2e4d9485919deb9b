//! The fallback policy of a step whose first Newton attempt fails (docs/method.md §8),
//! as [`Stepper::step`] applies it: other ρ∞ (thesis §4.2), fixed-set re-solves at a
//! branch point, the best iterate, halved substeps, and re-solves at a friction bound.

use super::predict::PREDICTED_START_ITERATIONS;
use super::spec::{AttemptSpec, SetRule, StartAt};
use super::Stepper;
use crate::attempt::{AttemptFailure, AttemptOutcome, Trial};
use crate::error::StepError;
use crate::options::{FailurePolicy, RhoInfRetry};
use crate::report::{Stage, StepStats};
use crate::sets::IndexSets;
use crate::system::System;

/// Newton iterations allowed when checking that a fixed-set solution also solves the
/// free step (it converges at once when it does; see [`Options::boundary_resolves`]).
///
/// [`Options::boundary_resolves`]: crate::Options::boundary_resolves
pub const QUICK_CHECK_ITERATIONS: usize = 8;

impl<S: System> Stepper<S> {
    /// The step with `halvings` halvings left: the policy of [`Stepper::step_once`];
    /// when it fails, the step as two halves, each with this same policy and one halving
    /// less; when that fails too, the re-solves at a friction bound.
    pub(super) fn step_halving(&mut self, halvings: usize) -> Result<(), StepError> {
        let error = match self.step_once() {
            Ok(()) => return Ok(()),
            Err(e) => e,
        };
        if halvings > 0 && self.split_step(2, |s| s.step_halving(halvings - 1)).is_ok() {
            return Ok(());
        }
        match error {
            StepError::NotConverged {
                visited_sets,
                cycling: true,
                residual,
                ..
            } if self.options.boundary_resolves => self.counting(Stage::Boundary, |s| {
                s.resolve_at_boundary(&visited_sets, residual)
            }),
            e => Err(e),
        }
    }

    /// Steps 1–4 of the policy of [`Stepper::step`]: the attempt at the default ρ∞, the
    /// ρ∞ retries, the fixed-set re-solves of a cycling step, the best iterate.
    fn step_once(&mut self) -> Result<(), StepError> {
        let rho0 = self.options.rho_inf;
        let first = self.counting(Stage::FirstAttempt, |s| s.first_attempt(rho0));
        let first = match first {
            Ok(t) => {
                let t = if self.options.probe_flips {
                    self.probe_flips(t, rho0)
                } else {
                    t
                };
                self.commit(t);
                return Ok(());
            }
            Err(f) => f,
        };
        let iterated = matches!(
            first,
            AttemptFailure::NotConverged { .. } | AttemptFailure::Refused { .. }
        );
        // A singular Newton matrix on every attempt is reported as such, not as a
        // non-converged step without iterates.
        let mut singular = matches!(first, AttemptFailure::Singular { .. }).then(|| first.clone());
        let (visited, cycling, mut best) = first.iterates();
        let mut retries = 1;
        let rho_retries = match self.options.rho_inf_retry {
            RhoInfRetry::SingularMatrix if iterated => Vec::new(),
            _ => self.options.rho_inf_retries.clone(),
        };
        for rho in rho_retries {
            let retry = self.retry_spec(SetRule::Free, rho);
            match self.counting(Stage::RhoRetries, |s| s.attempt(&retry)) {
                Ok(mut t) => {
                    t.stats.retries = retries;
                    self.commit(t);
                    return Ok(());
                }
                Err(AttemptFailure::NotConverged { best: b, .. }) => {
                    singular = None;
                    let residual = |t: &Option<Box<Trial>>| {
                        t.as_ref().map_or(f64::INFINITY, |t| t.stats.residual)
                    };
                    if residual(&b) < residual(&best) {
                        best = b;
                    }
                }
                Err(AttemptFailure::Singular { .. }) => {}
                Err(AttemptFailure::NonFinite | AttemptFailure::Refused { .. }) => singular = None,
            }
            retries += 1;
        }
        if cycling && self.options.explore_branches {
            let trial = self.counting(Stage::BranchTrials, |s| {
                s.branch_trial(&visited, rho0, retries)
            });
            if let Some(t) = trial {
                self.commit(t);
                return Ok(());
            }
        }
        if self.options.retry_without_friction_shift && self.options.friction_percussion_shift {
            if let Ok(mut t) = self.counting(Stage::Unshifted, |s| s.solve_unshifted(rho0)) {
                t.stats.retries = retries;
                self.commit(t);
                return Ok(());
            }
            retries += 1;
        }
        if self.options.on_failure == FailurePolicy::AcceptBest {
            if let Some(mut t) = best.take().map(|b| *b) {
                if t.state.q.iter().chain(&t.state.u).all(|x| x.is_finite()) {
                    t.stats.retries = retries;
                    t.stats.converged = false;
                    self.commit(t);
                    return Ok(());
                }
            }
        }
        if let (Some(s), true, None) = (singular, visited.is_empty(), &best) {
            return Err(s.into_error(&self.state));
        }
        Err(StepError::NotConverged {
            t: self.state.t,
            residual: best.as_ref().map_or(f64::INFINITY, |b| b.stats.residual),
            visited_sets: visited,
            cycling,
            state: Box::new(self.state.clone()),
        })
    }

    /// Runs `stage` of the policy, adding its linear solves to [`SolvesByStage`].
    ///
    /// [`SolvesByStage`]: crate::SolvesByStage
    fn counting<T>(&mut self, stage: Stage, run: impl FnOnce(&mut Self) -> T) -> T {
        let before = self.work.linear_solves;
        let out = run(self);
        let solves = self.work.linear_solves - before;
        self.stage_solves.add(stage, solves);
        out
    }

    /// The first attempt at a step: free Newton. In a system with more normal contacts
    /// than `max_iter` (whose free attempts get more updates, see
    /// [`Options::max_iter_per_contact`](crate::Options::max_iter_per_contact)), and with
    /// [`Options::max_openings_per_update`](crate::Options::max_openings_per_update) set,
    /// first the held-sets attempt (the previous step's sets, then a few openings per
    /// update; docs/method.md §8.2), and free Newton only when that fails; the fallback
    /// policy then handles free Newton's failure as before. With
    /// [`Options::predict_start`](crate::Options::predict_start) and a prediction at
    /// hand, free Newton first runs from the predicted unknowns with at most
    /// [`PREDICTED_START_ITERATIONS`] updates (more while they converge), and all of
    /// this from the last solution only when that fails. Every attempt here may take the
    /// quick updates of a step's first attempt.
    fn first_attempt(&mut self, rho0: f64) -> AttemptOutcome {
        // A step that converged without an update from its start is followed by another
        // one (a body at rest or in free flight): there the extrapolation would only
        // add round-off to a start that is already a solution.
        let moving = self.last.as_ref().is_some_and(|l| l.iterations > 0);
        let predicted = (self.options.predict_start && moving).then(|| {
            let o = &self.off;
            self.predictor
                .predict(self.state.k, self.options.dt, &self.state.x, o)
        });
        let free = self.first_spec(SetRule::Free, rho0);
        if let Some(x) = predicted.flatten() {
            let budget = PREDICTED_START_ITERATIONS.min(self.options.max_iter);
            let from_prediction = AttemptSpec {
                start: StartAt::Unknowns(x),
                budget,
                contracting_extra: self.options.max_iter - budget,
                ..free.clone()
            };
            let outcome = self.attempt(&from_prediction);
            if outcome.is_ok() {
                return outcome;
            }
        }
        if let Some(previous) = self.held_sets() {
            let most = self.options.max_openings_per_update;
            let held = self.first_spec(SetRule::Held { previous, most }, rho0);
            if let Ok(trial) = self.attempt(&held) {
                return Ok(trial);
            }
        }
        self.attempt(&free)
    }

    /// An attempt of the step's first stage: [`Stepper::spec`] with quick updates.
    fn first_spec(&self, sets: SetRule, rho0: f64) -> AttemptSpec {
        AttemptSpec {
            quick_updates: true,
            ..self.spec(sets, rho0)
        }
    }

    /// The previous step's sets, where a free attempt takes the held-sets attempt first
    /// (see [`Stepper::first_attempt`]).
    fn held_sets(&self) -> Option<IndexSets> {
        let most = self.options.max_openings_per_update;
        // Only systems that take the attempt pay for a copy of the previous sets.
        (most > 0 && self.free_budget() > self.options.max_iter)
            .then_some(self.last.as_ref())
            .flatten()
            .filter(|s| {
                s.sets
                    .is_consistent(self.off.nn, self.layout.friction.len())
            })
            .map(|s| s.sets.clone())
    }

    /// Stage 3b of the policy of [`Stepper::step`]: the step from the state's unknowns,
    /// with a free attempt's budget, without the friction percussions' half-step shift
    /// ([`Options::retry_without_friction_shift`]). Where the paper's step has no
    /// self-consistent index sets because that shift turns a body against its own
    /// closed contacts, this one usually has (docs/method.md §8.2).
    ///
    /// [`Options::retry_without_friction_shift`]: crate::Options::retry_without_friction_shift
    fn solve_unshifted(&mut self, rho0: f64) -> AttemptOutcome {
        let unshifted = AttemptSpec {
            friction_shift: false,
            ..self.spec(SetRule::Free, rho0)
        };
        self.attempt(&unshifted).map(|mut t| {
            t.stats.unshifted = true;
            t
        })
    }

    /// Takes the step t_n → t_n + Δt as `parts` substeps of Δt/`parts`, each committed
    /// by `substep` (for example `|s| s.step().map(|_| ())`, or a caller's own policy),
    /// then puts the state back on the time grid: k advances by one and t = t₀ + kΔt
    /// exactly. The generalized-α auxiliary variables (ā, λ̄) carry over between step
    /// sizes unchanged, since their recursion (eqs. 71, 73) does not involve Δt.
    ///
    /// The substeps' statistics are merged into one [`StepStats`]: iterations and retries
    /// summed (plus one retry for the failed whole step), `substeps` counted, the first
    /// branch point kept; [`RunStats`](crate::RunStats) counts one step.
    ///
    /// # Errors
    /// [`StepError::InvalidInput`] for `parts` = 0; otherwise the first substep error,
    /// after which the stepper is back at the state, options and statistics it had.
    pub fn split_step(
        &mut self,
        parts: usize,
        mut substep: impl FnMut(&mut Self) -> Result<(), StepError>,
    ) -> Result<&StepStats, StepError> {
        if parts == 0 {
            return Err(StepError::InvalidInput(
                "a step splits into at least one part".into(),
            ));
        }
        let saved_state = self.state.clone();
        let saved_options = self.options.clone();
        let saved_base = self.time_base;
        let saved_stats = self.stats.clone();
        let saved_last = self.last.clone();
        // Substeps are not on the step's grid: their solutions predict nothing for it
        // (nor the step's for them).
        self.forget_solutions();
        let mut sub = saved_options.clone();
        sub.dt = saved_options.dt / parts as f64;
        self.set_options(sub)?;
        let mut merged: Option<StepStats> = None;
        for _ in 0..parts {
            if let Err(e) = substep(self) {
                self.options = saved_options;
                self.time_base = saved_base;
                self.state = saved_state;
                self.forget_solutions();
                self.stats = saved_stats;
                self.last = saved_last;
                return Err(e);
            }
            let last = self.committed().clone();
            merged = Some(match merged {
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
        }
        let mut merged = merged.expect("parts >= 1");
        merged.retries += 1;
        self.options = saved_options;
        self.time_base = saved_base;
        self.state.k = saved_state.k + 1;
        self.state.t = self.grid_time(self.state.k);
        merged.t = self.state.t;
        self.forget_solutions();
        self.stats = saved_stats;
        self.stats.split_steps += 1;
        self.account(&merged);
        self.last = Some(merged);
        Ok(self.committed())
    }
}
