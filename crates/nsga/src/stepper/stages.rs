//! What each stage of a step's policy runs ([`Stage`], docs/method.md §8.2): the
//! attempts of the first stage, the ρ∞ retries (thesis §4.2), the step without the
//! friction shift, the best iterate; the fixed-set re-solves are in [`super::branch`].

use super::policy::{Policy, Stage, StageOutcome};
use super::spec::{AttemptSpec, SetRule, StartAt};
use super::Stepper;
use crate::attempt::AttemptOutcome;
use crate::system::System;

impl<S: System> Stepper<S> {
    /// Runs `stage` (any but [`Stage::Halving`] and [`Stage::LastResort`], which the
    /// policy's loop runs), adding its linear solves to
    /// [`SolvesByStage`](crate::SolvesByStage).
    pub(super) fn run_stage(&mut self, stage: Stage, policy: &mut Policy) -> StageOutcome {
        let before = self.work.linear_solves;
        let outcome = self.stage_outcome(stage, policy);
        let solves = self.work.linear_solves - before;
        self.stage_solves.add(stage, solves);
        outcome
    }

    /// [`Stepper::run_stage`] before its solves are counted.
    fn stage_outcome(&mut self, stage: Stage, policy: &mut Policy) -> StageOutcome {
        let rho0 = self.options.rho_inf;
        match stage {
            Stage::Predicted => {
                let x = policy.prediction.take().ok_or(None)?;
                let budget = (self.options.tuning.predicted_start_iterations)
                    .min(self.options.newton.max_iter);
                // Where the held-sets attempt follows, a prediction that needs new
                // factors has met a contact event, which that attempt is for: its free
                // updates would open the contacts it opens one at a time (docs/method.md
                // §4, "The predicted start").
                let from_prediction = AttemptSpec {
                    start: StartAt::Unknowns(x),
                    budget,
                    contracting_extra: self.options.newton.max_iter - budget,
                    start_limit: self.options.tuning.predicted_start_residual,
                    new_factors: !policy.held,
                    ..self.first_spec(SetRule::Free, rho0)
                };
                self.attempt(from_prediction).map_err(Some)
            }
            Stage::HeldSets => {
                let previous = self.last.as_ref().ok_or(None)?.sets.clone();
                let most = self.options.newton.max_openings_per_update;
                let held = self.first_spec(SetRule::Held { previous, most }, rho0);
                self.attempt(held).map_err(Some)
            }
            Stage::Free => self
                .attempt(self.first_spec(SetRule::Free, rho0))
                .map_err(Some),
            Stage::FlipProbe => {
                let converged = policy.converged.take().ok_or(None)?;
                Ok(self.probe_flips(converged, rho0))
            }
            Stage::RhoRetry(i) => {
                let rho = *self.options.policy.rho_inf_retries.get(i).ok_or(None)?;
                self.attempt(self.retry_spec(SetRule::Free, rho))
                    .map_err(Some)
            }
            Stage::BranchTrials => self.branch_trial(&policy.visited, rho0).map_err(|point| {
                policy.unfollowed = point;
                None
            }),
            Stage::Unshifted => self.solve_unshifted(rho0).map_err(Some),
            Stage::AcceptBest => {
                let best = policy.best.take().ok_or(None)?;
                let finite = best
                    .state
                    .q
                    .iter()
                    .chain(&best.state.u)
                    .all(|x| x.is_finite());
                finite.then_some(*best).ok_or(None)
            }
            Stage::Halving | Stage::LastResort => Err(None),
        }
    }

    /// An attempt of the step's first stages ([`Stage::Predicted`], [`Stage::HeldSets`],
    /// [`Stage::Free`]): [`Stepper::spec`] with the quick updates of a first attempt.
    fn first_spec(&self, sets: SetRule, rho0: f64) -> AttemptSpec {
        AttemptSpec {
            quick_updates: true,
            ..self.spec(sets, rho0)
        }
    }

    /// Whether the step starts with the held-sets attempt ([`Stage::HeldSets`]): in a
    /// system with more normal contacts than `max_iter` (whose free attempts get more
    /// updates, see [`NewtonOptions::max_iter_per_contact`](crate::NewtonOptions::max_iter_per_contact)),
    /// with [`NewtonOptions::max_openings_per_update`](crate::NewtonOptions::max_openings_per_update)
    /// set and the previous step's sets at hand.
    pub(super) fn held_sets_apply(&self) -> bool {
        let most = self.options.newton.max_openings_per_update;
        most > 0
            && self.free_budget() > self.options.newton.max_iter
            && self.last.as_ref().is_some_and(|s| {
                s.sets
                    .is_consistent(self.off.nn, self.layout.friction.len())
            })
    }

    /// The predicted start of the step ([`Stage::Predicted`]), with
    /// [`NewtonOptions::predict_start`](crate::NewtonOptions::predict_start) and a prediction at hand.
    pub(super) fn prediction(&mut self) -> Option<Vec<f64>> {
        // A step that converged without an update from its start is followed by another
        // one (a body at rest or in free flight): there the extrapolation would only
        // add round-off to a start that is already a solution.
        let moving = self.last.as_ref().is_some_and(|l| l.iterations > 0);
        if !(self.options.newton.predict_start && moving) {
            return None;
        }
        self.predictor
            .predict(self.state.k, self.options.dt, &self.state.x, &self.off)
    }

    /// [`Stage::Unshifted`]: the step from the state's unknowns,
    /// with a free attempt's budget, without the friction percussions' half-step shift
    /// ([`PolicyOptions::retry_without_friction_shift`]). Where the paper's step has no
    /// self-consistent index sets because that shift turns a body against its own
    /// closed contacts, this one usually has (docs/method.md §8.2).
    ///
    /// [`PolicyOptions::retry_without_friction_shift`]: crate::PolicyOptions::retry_without_friction_shift
    fn solve_unshifted(&mut self, rho0: f64) -> AttemptOutcome {
        let unshifted = AttemptSpec {
            friction_shift: false,
            ..self.spec(SetRule::Free, rho0)
        };
        self.attempt(unshifted).map(|mut t| {
            t.stats.unshifted = true;
            t
        })
    }
}
