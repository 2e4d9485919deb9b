//! What a step and a run report: per-step statistics with the index sets, branch
//! points, and the statistics accumulated over a run.

use crate::sets::IndexSets;
use crate::state::State;
use crate::stepper::Stage;
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
    /// Linear solver used ("dense", "markowitz", "band" or "sparse").
    pub solver: String,
    /// Substeps the step was taken in: 1, or more when it was split
    /// ([`Stepper::split_step`]).
    #[serde(default = "one")]
    pub substeps: usize,
    /// Set when the step was taken by the last resort (docs/method.md §8, step 7).
    #[serde(default)]
    pub last_resort: Option<LastResort>,
    /// Whether the step (or one of its substeps) was taken without the friction
    /// percussions' half-step shift, by `Stage::Unshifted` of the policy
    /// ([`PolicyOptions::retry_without_friction_shift`](crate::PolicyOptions::retry_without_friction_shift)).
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
    /// The first attempt (stages `Predicted`, `HeldSets`, `Free` of docs/method.md
    /// §8.2): from the predicted start, then from the last solution; held sets, then
    /// free Newton.
    pub first_attempt: u64,
    /// The ρ∞ retries (stage `RhoRetry`).
    pub rho_retries: u64,
    /// The fixed-set re-solves of a cycling step (stage `BranchTrials`).
    pub branch_trials: u64,
    /// The step without the friction percussions' half-step shift (stage `Unshifted`).
    pub unshifted: u64,
    /// Everything else: the flip probes of converged steps
    /// ([`PolicyOptions::probe_flips`](crate::PolicyOptions::probe_flips)).
    pub other: u64,
}

impl SolvesByStage {
    /// Adds `solves` to the field of `stage` (none for the stages that `other` counts).
    pub(crate) fn add(&mut self, stage: Stage, solves: u64) {
        let field = match stage {
            Stage::Predicted | Stage::HeldSets | Stage::Free => &mut self.first_attempt,
            Stage::RhoRetry(_) => &mut self.rho_retries,
            Stage::BranchTrials => &mut self.branch_trials,
            Stage::Unshifted => &mut self.unshifted,
            Stage::FlipProbe | Stage::AcceptBest | Stage::Halving | Stage::LastResort => return,
        };
        *field += solves;
    }
    /// The sum over the stages.
    #[must_use]
    pub fn total(&self) -> u64 {
        self.first_attempt + self.rho_retries + self.branch_trials + self.unshifted + self.other
    }
}

/// Where the Newton iterations of a run spent their work (docs/method.md §7, "Counting
/// the work"), over every attempt: the operations by kind, why each exact update was
/// made, and the seconds each kind took. The counts are exact and do not depend on the
/// machine; the seconds are wall-clock time, as noisy as the machine.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct NewtonWork {
    /// Iterates evaluated: kinematic updates, system, index sets and residual.
    pub evaluations: u64,
    /// Of those, the damped trials of the line search (and the full update taken
    /// again when none of them decreased the residual).
    pub line_search_trials: u64,
    /// Exact updates: the Newton matrix of the iterate assembled and factorized.
    pub exact_updates: u64,
    /// Simplified updates from the kept factors, for the sets they were made for.
    pub kept_updates: u64,
    /// Simplified updates from the kept factors for sets that differ in a few rows (the
    /// low-rank update).
    pub low_rank_updates: u64,
    /// Why the exact updates were made; the four add up to `exact_updates`.
    pub exact_because: ExactBecause,
    /// Attempts that converged to a far solution and were refused (docs/method.md §8.1,
    /// "Far solutions"; [`Tuning::far_correction`](crate::Tuning::far_correction)).
    #[serde(default)]
    pub far_solutions: u64,
    /// The seconds spent in each kind of work.
    pub seconds: WorkSeconds,
}

/// Why an exact Newton update was made instead of a simplified one ([`NewtonWork`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ExactBecause {
    /// No factors were kept: the attempt's first update, or one after a regularized
    /// or failed factorization.
    pub no_kept_factors: u64,
    /// The kept factors belong to another system: they lack a contact the attempt
    /// keeps (for other sets: other contacts are pruned), or were made for another Δt
    /// or ρ∞.
    pub other_system: u64,
    /// The kept factors fit, but gave no update: the sets differ from theirs in more
    /// rows than a low-rank update takes (or outside a step's first attempt), or the
    /// update failed.
    pub sets_changed: u64,
    /// The Newton engine asked for none: the last simplified update did not contract
    /// the residual enough, the most in a row were taken, or the stepper takes none
    /// (`LinearOptions::reuse_factorization` off).
    pub not_asked: u64,
}

impl ExactBecause {
    /// The sum over the reasons.
    #[must_use]
    pub fn total(&self) -> u64 {
        self.no_kept_factors + self.other_system + self.sets_changed + self.not_asked
    }
}

/// Seconds of each kind of Newton work ([`NewtonWork`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WorkSeconds {
    /// Evaluating iterates.
    pub evaluation: f64,
    /// Assembling Newton matrices: the system's derivatives and the rows of eq. 143.
    pub jacobian: f64,
    /// Factorizing them and solving for the exact update (the regularized solve of
    /// redundant contacts included).
    pub factorization: f64,
    /// Simplified updates, kept and low-rank, whether the kept factors gave one or
    /// refused.
    pub simplified: f64,
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
    /// Steps that repeated a state at rest without solving
    /// ([`PolicyOptions::rest`](crate::PolicyOptions::rest)).
    #[serde(default)]
    pub resting_steps: u64,
    /// Steps that started with an island of bodies at rest held out of the solve
    /// (docs/method.md §8.2, "Islands at rest").
    #[serde(default)]
    pub held_island_steps: u64,
    /// Times a held island's rows exceeded the tolerance and it returned to the solve.
    #[serde(default)]
    pub island_wakes: u64,
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
