//! One Newton attempt at the step (eq. 143) on the crate's [`crate::newton`]
//! engine: the step as a [`NewtonProblem`] (docs/method.md §4), with open contacts pruned
//! from its linear solve ([`super::prune`]) and its updates from [`super::direction`].

use super::direction::Refusal;
use super::held::{HeldSets, SetPolicy};
use super::kinematic::KinematicColumns;
use super::prune::Pruning;
use super::Stepper;
use crate::attempt::{AttemptFailure, Trial};
use crate::newton::{self, GiveUp, NewtonProblem, NewtonSettings, Outcome};
use crate::params::GenAlpha;
use crate::sets::IndexSets;
use crate::system::System;
use nalgebra::DMatrix;
use std::time::Instant;

/// The step seen by the Newton engine: the stepper at one ρ∞, with fixed index sets or
/// not, and the contacts pruned from this attempt.
struct StepProblem<'a, S: System> {
    stepper: &'a mut Stepper<S>,
    fixed: Option<&'a IndexSets>,
    params: GenAlpha,
    prune: Option<&'a Pruning>,
    /// The pruned contacts that closed at the iterate that asked for a restart.
    closing: Vec<bool>,
    /// The progress of a held-sets attempt ([`SetPolicy::Held`]).
    held: Option<HeldSets>,
    /// Whether this solve continues an attempt after a restart ([`Resumed`]).
    resuming: bool,
}

/// How far an attempt went before a pruned contact closed and asked for a restart: the
/// updates it made, and the progress of its held sets. The attempt goes on from the
/// iterate of the restart with that contact kept; its budget counts the updates before.
struct Resumed {
    updates: usize,
    held: Option<HeldSets>,
}

impl<S: System> NewtonProblem for StepProblem<'_, S> {
    type Sets = IndexSets;

    fn evaluate(&mut self, x: &[f64], first: bool) -> (IndexSets, f64) {
        let started = Instant::now();
        // A resumed attempt keeps the prox parameters of its start.
        let first = first && !self.resuming;
        let out = match &mut self.held {
            Some(held) => self.stepper.evaluate_held(x, &self.params, first, held),
            None => self
                .stepper
                .evaluate_at(x, self.fixed, &self.params, first, None),
        };
        let work = &mut self.stepper.newton_work;
        work.evaluations += 1;
        work.seconds.evaluation += started.elapsed().as_secs_f64();
        out
    }

    /// A contact pruned as unable to close does close at this iterate: the attempt goes
    /// on from it with that contact kept in the system ([`Resumed`]).
    fn restart(&mut self, sets: &IndexSets) -> bool {
        let Some((map, _)) = self.prune else {
            return false;
        };
        let o = self.stepper.off;
        self.closing.clear();
        self.closing
            .extend((0..o.nn).map(|k| map[o.kn + k] == usize::MAX && sets.a[k]));
        self.closing.iter().any(|&c| c)
    }

    fn exact_direction(
        &mut self,
        x: &[f64],
        sets: &IndexSets,
        dx: &mut [f64],
    ) -> Result<(), String> {
        if let Some(held) = &mut self.held {
            held.updated(sets);
        }
        let started = Instant::now();
        let jacobian_before = self.stepper.newton_work.seconds.jacobian;
        let out = self
            .stepper
            .exact_direction(x, sets, &self.params, self.prune, dx)
            .map_err(|e| e.0);
        let st = &mut *self.stepper;
        let work = &mut st.newton_work;
        work.exact_updates += 1;
        let because = &mut work.exact_because;
        *match st.refusal.take() {
            None => &mut because.not_asked,
            Some(Refusal::NoKeptFactors) => &mut because.no_kept_factors,
            Some(Refusal::OtherSystem) => &mut because.other_system,
            Some(Refusal::SetsChanged) => &mut because.sets_changed,
        } += 1;
        let jacobian = work.seconds.jacobian - jacobian_before;
        work.seconds.factorization += started.elapsed().as_secs_f64() - jacobian;
        out
    }

    fn recycle(&mut self, sets: IndexSets) {
        self.stepper.recycle_sets(sets);
    }

    fn kept_direction(&mut self, x: &[f64], sets: &IndexSets, dx: &mut [f64]) -> bool {
        let started = Instant::now();
        let kept = self
            .stepper
            .kept_direction(x, sets, &self.params, self.prune, dx);
        self.stepper.newton_work.seconds.simplified += started.elapsed().as_secs_f64();
        if let (true, Some(held)) = (kept, &mut self.held) {
            held.updated(sets);
        }
        kept
    }
}

impl<S: System> Stepper<S> {
    /// One Newton attempt at the step from the state's unknowns `x`, with ρ∞ = `rho_inf`
    /// and the index sets computed per iterate or `fixed`; open contacts are pruned when
    /// [`Options::prune_open_contacts`](crate::Options::prune_open_contacts) asks for it
    /// (with fixed sets, only those the sets leave open).
    pub(super) fn solve(
        &mut self,
        fixed: Option<&IndexSets>,
        rho_inf: f64,
        x: Vec<f64>,
    ) -> Result<Trial, AttemptFailure> {
        let policy = SetPolicy::Free {
            budget: self.free_budget(),
        };
        self.solve_with(fixed, &policy, rho_inf, x)
    }

    /// Whether this attempt takes the updates of
    /// [`Options::low_rank_updates`](crate::Options::low_rank_updates): a step's first
    /// attempt, when they are asked for.
    pub(super) fn quick_updates(&self) -> bool {
        self.options.low_rank_updates && self.work.first_attempt
    }

    /// Largest number of updates of a free attempt: see
    /// [`Options::max_iter_per_contact`](crate::Options::max_iter_per_contact).
    pub(super) fn free_budget(&self) -> usize {
        (self.options.max_iter_per_contact * self.off.nn).max(self.options.max_iter)
    }

    /// [`Stepper::solve`] with the sets of a free attempt chosen by `policy` (ignored
    /// when the sets are `fixed`).
    pub(super) fn solve_with(
        &mut self,
        fixed: Option<&IndexSets>,
        policy: &SetPolicy,
        rho_inf: f64,
        x: Vec<f64>,
    ) -> Result<Trial, AttemptFailure> {
        let keep = self.options.prune_open_contacts.then(|| {
            (0..self.off.nn)
                .map(|k| fixed.is_some_and(|f| f.a[k]))
                .collect()
        });
        self.solve_keeping(fixed, policy, rho_inf, x, keep)
    }

    /// [`Stepper::solve_with`] with `keep` the contacts that may not be pruned (None: no
    /// pruning).
    fn solve_keeping(
        &mut self,
        fixed: Option<&IndexSets>,
        policy: &SetPolicy,
        rho_inf: f64,
        mut x: Vec<f64>,
        keep: Option<Vec<bool>>,
    ) -> Result<Trial, AttemptFailure> {
        self.solve_resuming(fixed, policy, rho_inf, &mut x, keep, None)
    }

    /// [`Stepper::solve_keeping`] from the iterate `x`, which continues an attempt when
    /// `resumed` says how far it went (see [`Resumed`]).
    fn solve_resuming(
        &mut self,
        fixed: Option<&IndexSets>,
        policy: &SetPolicy,
        rho_inf: f64,
        x: &mut Vec<f64>,
        keep: Option<Vec<bool>>,
        resumed: Option<Resumed>,
    ) -> Result<Trial, AttemptFailure> {
        let prune = keep.as_ref().and_then(|k| self.open_contacts(x, k));
        self.mark_unused(prune.as_ref().map(|(map, _)| map.as_slice()));
        let params = GenAlpha::new(rho_inf);
        let budget = match fixed {
            None => policy.budget(),
            Some(_) => self.options.max_iter,
        };
        let updates_before = resumed.as_ref().map_or(0, |r| r.updates);
        let max_iter = budget.saturating_sub(updates_before);
        // The held-sets attempt takes its updates whole: after the release each update
        // changes the sets of a contact or a few, and halving such updates only delayed
        // the next change (docs/method.md §8.2, stage 1).
        let line_search = match policy {
            SetPolicy::Held { .. } => 0,
            SetPolicy::Free { .. } => self.options.line_search,
        };
        let settings = NewtonSettings {
            tol: self.options.tol,
            max_iter,
            line_search,
            reuse_factorization: self.options.reuse_factorization,
            resume_reuse: self.quick_updates(),
            give_up: if fixed.is_some() {
                GiveUp::Stall
            } else {
                GiveUp::SettledCycle
            },
            contracting_extra: self.contracting_extra,
        };
        self.prepare_step();
        let mut scratch = std::mem::take(&mut self.work.newton);
        let (held, resuming) = match resumed {
            Some(r) => (r.held, true),
            None => match (fixed, policy) {
                (None, SetPolicy::Held { previous, most, .. }) => {
                    (Some(HeldSets::new(previous.clone(), *most)), false)
                }
                _ => (None, false),
            },
        };
        let mut problem = StepProblem {
            stepper: self,
            fixed,
            params,
            prune: prune.as_ref(),
            closing: Vec::new(),
            held,
            resuming,
        };
        let outcome = newton::solve(&mut problem, x, &settings, &mut scratch);
        let (closing, held) = (problem.closing, problem.held);
        self.newton_work.line_search_trials += scratch.line_search_trials();
        // Updates this solve made: one fewer than its evaluations.
        let updates = updates_before + scratch.evaluations().saturating_sub(1);
        self.work.newton = scratch;
        match outcome {
            Outcome::Converged { visited, sets, .. } if self.is_far(x) => {
                // Refused as a failed attempt, not as a cycling one: the fixed-set
                // re-solves of the sets it wandered through cost more than the policy's
                // later stages, which found the near solution (docs/method.md §8.1).
                self.newton_work.far_solutions += 1;
                let mut visited = visited;
                if !visited.contains(&sets) {
                    visited.push(sets);
                }
                Err(AttemptFailure::NotConverged {
                    visited,
                    cycling: false,
                    best: None,
                })
            }
            Outcome::Converged {
                sets,
                iterations,
                residual,
                visited,
            } => Ok(self.make_trial(
                std::mem::take(x),
                sets,
                updates_before + iterations,
                residual,
                rho_inf,
                true,
                visited,
                false,
            )),
            Outcome::Restart => {
                // The iterate is the one the unpruned attempt would have reached (a pruned
                // contact's unknowns stay zero while it is open): go on from it with the
                // closing contacts kept, within what is left of the budget.
                let mut keep = keep.unwrap_or_else(|| vec![false; self.off.nn]);
                for (kk, c) in keep.iter_mut().zip(closing) {
                    *kk |= c;
                }
                let resumed = Resumed { updates, held };
                self.solve_resuming(fixed, policy, rho_inf, x, Some(keep), Some(resumed))
            }
            Outcome::NonFinite => Err(AttemptFailure::NonFinite),
            Outcome::Singular(message) => Err(AttemptFailure::Singular { message }),
            Outcome::NotConverged {
                visited,
                cycling,
                best,
            } => {
                let best = best.map(|b| {
                    // Re-derive the best iterate's state.
                    self.derive(&b.x, &params);
                    Box::new(self.make_trial(
                        b.x,
                        b.sets,
                        b.iteration,
                        b.residual,
                        rho_inf,
                        false,
                        Vec::new(),
                        cycling,
                    ))
                });
                Err(AttemptFailure::NotConverged {
                    visited,
                    cycling,
                    best,
                })
            }
        }
    }

    /// Evaluates the iterate `x`: kinematic updates, system, index sets (the fixed ones
    /// when given) and residual; returns the sets and ‖R‖∞.
    ///
    /// With `limit` (free sets only) and ‖R‖∞ above the tolerance, the returned sets are
    /// those of [`Stepper::compute_sets`] with that limit on openings, and the residual
    /// kept for the next update is theirs; ‖R‖∞ stays that of the laws' own sets.
    pub(super) fn evaluate_at(
        &mut self,
        x: &[f64],
        fixed: Option<&IndexSets>,
        p: &GenAlpha,
        update_prox: bool,
        limit: Option<(&IndexSets, usize)>,
    ) -> (IndexSets, f64) {
        self.derive(x, p);
        self.evaluate_iterate(update_prox);
        self.finish_accelerations(x);
        let sets = match fixed {
            Some(s) => s.clone(),
            None => self.compute_sets(x, None, update_prox),
        };
        self.residual(x, &sets, p);
        let res = crate::linalg::max_norm(&self.work.res);
        if let Some(limit) = limit.filter(|_| fixed.is_none() && res > self.options.tol) {
            let limited = self.compute_sets(x, Some(limit), update_prox);
            if limited != sets {
                self.residual(x, &limited, p);
                return (limited, res);
            }
        }
        (sets, res)
    }

    /// The index sets the contact laws give at unknowns `x` (no Newton update).
    pub fn sets_of(&mut self, x: &[f64], rho_inf: f64) -> IndexSets {
        let p = GenAlpha::new(rho_inf);
        self.prepare_step();
        self.derive(x, &p);
        self.evaluate_iterate(true);
        self.finish_accelerations(x);
        self.compute_sets(x, None, false)
    }

    /// Test oracle hook: the scaled residual R(x) and the semismooth Jacobian ∂R/∂x
    /// (dense) for fixed sets. `update_prox` recomputes the prox parameters from this x
    /// (keep it false when finite-differencing, so that r stays fixed).
    #[doc(hidden)]
    pub fn newton_system(
        &mut self,
        x: &[f64],
        sets: &IndexSets,
        rho_inf: f64,
        update_prox: bool,
    ) -> (Vec<f64>, DMatrix<f64>) {
        let p = GenAlpha::new(rho_inf);
        // The derivative rows are replaced: the kept factors no longer fit them.
        self.work.factored = None;
        self.prepare_step();
        self.derive(x, &p);
        self.evaluate_iterate(update_prox);
        self.finish_accelerations(x);
        self.residual(x, sets, &p);
        // The full matrix: nothing pruned.
        self.mark_unused(None);
        self.jacobian(x, sets, &p);
        let n = self.off.n;
        let mut j = DMatrix::zeros(n, n);
        for &(r, c, v) in &self.work.jac {
            j[(r, c)] += v;
        }
        KinematicColumns::new(self.options.dt, &p).to_unknown_columns(&self.off, &mut j);
        (self.work.res.clone(), j)
    }
}
