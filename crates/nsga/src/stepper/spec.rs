//! One Newton attempt at a step, as a value ([`AttemptSpec`]): where its iterates start,
//! how they choose their index sets, and what they iterate with. The stages of the
//! step's policy differ only in the attempts they ask for; none changes the options.

use super::held::HeldSets;
use super::scheme::Scheme;
use super::Stepper;
use crate::params::GenAlpha;
use crate::sets::IndexSets;
use crate::state::State;
use crate::system::System;

/// Where an attempt's Newton iterates start.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum StartAt {
    /// The unknowns x of the last accepted step (`State::x`).
    LastSolution,
    /// Other unknowns: a predicted start, or a fixed-set solution checked as a free one.
    Unknowns(Vec<f64>),
}

/// How an attempt's iterates choose their index sets.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum SetRule {
    /// The contact laws' sets at every iterate (eqs. 128–142).
    Free,
    /// The previous step's sets held, then released with at most `most` openings per
    /// update ([`HeldSets`], docs/method.md §8.2).
    Held {
        /// The previous step's sets.
        previous: IndexSets,
        /// Openings per update after the release.
        most: usize,
    },
    /// These sets throughout (a fixed-set re-solve).
    Fixed(IndexSets),
}

impl SetRule {
    /// The fixed sets, if any.
    pub(super) fn fixed(&self) -> Option<&IndexSets> {
        match self {
            Self::Fixed(sets) => Some(sets),
            Self::Free | Self::Held { .. } => None,
        }
    }

    /// The progress of a held-sets attempt at its start (None for other rules).
    pub(super) fn held_start(&self) -> Option<HeldSets> {
        match self {
            Self::Held { previous, most } => Some(HeldSets::new(previous.clone(), *most)),
            Self::Free | Self::Fixed(_) => None,
        }
    }
}

/// One Newton attempt at the step: everything [`Stepper::attempt`] needs besides the
/// stepper's state and options.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct AttemptSpec {
    /// Where the iterates start.
    pub start: StartAt,
    /// How they choose their index sets.
    pub sets: SetRule,
    /// The generalized-α ρ∞ of the attempt.
    pub rho_inf: f64,
    /// Largest number of Newton updates.
    pub budget: usize,
    /// Updates allowed beyond `budget` while the iterates converge
    /// (`NewtonSettings::contracting_extra`).
    pub contracting_extra: usize,
    /// Whether the friction percussions shift the position by half a step
    /// ([`Options::friction_percussion_shift`](crate::Options::friction_percussion_shift)).
    pub friction_shift: bool,
    /// Halvings of an update allowed in the line search (0: whole updates).
    pub line_search: usize,
    /// Whether the updates may take the quick forms of a step's first attempt
    /// ([`Scheme::quick_updates`]).
    pub quick_updates: bool,
    /// Whether the attempt may factor a Newton matrix of its own (false: it takes
    /// simplified and low-rank updates on the kept factors only).
    pub new_factors: bool,
    /// The factor by which each simplified or low-rank update must reduce ‖R‖∞ for the
    /// kept factors to serve on ([`Tuning::reuse_contraction`](crate::Tuning::reuse_contraction);
    /// 1 in a held-sets attempt, see [`Stepper::spec`]).
    pub reuse_contraction: f64,
}

impl AttemptSpec {
    /// The scheme the attempt's iterates are evaluated and updated with.
    pub(super) fn scheme(&self) -> Scheme {
        Scheme {
            alpha: GenAlpha::new(self.rho_inf),
            friction_shift: self.friction_shift,
            quick_updates: self.quick_updates,
        }
    }

    /// The unknowns the iterates start from, at the step from `state`, in a buffer of
    /// their own: the start's, taken out of the spec (an attempt reads its start once,
    /// and a predicted start is not needed after it), or `spare()` filled with the last
    /// solution.
    pub(super) fn take_start(
        &mut self,
        state: &State,
        spare: impl FnOnce() -> Vec<f64>,
    ) -> Vec<f64> {
        match &mut self.start {
            StartAt::LastSolution => {
                let mut x = spare();
                x.extend_from_slice(&state.x);
                x
            }
            StartAt::Unknowns(x) => std::mem::take(x),
        }
    }
}

impl<S: System> Stepper<S> {
    /// The attempt with `sets` at ρ∞ = `rho_inf` that the options describe: from the last
    /// solution, with a free attempt's budget ([`Stepper::free_budget`]) or, with fixed
    /// sets, [`NewtonOptions::max_iter`](crate::NewtonOptions::max_iter) updates; a held-sets
    /// attempt takes its updates whole (after the release each update changes the sets
    /// of a contact or a few, and halving such updates only delayed the next change;
    /// docs/method.md §8.2, `Stage::HeldSets` and `Stage::Free`) and keeps its factors
    /// while the residual falls.
    pub(super) fn spec(&self, sets: SetRule, rho_inf: f64) -> AttemptSpec {
        let budget = match sets {
            SetRule::Fixed(_) => self.options.newton.max_iter,
            SetRule::Free | SetRule::Held { .. } => self.free_budget(),
        };
        let line_search = match sets {
            SetRule::Held { .. } => 0,
            SetRule::Free | SetRule::Fixed(_) => self.options.newton.line_search,
        };
        // After the release a held-sets update opens at most a few contacts, which bounds
        // its progress whatever the factors: an exact update contracts no more than a
        // simplified one, so the kept factors serve while the residual falls. The value
        // holds for the whole attempt, the held solve before the release included, as
        // measured (docs/method.md §8.2, "The held-sets attempt").
        let reuse_contraction = match sets {
            SetRule::Held { .. } => 1.0,
            SetRule::Free | SetRule::Fixed(_) => self.options.tuning.reuse_contraction,
        };
        AttemptSpec {
            start: StartAt::LastSolution,
            sets,
            rho_inf,
            budget,
            contracting_extra: 0,
            friction_shift: self.options.friction_percussion_shift,
            line_search,
            quick_updates: false,
            new_factors: true,
            reuse_contraction,
        }
    }

    /// A retry or fixed-set re-solve: [`Stepper::spec`] with at most
    /// [`PolicyOptions::retry_max_iter`](crate::PolicyOptions::retry_max_iter) updates, free retries
    /// too (their budget would otherwise grow with the contacts).
    pub(super) fn retry_spec(&self, sets: SetRule, rho_inf: f64) -> AttemptSpec {
        AttemptSpec {
            budget: self
                .options
                .policy
                .retry_max_iter
                .min(self.options.newton.max_iter),
            ..self.spec(sets, rho_inf)
        }
    }

    /// Largest number of updates of a free attempt: see
    /// [`NewtonOptions::max_iter_per_contact`](crate::NewtonOptions::max_iter_per_contact).
    pub(super) fn free_budget(&self) -> usize {
        self.free_budget_over(self.options.newton.max_iter)
    }

    /// [`Stepper::free_budget`] with `max_iter` in place of the options'.
    pub(super) fn free_budget_over(&self, max_iter: usize) -> usize {
        (self.options.newton.max_iter_per_contact * self.off.nn).max(max_iter)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec_from(start: StartAt) -> AttemptSpec {
        AttemptSpec {
            start,
            sets: SetRule::Free,
            rho_inf: 0.8,
            budget: 10,
            contracting_extra: 0,
            friction_shift: true,
            line_search: 0,
            quick_updates: false,
            new_factors: true,
            reuse_contraction: 0.1,
        }
    }

    /// A held-sets attempt keeps its factors while the residual falls; the others ask
    /// each simplified update to contract it by `Tuning::reuse_contraction`
    /// (docs/method.md §8.2, "The held-sets attempt").
    #[test]
    fn a_held_sets_attempt_keeps_its_factors_while_the_residual_falls() {
        use crate::systems::chain::Chain;
        use crate::Options;
        let chain = Chain::benchmark(2);
        let q0 = [0.0, chain.height / 2.0, 0.0, 2.0 * chain.height];
        let s = Stepper::new(chain, 0.0, &q0, &[0.0; 4], Options::default()).unwrap();
        let previous = IndexSets::empty(s.off.nn, s.layout.friction.len());
        let held = s.spec(SetRule::Held { previous, most: 1 }, 0.8);
        assert_eq!(held.reuse_contraction, 1.0);
        let tuned = s.options.tuning.reuse_contraction;
        assert!(tuned < 1.0);
        assert_eq!(s.spec(SetRule::Free, 0.8).reuse_contraction, tuned);
    }

    #[test]
    fn a_start_of_its_own_becomes_the_iterates_buffer() {
        let state = State {
            x: vec![1.0, 2.0],
            ..State::default()
        };
        let predicted = vec![3.0, 4.0];
        let buffer = predicted.as_ptr();
        let mut spec = spec_from(StartAt::Unknowns(predicted));
        let x = spec.take_start(&state, || panic!("no spare buffer is needed"));
        assert_eq!((x.as_slice(), x.as_ptr()), (&[3.0, 4.0][..], buffer));
        // From the last solution: copied into the spare buffer.
        let spare = Vec::with_capacity(2);
        let buffer = spare.as_ptr();
        let x = spec_from(StartAt::LastSolution).take_start(&state, || spare);
        assert_eq!((x.as_slice(), x.as_ptr()), (&[1.0, 2.0][..], buffer));
    }
}
