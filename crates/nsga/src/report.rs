//! What a step and a run report: per-step statistics with the index sets, branch
//! points, and the statistics accumulated over a run.

use crate::sets::IndexSets;
use crate::state::State;
#[cfg(doc)]
use crate::{FailurePolicy, Stepper};

/// A branch point: several self-consistent solutions of one step (docs/method.md §8, ERRATA 22).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BranchPoint {
    /// Time t_n at the start of the step.
    pub t: f64,
    /// Distinct converged continuations (deduplicated by state), each with the sets it
    /// was solved with.
    pub candidates: Vec<(IndexSets, State)>,
    /// Per candidate: whether it is self-consistent (its sets, recomputed from it, are
    /// the ones it was solved with). All true under [`BranchRule::SelfConsistent`]; under
    /// [`BranchRule::Converged`] the others are solutions of the fixed-set equations that
    /// break a contact law the fixed sets did not impose.
    ///
    /// [`BranchRule::SelfConsistent`]: crate::BranchRule::SelfConsistent
    /// [`BranchRule::Converged`]: crate::BranchRule::Converged
    #[serde(default)]
    pub consistent: Vec<bool>,
    /// How many fixed-set re-solves were tried.
    pub tried: usize,
    /// Index of the candidate the stepper continued with (the first, in the order the
    /// sets were first visited by the failed Newton iteration).
    pub chosen: usize,
}

/// Statistics of one step.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StepStats {
    /// Time t_{n+1} at the end of the step.
    pub t: f64,
    /// Newton iterations (linear solves) of the accepted attempt.
    pub iterations: usize,
    /// Final ‖R‖∞ (scaled rows).
    pub residual: f64,
    /// ρ∞ of the accepted attempt.
    pub rho_inf: f64,
    /// Index sets of the accepted solution.
    pub sets: IndexSets,
    /// Failed attempts before the accepted one.
    pub retries: usize,
    /// Whether Newton converged (false only with [`FailurePolicy::AcceptBest`]).
    pub converged: bool,
    /// Set when the step was resolved by fixed-set re-solves.
    pub branch: Option<BranchPoint>,
    /// Linear solver used ("dense", "markowitz" or "sparse").
    pub solver: String,
    /// Substeps the step was taken in: 1, or more when it was split
    /// ([`Stepper::split_step`]).
    #[serde(default = "one")]
    pub substeps: usize,
    /// Set when the step was taken by the last resort (docs/method.md §8, step 7).
    #[serde(default)]
    pub last_resort: Option<LastResort>,
    /// Whether the step (or one of its substeps) was taken without the friction
    /// percussions' half-step shift, by stage 3b of the policy
    /// ([`Options::retry_without_friction_shift`](crate::Options::retry_without_friction_shift)).
    #[serde(default)]
    pub unshifted: bool,
}

/// How the last resort took a step: a Moreau–Jean step whose contact problem Lemke's
/// method solved, and the position projection after it.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LastResort {
    /// Pivots of Lemke's method.
    pub pivots: usize,
    /// Complementarity residual of its solution, max |min(z, w)| (impulse and velocity
    /// units).
    pub residual: f64,
    /// Largest coordinate change of the projection onto the gaps (0: none needed).
    pub projection: f64,
}

fn one() -> usize {
    1
}

/// The linear solves of a run by the stage of a step's policy that made them
/// (docs/method.md §8.2): where the work of the failed and retried steps goes. Substeps
/// count in the stages they run, so the fields add up to
/// [`Stepper::linear_solves`](crate::Stepper::linear_solves).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct SolvesByStage {
    /// Stage 1, the first attempt: from the predicted start, then from the last
    /// solution; held sets, then free Newton.
    pub first_attempt: u64,
    /// Stage 2, the ρ∞ retries.
    pub rho_retries: u64,
    /// Stage 3, the fixed-set re-solves of a cycling step (branch trials).
    pub branch_trials: u64,
    /// Stage 3b, the step without the friction percussions' half-step shift.
    pub unshifted: u64,
    /// The re-solves at a friction bound, after the halvings.
    pub boundary: u64,
    /// Everything else: the flip probes of converged steps
    /// ([`Options::probe_flips`](crate::Options::probe_flips)).
    pub other: u64,
}

/// A stage of [`SolvesByStage`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Stage {
    FirstAttempt,
    RhoRetries,
    BranchTrials,
    Unshifted,
    Boundary,
}

impl SolvesByStage {
    /// Adds `solves` to `stage`.
    pub(crate) fn add(&mut self, stage: Stage, solves: u64) {
        let field = match stage {
            Stage::FirstAttempt => &mut self.first_attempt,
            Stage::RhoRetries => &mut self.rho_retries,
            Stage::BranchTrials => &mut self.branch_trials,
            Stage::Unshifted => &mut self.unshifted,
            Stage::Boundary => &mut self.boundary,
        };
        *field += solves;
    }
    /// The sum over the stages.
    #[must_use]
    pub fn total(&self) -> u64 {
        self.first_attempt
            + self.rho_retries
            + self.branch_trials
            + self.unshifted
            + self.boundary
            + self.other
    }
}

/// Accumulated statistics of a run.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RunStats {
    /// Steps taken.
    pub steps: u64,
    /// Sum of Newton iterations.
    pub newton_iterations: u64,
    /// Largest Newton iteration count of a step.
    pub max_iterations: usize,
    /// Steps that needed a retry (another ρ∞ or fixed sets).
    pub retried_steps: u64,
    /// Steps accepted without convergence.
    pub unconverged_steps: u64,
    /// Branch points met (steps with more than one distinct candidate).
    pub branch_points: u64,
    /// Steps taken as several substeps ([`Stepper::split_step`]).
    pub split_steps: u64,
    /// Steps taken by the last resort (docs/method.md §8, step 7).
    #[serde(default)]
    pub last_resort_steps: u64,
    /// The largest complementarity residual of those steps.
    #[serde(default)]
    pub last_resort_residual: f64,
    /// Steps taken without the friction percussions' half-step shift
    /// ([`StepStats::unshifted`]).
    #[serde(default)]
    pub unshifted_steps: u64,
}

impl RunStats {
    /// Mean Newton iterations per step.
    #[must_use]
    pub fn mean_iterations(&self) -> f64 {
        if self.steps == 0 {
            0.0
        } else {
            self.newton_iterations as f64 / self.steps as f64
        }
    }
}
