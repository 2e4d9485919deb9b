//! The outcome of one Newton attempt at a step ([`AttemptOutcome`]): a [`Trial`] to
//! commit, or an [`AttemptFailure`] that tells the step's policy what the iterates did.
//!
//! The attempt reports its failure as data, not as a [`StepError`]: the policy of
//! [`Stepper::step`] decides from it what to try next (other ρ∞, fixed index sets,
//! halving), and only the step's final failure becomes a [`StepError`].

use crate::error::StepError;
use crate::report::StepStats;
use crate::sets::IndexSets;
use crate::state::State;
#[cfg(doc)]
use crate::Stepper;

/// The result of solving one step without committing it (see [`Stepper::trial`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Trial {
    /// The state at t_{n+1}.
    pub state: State,
    /// Statistics of the solve.
    pub stats: StepStats,
    /// Sets visited by the Newton iterates, in first-visit order.
    pub visited: Vec<IndexSets>,
    /// Whether the visited sets cycled in the last iterations (a branch-point sign).
    pub cycling: bool,
}

/// The outcome of one Newton attempt at a step: converged ([`Trial`]) or failed.
pub type AttemptOutcome = Result<Trial, AttemptFailure>;

/// Why a converged attempt's solution was refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RefusedBecause {
    /// Its position correction moves the bodies much farther than their motion over the
    /// step could ([`Tuning::far_correction`](crate::Tuning::far_correction), docs/method.md §8.1).
    FarSolution,
}

/// Why one Newton attempt at a step failed.
#[derive(Debug, Clone, PartialEq)]
pub enum AttemptFailure {
    /// The iterates converged on a solution that is refused.
    Refused {
        /// Why.
        reason: RefusedBecause,
        /// Index sets visited by the Newton iterates, in first-visit order, the
        /// solution's last.
        visited: Vec<IndexSets>,
    },
    /// The iterates did not converge: iteration limit, a settled cycle of index sets, or
    /// (with fixed sets) a stalled residual.
    NotConverged {
        /// Index sets visited by the Newton iterates, in first-visit order.
        visited: Vec<IndexSets>,
        /// Whether the sets cycled (a possible branch point, docs/method.md §8).
        cycling: bool,
        /// The best (smallest-residual) iterate, as an uncommitted step.
        best: Option<Box<Trial>>,
    },
    /// A residual became NaN or infinite.
    NonFinite,
    /// The Newton matrix could not be factorized.
    Singular {
        /// The linear solver's message.
        message: String,
    },
    /// The stepper's [`Interrupt`](crate::Interrupt) asked the attempt to stop.
    Interrupted,
}

impl AttemptFailure {
    /// The smallest residual reached (∞ when there is no iterate).
    #[must_use]
    pub fn residual(&self) -> f64 {
        match self {
            Self::NotConverged { best: Some(b), .. } => b.stats.residual,
            _ => f64::INFINITY,
        }
    }

    /// What the iterates did: the sets they visited, whether those cycled, and the
    /// best iterate (none for an attempt without iterates or with a refused solution).
    #[must_use]
    pub fn iterates(self) -> (Vec<IndexSets>, bool, Option<Box<Trial>>) {
        match self {
            Self::NotConverged {
                visited,
                cycling,
                best,
            } => (visited, cycling, best),
            Self::Refused { visited, .. } => (visited, false, None),
            Self::NonFinite | Self::Singular { .. } | Self::Interrupted => {
                (Vec::new(), false, None)
            }
        }
    }

    /// The failure as the error of a step that started at `state` (a refused solution
    /// as a step that did not converge).
    #[must_use]
    pub fn into_error(self, state: &State) -> StepError {
        let residual = self.residual();
        match self {
            Self::NotConverged {
                visited, cycling, ..
            } => StepError::NotConverged {
                t: state.t,
                residual,
                visited_sets: visited,
                cycling,
                state: Box::new(state.clone()),
            },
            Self::Refused { visited, .. } => StepError::NotConverged {
                t: state.t,
                residual,
                visited_sets: visited,
                cycling: false,
                state: Box::new(state.clone()),
            },
            Self::NonFinite => StepError::NonFinite {
                t: state.t,
                state: Box::new(state.clone()),
            },
            Self::Singular { message } => StepError::Linear {
                t: state.t,
                message,
                state: Box::new(state.clone()),
            },
            Self::Interrupted => StepError::Interrupted {
                t: state.t,
                state: Box::new(state.clone()),
            },
        }
    }
}
