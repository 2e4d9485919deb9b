//! Typed errors of the stepper.

use crate::sets::IndexSets;
use crate::state::State;

/// Why a step (or the start) failed. Every variant that happens during a run carries
/// the time and the last good state, from which the run can continue.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StepError {
    /// Bad input: sizes, options, non-finite initial values, bad fixed sets.
    #[error("invalid input: {0}")]
    InvalidInput(String),
    /// The consistent start (acceleration-level problem at t0) did not converge.
    #[error("consistent start at t = {t} failed: {message}")]
    Start {
        /// Initial time.
        t: f64,
        /// What failed.
        message: String,
    },
    /// Newton did not converge after every retry.
    #[error("step from t = {t} did not converge (best residual {residual:.3e}, {} index sets visited{})",
        visited_sets.len(), if *cycling { ", cycling" } else { "" })]
    NotConverged {
        /// Time at the start of the failed step.
        t: f64,
        /// Smallest residual reached.
        residual: f64,
        /// Index sets visited by the Newton iterates.
        visited_sets: Vec<IndexSets>,
        /// Whether the sets cycled (a possible branch point, docs/method.md §8).
        cycling: bool,
        /// The last good state (the stepper stays there).
        state: Box<State>,
    },
    /// A residual became NaN or infinite.
    #[error("non-finite residual in the step from t = {t}")]
    NonFinite {
        /// Time at the start of the step.
        t: f64,
        /// The last good state.
        state: Box<State>,
    },
    /// The step's contact problem has no solution (the last resort found none), or the
    /// last resort could not be set up.
    #[error("no step from t = {t}: {message}")]
    NoSolution {
        /// Time at the start of the step.
        t: f64,
        /// Why.
        message: String,
        /// The last good state.
        state: Box<State>,
    },
    /// The caller's [`Interrupt`](crate::Interrupt) stopped the step before it ended
    /// (a cancelled run, or one past its time bound).
    #[error("the step from t = {t} was interrupted before it ended")]
    Interrupted {
        /// Time at the start of the step.
        t: f64,
        /// The state the step started from (the stepper stays there).
        state: Box<State>,
    },
    /// The Newton matrix could not be factorised.
    #[error("linear solve in the step from t = {t}: {message}")]
    Linear {
        /// Time at the start of the step.
        t: f64,
        /// Solver message.
        message: String,
        /// The last good state.
        state: Box<State>,
    },
}

impl StepError {
    /// The last good state, from which a run can continue (None for invalid input and a
    /// failed start).
    #[must_use]
    pub fn state(&self) -> Option<&State> {
        match self {
            Self::NotConverged { state, .. }
            | Self::NonFinite { state, .. }
            | Self::Linear { state, .. }
            | Self::Interrupted { state, .. }
            | Self::NoSolution { state, .. } => Some(state),
            Self::InvalidInput(_) | Self::Start { .. } => None,
        }
    }
}
