//! What an attempt's iterates are evaluated and updated with, besides the state: the
//! generalized-α parameters of its ρ∞ (paper eq. 72), whether the friction percussions
//! shift the position by half a step (eq. 127), whether its updates may take the quick
//! forms of a step's first attempt, and how many rows its low-rank updates replace.

use super::Stepper;
use crate::params::GenAlpha;
use crate::system::System;

/// The scheme of one Newton attempt (part of its [`AttemptSpec`](super::spec::AttemptSpec)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Scheme {
    /// α_m, α_f, γ, β for the attempt's ρ∞.
    pub alpha: GenAlpha,
    /// Whether the friction percussions shift the position by half a step
    /// ([`Options::friction_percussion_shift`](crate::Options::friction_percussion_shift)).
    pub friction_shift: bool,
    /// Whether the updates may be low-rank updates of kept factors
    /// ([`LinearOptions::low_rank_updates`](crate::LinearOptions::low_rank_updates)) and kept
    /// factors of a regularized matrix: in a step's first attempt only.
    pub quick_updates: bool,
    /// Most rows a low-rank update replaces (`KeptFactors::low_rank_rows`).
    pub low_rank_rows: usize,
}

impl<S: System> Stepper<S> {
    /// The scheme of the options at ρ∞ = `rho_inf`, without quick updates.
    pub(super) fn scheme(&self, rho_inf: f64) -> Scheme {
        Scheme {
            alpha: GenAlpha::new(rho_inf),
            friction_shift: self.options.friction_percussion_shift,
            quick_updates: false,
            low_rank_rows: self.options.tuning.low_rank_rows,
        }
    }
}
