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
    /// The attempt gives up at its start where ‖R‖∞ there exceeds this
    /// (`NewtonSettings::start_limit`; ∞: never).
    pub start_limit: f64,
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
    /// How long the kept factors serve, and how far their low-rank updates reach.
    pub kept: KeptFactors,
}

/// How long an attempt's kept factors serve (docs/method.md §8.1, "Simplified Newton
/// with kept factors"; §8.2, "The held-sets attempt"): [`Stepper::spec`] sets it by the
/// set rule.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct KeptFactors {
    /// The factor by which each simplified or low-rank update must reduce ‖R‖∞ for them
    /// to serve on ([`Tuning::reuse_contraction`](crate::Tuning::reuse_contraction)).
    pub contraction: f64,
    /// Most rows of the Newton matrix a low-rank update replaces
    /// ([`Tuning::low_rank_rows`](crate::Tuning::low_rank_rows)).
    pub low_rank_rows: usize,
    /// Whether they follow the index sets ([`NewtonSettings::follow_sets`](crate::newton::NewtonSettings::follow_sets)).
    pub follow_sets: bool,
}

impl AttemptSpec {
    /// The scheme the attempt's iterates are evaluated and updated with.
    pub(super) fn scheme(&self) -> Scheme {
        Scheme {
            alpha: GenAlpha::new(self.rho_inf),
            friction_shift: self.friction_shift,
            quick_updates: self.quick_updates,
            low_rank_rows: self.kept.low_rank_rows,
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
    /// docs/method.md §8.2, `Stage::HeldSets` and `Stage::Free`) and its kept factors
    /// follow its sets ([`Stepper::kept_factors`]).
    pub(super) fn spec(&self, sets: SetRule, rho_inf: f64) -> AttemptSpec {
        let budget = match sets {
            SetRule::Fixed(_) => self.options.newton.max_iter,
            SetRule::Free | SetRule::Held { .. } => self.free_budget(),
        };
        let line_search = match sets {
            SetRule::Held { .. } => 0,
            SetRule::Free | SetRule::Fixed(_) => self.options.newton.line_search,
        };
        let kept = self.kept_factors(&sets);
        AttemptSpec {
            start: StartAt::LastSolution,
            sets,
            rho_inf,
            budget,
            contracting_extra: 0,
            start_limit: f64::INFINITY,
            friction_shift: self.options.friction_percussion_shift,
            line_search,
            quick_updates: false,
            new_factors: true,
            kept,
        }
    }

    /// How long the kept factors of an attempt with `sets` serve. In most attempts, while
    /// each update contracts the residual by [`Tuning::reuse_contraction`](crate::Tuning::reuse_contraction),
    /// at most [`Tuning::max_reuses`](crate::Tuning::max_reuses) in a row. In a held-sets
    /// attempt they follow its sets: after the release each update opens at most a few
    /// contacts, which bounds its progress whatever the factors, so they serve while the
    /// residual falls at all, and on through a rise at sets that a low-rank update of up
    /// to [`Tuning::held_low_rank_rows`](crate::Tuning::held_low_rank_rows) rows reached
    /// first, where the count of updates in a row starts afresh: a rocking corner that
    /// climbs the column one interface every two updates, or a band of corners that open
    /// one per update, reaches new sets again and again, whose residual does not compare
    /// with the last one's (docs/method.md §8.2, "The held-sets attempt").
    pub(super) fn kept_factors(&self, sets: &SetRule) -> KeptFactors {
        let t = &self.options.tuning;
        match sets {
            SetRule::Held { .. } => {
                let follow_sets = self.options.newton.held_factors_follow_sets;
                KeptFactors {
                    contraction: 1.0,
                    low_rank_rows: if follow_sets {
                        t.held_low_rank_rows
                    } else {
                        t.low_rank_rows
                    },
                    follow_sets,
                }
            }
            SetRule::Free | SetRule::Fixed(_) => KeptFactors {
                contraction: t.reuse_contraction,
                low_rank_rows: t.low_rank_rows,
                follow_sets: false,
            },
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
            start_limit: f64::INFINITY,
            friction_shift: true,
            line_search: 0,
            quick_updates: false,
            new_factors: true,
            kept: KeptFactors {
                contraction: 0.1,
                low_rank_rows: 8,
                follow_sets: false,
            },
        }
    }

    /// A held-sets attempt's kept factors follow its sets, with low-rank updates of
    /// `Tuning::held_low_rank_rows` rows, while the residual falls at all; the others ask each
    /// simplified update to contract the residual by `Tuning::reuse_contraction`
    /// (docs/method.md §8.2, "The held-sets attempt").
    #[test]
    fn a_held_sets_attempts_kept_factors_follow_its_sets() {
        use crate::systems::chain::Chain;
        use crate::Options;
        let chain = Chain::benchmark(2);
        let q0 = [0.0, chain.height / 2.0, 0.0, 2.0 * chain.height];
        let s = Stepper::new(chain, 0.0, &q0, &[0.0; 4], Options::default()).unwrap();
        let t = s.options.tuning;
        let previous = IndexSets::empty(s.off.nn, s.layout.friction.len());
        let held = s.spec(SetRule::Held { previous, most: 1 }, 0.8);
        let following = KeptFactors {
            contraction: 1.0,
            low_rank_rows: t.held_low_rank_rows,
            follow_sets: true,
        };
        assert_eq!(held.kept, following);
        assert_eq!(held.scheme().low_rank_rows, t.held_low_rank_rows);
        let contracting = KeptFactors {
            contraction: t.reuse_contraction,
            low_rank_rows: t.low_rank_rows,
            follow_sets: false,
        };
        assert!(t.reuse_contraction < 1.0 && t.held_low_rank_rows > t.low_rank_rows);
        assert_eq!(s.spec(SetRule::Free, 0.8).kept, contracting);
        let fixed = SetRule::Fixed(IndexSets::empty(s.off.nn, s.layout.friction.len()));
        assert_eq!(s.spec(fixed, 0.8).kept, contracting);
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
