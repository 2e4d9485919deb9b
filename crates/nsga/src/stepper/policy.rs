//! The policy of a step (docs/method.md §8.2): its stages, the one transition table
//! between them ([`Policy::next`]), and the loop of [`Stepper::step`] over them, whose
//! step halving is an outer Δt controller: a halved step runs the whole policy again on
//! each half, one level of halving down ([`super::halving`]).

use super::branch::record_unfollowed;
use super::halving::Halves;
use super::Stepper;
use crate::attempt::{AttemptFailure, Trial};
use crate::error::StepError;
use crate::options::{FailurePolicy, Options, RhoInfRetry};
use crate::report::BranchPoint;
use crate::sets::IndexSets;
use crate::state::State;
use crate::system::System;

/// A stage of a step's policy. This is the list of stages, in the order
/// [`Policy::next`] tries them; a step is committed by the first stage that finds it.
///
/// 1. [`Stage::Predicted`]: free Newton from the start extrapolated from the last steps.
/// 2. [`Stage::HeldSets`]: the previous step's index sets held, then released.
/// 3. [`Stage::Free`]: free Newton from the last step's solution.
/// 4. [`Stage::FlipProbe`]: after a converged first attempt, its contacts' states flipped.
/// 5. [`Stage::RhoRetry`]: the other ρ∞ of the options.
/// 6. [`Stage::BranchTrials`]: one fixed-set re-solve per set a cycling attempt visited.
/// 7. [`Stage::Unshifted`]: the step without the friction percussions' half-step shift.
/// 8. [`Stage::AcceptBest`]: the best iterate.
/// 9. [`Stage::Halving`]: the step as two halves, each with this whole policy.
/// 10. [`Stage::LastResort`]: a Moreau–Jean step whose contact problem Lemke's method solves.
///
/// docs/method.md §8.2 shows the same list (a test keeps them in step).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Stage {
    /// Free Newton from the unknowns the last steps' solutions extrapolate to
    /// ([`NewtonOptions::predict_start`](crate::NewtonOptions::predict_start)), with at most
    /// [`Tuning::predicted_start_iterations`](crate::Tuning::predicted_start_iterations) updates, more
    /// while they converge, and none where the prediction is off by more than
    /// [`Tuning::predicted_start_residual`](crate::Tuning::predicted_start_residual) (a
    /// contact event, which the extrapolation does not foresee). Where it fails, the
    /// first attempt starts again from the last solution. Where that attempt is
    /// [`Stage::HeldSets`], it factors nothing: it takes the kept factors' updates only
    /// (docs/method.md §4, "The predicted start").
    Predicted,
    /// The held-sets attempt ([`NewtonOptions::max_openings_per_update`](crate::NewtonOptions::max_openings_per_update)), in a system with
    /// more normal contacts than [`NewtonOptions::max_iter`]: the previous step's sets held,
    /// then released a few openings per update (docs/method.md §8.2).
    HeldSets,
    /// Free Newton from the last step's solution, with a free attempt's budget
    /// ([`NewtonOptions::max_iter_per_contact`](crate::NewtonOptions::max_iter_per_contact)). Its failure is the step's first failure,
    /// which the later stages read.
    Free,
    /// The flip probe of a converged first attempt ([`PolicyOptions::probe_flips`], or
    /// [`PolicyOptions::probe_painleve`] where a sliding contact has b ≤ 0): the step
    /// re-solved with each touching contact's state flipped; it commits the converged
    /// step, with a branch point when a flip gives another self-consistent solution.
    FlipProbe,
    /// The `i`th ρ∞ of [`PolicyOptions::rho_inf_retries`] (after the failures that
    /// [`PolicyOptions::rho_inf_retry`] names; thesis §4.2).
    RhoRetry(usize),
    /// With [`PolicyOptions::branch_trials`], when the first attempt's index sets cycled
    /// (with [`PolicyOptions::branch_on_any_failure`]: whenever it did not converge):
    /// one re-solve per distinct set seen with the sets fixed; the self-consistent
    /// candidates, deduplicated by state, make a branch point, and the step continues
    /// with one of them whatever [`PolicyOptions::branch_rule`] records.
    BranchTrials,
    /// With [`PolicyOptions::retry_without_friction_shift`]: the step without the friction
    /// percussions' half-step shift.
    Unshifted,
    /// With [`FailurePolicy::AcceptBest`]: the best iterate, marked not converged.
    AcceptBest,
    /// Up to [`PolicyOptions::max_halvings`] times: the step as two halves, each with this
    /// whole policy.
    Halving,
    /// With [`PolicyOptions::last_resort`], at the step's own Δt: a Moreau–Jean step whose
    /// contact problem is solved by Lemke's method, which terminates.
    LastResort,
}

#[cfg(test)]
impl Stage {
    /// Every stage, in the order of the policy.
    pub(crate) const ALL: [Self; 10] = [
        Self::Predicted,
        Self::HeldSets,
        Self::Free,
        Self::FlipProbe,
        Self::RhoRetry(0),
        Self::BranchTrials,
        Self::Unshifted,
        Self::AcceptBest,
        Self::Halving,
        Self::LastResort,
    ];

    /// The variant's name, as docs/method.md writes it.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Self::Predicted => "Predicted",
            Self::HeldSets => "HeldSets",
            Self::Free => "Free",
            Self::FlipProbe => "FlipProbe",
            Self::RhoRetry(_) => "RhoRetry",
            Self::BranchTrials => "BranchTrials",
            Self::Unshifted => "Unshifted",
            Self::AcceptBest => "AcceptBest",
            Self::Halving => "Halving",
            Self::LastResort => "LastResort",
        }
    }
}

/// How a stage ended: the step it found (not yet committed), or why not; `Err(None)` for
/// a stage that is not one attempt and found nothing.
pub(super) type StageOutcome = Result<Trial, Option<AttemptFailure>>;

/// What follows a stage. One per stage, moved once: boxing the trial would only add an
/// allocation.
#[allow(clippy::large_enum_variant)]
pub(super) enum Next {
    /// Run this stage.
    Run(Stage),
    /// Commit this step: the policy at this Δt is done.
    Commit(Trial),
    /// Every stage at this Δt failed.
    Fail(StepError),
}

/// The stages tried, in order, once the attempts from the last solution and the ρ∞
/// retries failed.
const LATER: [Stage; 5] = [
    Stage::BranchTrials,
    Stage::Unshifted,
    Stage::AcceptBest,
    Stage::Halving,
    Stage::LastResort,
];

/// The stages the options switch on.
#[derive(Debug, Clone, Copy)]
struct Enabled {
    probe_flips: bool,
    /// The number of ρ∞ retries, and whether they follow a first attempt that iterated.
    rho_retries: usize,
    rho_after_iterates: bool,
    branch_trials: bool,
    /// Branch trials after any non-converged first attempt, not only a cycling one.
    branch_on_any_failure: bool,
    unshifted: bool,
    accept_best: bool,
    last_resort: bool,
}

impl Enabled {
    fn new(o: &Options) -> Self {
        let p = &o.policy;
        Self {
            probe_flips: p.probe_flips,
            rho_retries: p.rho_inf_retries.len(),
            rho_after_iterates: p.rho_inf_retry != RhoInfRetry::SingularMatrix,
            branch_trials: p.branch_trials,
            branch_on_any_failure: p.branch_on_any_failure,
            unshifted: p.retry_without_friction_shift && o.friction_percussion_shift,
            accept_best: p.on_failure == FailurePolicy::AcceptBest,
            last_resort: p.last_resort,
        }
    }
}

/// The policy of one step at one Δt: the stages the options switch on, and what the
/// stages so far found out (the first failure's iterates, the best iterate, the failed
/// attempts).
#[derive(Debug)]
pub(super) struct Policy {
    enabled: Enabled,
    /// Whether the converged first attempt just reported has a touching sliding contact
    /// with App. I's b ≤ 0 ([`PolicyOptions::probe_painleve`](crate::PolicyOptions::probe_painleve)),
    /// set by the loop of [`Stepper::run_policy`] before it asks what follows.
    painleve: bool,
    /// The halvings left at this Δt.
    pub(super) halvings: usize,
    /// Whether this is the step's own Δt (not a half), where the last resort may follow.
    top: bool,
    /// The predicted start, when there is one.
    pub(super) prediction: Option<Vec<f64>>,
    /// Whether the held-sets attempt applies.
    pub(super) held: bool,
    /// The ρ∞ retries that follow the first attempt's failure.
    rho_retries: usize,
    /// A converged first attempt, for the flip probe.
    pub(super) converged: Option<Trial>,
    /// The sets the first failed attempt visited, and whether they cycled.
    pub(super) visited: Vec<IndexSets>,
    cycling: bool,
    /// The best iterate of the failed attempts.
    pub(super) best: Option<Box<Trial>>,
    /// The branch point of fixed-set re-solves that converged but were none
    /// self-consistent ([`crate::BranchRule::Converged`]), recorded on the step a later
    /// stage finds.
    pub(super) unfollowed: Option<BranchPoint>,
    /// A singular first attempt, while no later attempt iterated.
    singular: Option<AttemptFailure>,
    /// Failed attempts before the current stage (`StepStats::retries`), from the first.
    retries: usize,
    /// Why the step failed at this Δt, once its attempts are spent.
    pub(super) failure: Option<StepError>,
}

impl Policy {
    /// The policy of a step from `stepper`'s state at its current Δt, with `halvings`
    /// halvings left; `top`: at the step's own Δt.
    pub(super) fn new<S: System>(stepper: &mut Stepper<S>, halvings: usize, top: bool) -> Self {
        let enabled = Enabled::new(&stepper.options);
        let prediction = stepper.prediction();
        let held = stepper.held_sets_apply();
        Self::before_any_stage(enabled, halvings, top, prediction, held)
    }

    /// The policy before any stage has run: the stages `enabled`, `halvings` halvings
    /// left, `top` at the step's own Δt, the predicted start if any, whether the
    /// held-sets attempt applies.
    fn before_any_stage(
        enabled: Enabled,
        halvings: usize,
        top: bool,
        prediction: Option<Vec<f64>>,
        held: bool,
    ) -> Self {
        Self {
            enabled,
            painleve: false,
            halvings,
            top,
            prediction,
            held,
            rho_retries: 0,
            converged: None,
            visited: Vec::new(),
            cycling: false,
            best: None,
            unfollowed: None,
            singular: None,
            retries: 1,
            failure: None,
        }
    }

    /// The stage a step starts with.
    pub(super) fn first(&self) -> Stage {
        if self.prediction.is_some() {
            Stage::Predicted
        } else {
            self.attempt_from_last_solution()
        }
    }

    /// The first attempt from the last solution.
    fn attempt_from_last_solution(&self) -> Stage {
        if self.held {
            Stage::HeldSets
        } else {
            Stage::Free
        }
    }

    /// The transition table: what follows `stage`, which ended with `outcome` (recorded
    /// for the stages after it). A failure reports the step from `state`.
    pub(super) fn next(&mut self, stage: Stage, outcome: StageOutcome, state: &State) -> Next {
        use Stage::{
            AcceptBest, BranchTrials, FlipProbe, Free, HeldSets, Predicted, RhoRetry, Unshifted,
        };
        match (stage, outcome) {
            (Predicted | HeldSets | Free, Ok(t)) if self.enabled.probe_flips || self.painleve => {
                self.converged = Some(t);
                Next::Run(FlipProbe)
            }
            (Predicted | HeldSets | Free | FlipProbe, Ok(t)) => Next::Commit(t),
            (RhoRetry(_) | BranchTrials | Unshifted | AcceptBest, Ok(mut t)) => {
                t.stats.retries = self.retries;
                if stage == AcceptBest {
                    t.stats.converged = false;
                }
                if let Some(point) = self.unfollowed.take() {
                    record_unfollowed(point, &mut t);
                }
                Next::Commit(t)
            }
            (Predicted, Err(_)) => Next::Run(self.attempt_from_last_solution()),
            (HeldSets, Err(_)) => Next::Run(Free),
            (Free, Err(failure)) => {
                self.first_failure(failure);
                self.after(stage, state)
            }
            (RhoRetry(_), Err(failure)) => {
                self.failed_retry(failure);
                self.after(stage, state)
            }
            (Unshifted, Err(_)) => {
                self.retries += 1;
                self.after(stage, state)
            }
            (_, _) => self.after(stage, state),
        }
    }

    /// Records the failure of the first attempt from the last solution.
    fn first_failure(&mut self, failure: Option<AttemptFailure>) {
        let Some(failure) = failure else { return };
        let iterated = matches!(
            failure,
            AttemptFailure::NotConverged { .. } | AttemptFailure::Refused { .. }
        );
        if !iterated || self.enabled.rho_after_iterates {
            self.rho_retries = self.enabled.rho_retries;
        }
        // A singular Newton matrix on every attempt is reported as such, not as a
        // non-converged step without iterates.
        if matches!(failure, AttemptFailure::Singular { .. }) {
            self.singular = Some(failure.clone());
        }
        (self.visited, self.cycling, self.best) = failure.iterates();
    }

    /// Records a failed ρ∞ retry.
    fn failed_retry(&mut self, failure: Option<AttemptFailure>) {
        match failure {
            Some(AttemptFailure::NotConverged { best, .. }) => {
                self.singular = None;
                let residual =
                    |t: &Option<Box<Trial>>| t.as_ref().map_or(f64::INFINITY, |t| t.stats.residual);
                if residual(&best) < residual(&self.best) {
                    self.best = best;
                }
            }
            // An interrupted retry ends the step before the next stage.
            Some(AttemptFailure::Singular { .. } | AttemptFailure::Interrupted) | None => {}
            Some(AttemptFailure::NonFinite | AttemptFailure::Refused { .. }) => {
                self.singular = None;
            }
        }
        self.retries += 1;
    }

    /// The first stage after the failed `stage` that the options and what the step
    /// found so far switch on.
    fn after(&mut self, stage: Stage, state: &State) -> Next {
        let retry = match stage {
            Stage::Free => Some(0),
            Stage::RhoRetry(i) => Some(i + 1),
            _ => None,
        };
        if let Some(i) = retry.filter(|&i| i < self.rho_retries) {
            return Next::Run(Stage::RhoRetry(i));
        }
        let from = LATER.iter().position(|&s| s == stage).map_or(0, |i| i + 1);
        for &later in &LATER[from..] {
            if later == Stage::Halving {
                // The attempts at this Δt are spent.
                self.failure = Some(self.attempts_failed(state));
            }
            if self.switched_on(later) {
                return Next::Run(later);
            }
        }
        Next::Fail(match self.failure.take() {
            Some(failure) => failure,
            None => self.attempts_failed(state),
        })
    }

    /// Whether a stage after the ρ∞ retries runs.
    fn switched_on(&self, stage: Stage) -> bool {
        let e = &self.enabled;
        match stage {
            Stage::BranchTrials => (self.cycling || e.branch_on_any_failure) && e.branch_trials,
            Stage::Unshifted => e.unshifted,
            Stage::AcceptBest => e.accept_best,
            Stage::Halving => self.halvings > 0,
            // The stepper was refused at setup where the last resort cannot take the
            // system, so the option says whether the stage exists.
            Stage::LastResort => self.top && e.last_resort,
            _ => false,
        }
    }

    /// The error of a step whose attempts at this Δt all failed: a singular matrix when
    /// no attempt iterated, otherwise a step that did not converge.
    fn attempts_failed(&mut self, state: &State) -> StepError {
        if let (Some(s), true, None) = (self.singular.take(), self.visited.is_empty(), &self.best) {
            return s.into_error(state);
        }
        StepError::NotConverged {
            t: state.t,
            residual: self
                .best
                .as_ref()
                .map_or(f64::INFINITY, |b| b.stats.residual),
            visited_sets: self.visited.clone(),
            cycling: self.cycling,
            state: Box::new(state.clone()),
        }
    }
}

/// How the step at one Δt ending leaves the levels of halving above it. One per level,
/// moved once (as [`Next`]).
#[allow(clippy::large_enum_variant)]
enum Resume {
    /// Go on at this Δt with this policy and stage.
    At(Policy, Stage),
    /// The whole step ended.
    Finished(Result<(), StepError>),
}

impl<S: System> Stepper<S> {
    /// The policy of one step: the stages at the step's Δt, in the order of
    /// [`Policy::next`], where [`Stage::Halving`] takes the step as two halves that each
    /// run the stages again with one halving less, the Δt controller keeping the levels
    /// of halving above the current Δt.
    pub(super) fn run_policy(&mut self) -> Result<(), StepError> {
        let mut above: Vec<(Policy, Halves)> = Vec::new();
        let mut policy = Policy::new(self, self.options.policy.max_halvings, true);
        let mut stage = policy.first();
        loop {
            if self.interrupt.requested() {
                return Err(self.interrupted(above));
            }
            let next = match stage {
                Stage::Halving => match self.begin_split(2) {
                    Ok(halves) => {
                        let inner = Policy::new(self, policy.halvings - 1, false);
                        stage = inner.first();
                        above.push((std::mem::replace(&mut policy, inner), halves));
                        continue;
                    }
                    Err(_) => policy.next(stage, Err(None), &self.state),
                },
                // Only at the step's own Δt, so it ends the step.
                Stage::LastResort => return self.last_resort(),
                _ => {
                    let outcome = self.run_stage(stage, &mut policy);
                    policy.painleve = self.options.policy.probe_painleve
                        && matches!(stage, Stage::Predicted | Stage::HeldSets | Stage::Free)
                        && outcome.as_ref().is_ok_and(|t| self.painleve_possible(t));
                    policy.next(stage, outcome, &self.state)
                }
            };
            let ended = match next {
                Next::Run(s) => {
                    stage = s;
                    continue;
                }
                Next::Commit(trial) => {
                    self.commit(trial);
                    Ok(())
                }
                Next::Fail(e) => Err(e),
            };
            match self.level_ended(&mut above, ended) {
                Resume::At(p, s) => (policy, stage) = (p, s),
                Resume::Finished(result) => return result,
            }
        }
    }

    /// The step stopped by the caller's [`Interrupt`](crate::Interrupt): the levels of
    /// halving left, the state back where the step started.
    fn interrupted(&mut self, mut above: Vec<(Policy, Halves)>) -> StepError {
        while let Some((_, halves)) = above.pop() {
            self.abort_split(halves);
        }
        StepError::Interrupted {
            t: self.state.t,
            state: Box::new(self.state.clone()),
        }
    }

    /// The step at the innermost Δt ended: the next half, or the end of the halved step
    /// above (whose Δt goes on after a failure), and so on up the levels.
    fn level_ended(
        &mut self,
        above: &mut Vec<(Policy, Halves)>,
        mut ended: Result<(), StepError>,
    ) -> Resume {
        loop {
            let Some((mut parent, mut halves)) = above.pop() else {
                return Resume::Finished(ended);
            };
            if ended.is_err() {
                self.abort_split(halves);
                match parent.next(Stage::Halving, Err(None), &self.state) {
                    Next::Run(s) => return Resume::At(parent, s),
                    Next::Commit(trial) => {
                        self.commit(trial);
                        ended = Ok(());
                    }
                    Next::Fail(e) => ended = Err(e),
                }
                continue;
            }
            self.substep_done(&mut halves);
            if halves.left > 0 {
                let inner = Policy::new(self, parent.halvings - 1, false);
                let first = inner.first();
                above.push((parent, halves));
                return Resume::At(inner, first);
            }
            self.finish_split(halves);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{Enabled, Next, Policy, Stage};
    use crate::attempt::{AttemptFailure, RefusedBecause};
    use crate::error::StepError;
    use crate::options::{FailurePolicy, Options, PolicyOptions, RhoInfRetry};
    use crate::sets::IndexSets;
    use crate::state::State;

    /// The policy of a step at the step's own Δt with these options, before any stage.
    fn policy(o: &Options) -> Policy {
        Policy::before_any_stage(Enabled::new(o), o.policy.max_halvings, true, None, false)
    }

    fn not_converged(visited: &[IndexSets], cycling: bool) -> AttemptFailure {
        AttemptFailure::NotConverged {
            visited: visited.to_vec(),
            cycling,
            best: None,
        }
    }

    fn stage(next: &Next) -> Option<Stage> {
        match next {
            Next::Run(s) => Some(*s),
            Next::Commit(_) | Next::Fail(_) => None,
        }
    }

    /// A refused far solution is a failure whose iterates count (the ρ∞ retries that
    /// follow only a singular matrix are skipped) and that has no best iterate; a
    /// singular matrix is followed by the retries.
    #[test]
    fn a_refused_solution_is_a_failure_with_iterates_and_no_best() {
        let o = Options {
            policy: PolicyOptions {
                rho_inf_retry: RhoInfRetry::SingularMatrix,
                rho_inf_retries: vec![0.8, 0.9],
                branch_trials: false,
                retry_without_friction_shift: false,
                last_resort: false,
                max_halvings: 0,
                ..PolicyOptions::default()
            },
            ..Options::default()
        };
        let sets = vec![IndexSets::empty(1, 0)];
        let refused = AttemptFailure::Refused {
            reason: RefusedBecause::FarSolution,
            visited: sets.clone(),
        };
        let state = State::default();
        match policy(&o).next(Stage::Free, Err(Some(refused)), &state) {
            Next::Fail(StepError::NotConverged {
                residual,
                visited_sets,
                cycling: false,
                ..
            }) => assert!(residual.is_infinite() && visited_sets == sets),
            other => panic!("{:?}", stage(&other)),
        }
        let singular = AttemptFailure::Singular {
            message: "pivot".into(),
        };
        let next = policy(&o).next(Stage::Free, Err(Some(singular)), &state);
        assert_eq!(stage(&next), Some(Stage::RhoRetry(0)));
    }

    /// With every stage switched on and every stage failing, a step whose first
    /// attempt cycled goes through the stages in the order of `Stage::ALL`.
    #[test]
    fn failing_stages_follow_one_another_in_order() {
        let o = Options {
            friction_percussion_shift: true,
            policy: PolicyOptions {
                rho_inf_retries: vec![0.8],
                branch_trials: true,
                retry_without_friction_shift: true,
                on_failure: FailurePolicy::AcceptBest,
                last_resort: true,
                max_halvings: 1,
                ..PolicyOptions::default()
            },
            ..Options::default()
        };
        let (mut p, state) = (policy(&o), State::default());
        let visited = [IndexSets::empty(1, 0)];
        let mut next = p.next(
            Stage::Free,
            Err(Some(not_converged(&visited, true))),
            &state,
        );
        let mut seen = vec![Stage::Free];
        while let Some(s) = stage(&next) {
            seen.push(s);
            let outcome = match s {
                Stage::RhoRetry(_) => Some(not_converged(&visited, true)),
                _ => None,
            };
            if s == Stage::LastResort {
                break;
            }
            next = p.next(s, Err(outcome), &state);
        }
        let expected = [
            Stage::Free,
            Stage::RhoRetry(0),
            Stage::BranchTrials,
            Stage::Unshifted,
            Stage::AcceptBest,
            Stage::Halving,
            Stage::LastResort,
        ];
        assert_eq!(seen, expected);
    }

    /// The names of the stages in the list at the head of `text` that starts at the
    /// line `from` and ends at the first line without `marker`.
    fn listed<'a>(text: &'a str, from: &str, marker: &str) -> Vec<&'a str> {
        let start = text.find(from).expect("the list's heading") + from.len();
        text[start..]
            .lines()
            .skip_while(|l| !l.contains(marker))
            .take_while(|l| l.contains(marker))
            .filter_map(|l| l.split(marker).nth(1)?.split('`').next())
            .collect()
    }

    fn names() -> Vec<&'static str> {
        Stage::ALL.iter().map(|s| s.name()).collect()
    }

    /// The doc comment of `Stage` lists the stages in the order of `Stage::ALL`, which
    /// `name` covers exhaustively.
    #[test]
    fn the_stage_enum_lists_its_stages_in_order() {
        let source = include_str!("policy.rs");
        let doc = listed(source, "/// A stage of a step's policy.", "[`Stage::");
        assert_eq!(doc, names());
        for (i, s) in Stage::ALL.iter().enumerate() {
            assert_eq!(
                Stage::ALL.iter().position(|a| a.name() == s.name()),
                Some(i)
            );
        }
    }

    /// docs/method.md §8.2 shows the stages in a table, in the order of `Stage::ALL`.
    #[test]
    fn docs_method_lists_the_stages_in_order() {
        let method = include_str!("../../../../docs/method.md");
        let table = listed(method, "#### The stages", "| `Stage::");
        assert_eq!(table, names());
    }
}
