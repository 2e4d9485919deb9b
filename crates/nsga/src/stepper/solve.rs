//! One Newton attempt at the step (eq. 143) on the crate's [`crate::newton`]
//! engine: the step as a [`NewtonProblem`], the pruning of open contacts from the linear
//! solve, and the Newton update with its regularization of singular matrices
//! (docs/method.md §4, §7).

use super::assemble::KinematicColumns;
use super::held::{HeldSets, SetPolicy};
use super::{FactoredFor, Stepper, SINGULAR_SETS_KEPT};
use crate::attempt::{AttemptFailure, Trial};
use crate::linalg::{equilibrate_rows, max_norm};
use crate::newton::{self, GiveUp, NewtonProblem, NewtonSettings, Outcome};
use crate::params::GenAlpha;
use crate::report::StepStats;
use crate::sets::IndexSets;
use crate::state::State;
use crate::system::System;
use nalgebra::DMatrix;
use std::time::Instant;

/// The map full → reduced index of the unknowns left in the linear solve
/// (`usize::MAX` for a pruned one) and the reduced size.
pub(super) type Pruning = (Vec<usize>, usize);

/// Writes the entries of the full-length `full` left in the linear solve into `reduced`,
/// in the reduced numbering of the prune `map` (all of them, in order, without one).
pub(super) fn restrict(map: Option<&[usize]>, full: &[f64], reduced: &mut [f64]) {
    let Some(map) = map else {
        reduced.copy_from_slice(full);
        return;
    };
    for (&m, &v) in map.iter().zip(full) {
        if m != usize::MAX {
            reduced[m] = v;
        }
    }
}

/// The inverse of [`restrict`]: `full` from `reduced`, the pruned entries 0.
pub(super) fn expand(map: Option<&[usize]>, reduced: &[f64], full: &mut [f64]) {
    let Some(map) = map else {
        full.copy_from_slice(reduced);
        return;
    };
    for (f, &m) in full.iter_mut().zip(map) {
        *f = if m == usize::MAX { 0.0 } else { reduced[m] };
    }
}

/// How a Newton update gets its factors.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Factor {
    /// Factor the assembled Jacobian as it is.
    Plain,
    /// Factor the regularized Jacobian with its rows equilibrated by their plain
    /// entries (docs/method.md §7): the rows span scales from 1/Δt to Δt, and the
    /// singularity test compares pivots across them, so without it a regularized row
    /// failed the test at small Δt.
    Equilibrated,
    /// Reuse the kept factors (a simplified Newton update).
    Kept,
    /// Reuse the kept factors of an `Equilibrated` matrix, whose row scales the
    /// right-hand side takes.
    KeptEquilibrated,
}

/// Why the kept factors gave no simplified update (`NewtonWork::exact_because`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Refusal {
    /// None are kept.
    NoKeptFactors,
    /// They were made for another Δt or ρ∞, or without a contact this attempt keeps
    /// (for other sets: with another prune map).
    OtherSystem,
    /// They fit, but the sets changed too much for them, or their update failed.
    SetsChanged,
}

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
    fn quick_updates(&self) -> bool {
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

    /// Marks the unknowns of contacts that are open, force-free and cannot close within
    /// the step, sets them to zero in `x`, and returns the map full → reduced index
    /// (`usize::MAX` for pruned) and the reduced size; None when nothing is pruned.
    fn open_contacts(&mut self, x: &mut [f64], keep: &[bool]) -> Option<Pruning> {
        let o = self.off;
        let dt = self.options.dt;
        self.state_levels();
        let st = &self.state;
        let levels = &self.work.state_levels;
        let (gap, rate, acc) = (&levels.position, &levels.rate, &levels.acceleration);
        let mut pruned_n = vec![false; o.nn];
        for (k, pr) in pruned_n.iter_mut().enumerate() {
            let pk = o.ng + k;
            let margin = 2.0 * dt * rate[pk].abs() + dt * dt * acc[pk].abs();
            *pr = !keep[k]
                && gap[pk] > margin
                && gap[pk] > 0.0
                && st.lambda_n[k] == 0.0
                && st.lambda_n_bar[k] == 0.0;
        }
        if !pruned_n.iter().any(|&b| b) {
            return None;
        }
        let mut map = vec![0usize; o.n];
        let prune_unknown = |i: usize, map: &mut Vec<usize>, x: &mut [f64]| {
            map[i] = usize::MAX;
            x[i] = 0.0;
        };
        for (k, &pr) in pruned_n.iter().enumerate() {
            if pr {
                for base in [o.kn, o.cn, o.ln] {
                    prune_unknown(base + k, &mut map, x);
                }
            }
        }
        for (j, law) in self.layout.friction.iter().enumerate() {
            let f0 = self.law_off[j];
            let quiet = (0..law.components)
                .all(|m| st.lambda_f[f0 + m] == 0.0 && st.lambda_f_bar[f0 + m] == 0.0);
            if quiet && law.normals.iter().all(|&k| pruned_n[k]) {
                for m in 0..law.components {
                    prune_unknown(o.cf + f0 + m, &mut map, x);
                    prune_unknown(o.lf + f0 + m, &mut map, x);
                }
            }
        }
        let n_red = number_kept(&mut map);
        Some((map, n_red))
    }

    /// Makes `work.state_levels` those of the current state: kept from the iterate that
    /// became it (`state_levels`), or evaluated here.
    fn state_levels(&mut self) {
        let st = &self.state;
        let w = &mut self.work;
        if w.state_levels.describe(st) {
            return;
        }
        w.eval.reset();
        self.system.evaluate_real(st.t, &st.q, &st.u, &mut w.eval);
        w.state_levels.evaluate(st, &w.eval);
    }

    /// Marks the constraints whose unknowns the prune `map` leaves out (none without).
    fn mark_unused(&mut self, map: Option<&[usize]>) {
        let o = self.off;
        let w = &mut self.work;
        w.unused_position.clear();
        w.unused_velocity.clear();
        if let Some(map) = map {
            let pruned = |i: usize| map[i] == usize::MAX;
            w.unused_position.resize(o.ng, false);
            w.unused_position
                .extend((0..o.nn).map(|k| pruned(o.kn + k)));
            w.unused_velocity.resize(o.nga, false);
            w.unused_velocity
                .extend((0..o.nf).map(|c| pruned(o.cf + c)));
        }
    }

    /// The exact Newton update at `x` (eq. 143) into `dx`: assembles and factors the
    /// Jacobian, regularized ([`Options::regularization`](crate::Options::regularization))
    /// when it is singular.
    pub(super) fn exact_direction(
        &mut self,
        x: &[f64],
        sets: &IndexSets,
        p: &GenAlpha,
        prune: Option<&Pruning>,
        dx: &mut [f64],
    ) -> Result<(), crate::linalg::LinalgError> {
        let eps = self.options.regularization;
        // The factors made below replace the kept ones; a regularized matrix's serve the
        // same sets only, and only in a step's first attempt (docs/method.md §7).
        self.work.factored = None;
        // Redundancy is a property of which contacts are closed: sets whose normal
        // contacts are those of a singular plain matrix go straight to the regularized
        // one, whatever their friction sets.
        let redundant = |known: &IndexSets| known.same_normal_sets(sets);
        let started = Instant::now();
        self.jacobian(x, sets, p);
        self.newton_work.seconds.jacobian += started.elapsed().as_secs_f64();
        if !(eps > 0.0 && self.work.singular_sets.iter().any(redundant)) {
            match self
                .newton_direction(prune, Factor::Plain, p, dx)
                .and_then(|()| numerically_regular(x, dx))
            {
                Ok(()) => {
                    if self.options.low_rank_updates {
                        let w = &mut self.work;
                        let factored = if prune.is_some() {
                            &mut w.jac_pruned
                        } else {
                            &mut w.jac
                        };
                        // Swapped, not copied: the buffer left here holds the matrix
                        // factored before, and is assembled anew before its next read.
                        w.low_rank.factored(factored);
                    }
                    self.work.factored = Some(FactoredFor {
                        sets: sets.clone(),
                        prune: prune.cloned(),
                        dt: self.options.dt,
                        rho_inf: p.rho_inf,
                        regularized: false,
                    });
                    return Ok(());
                }
                Err(e) if eps <= 0.0 => return Err(e),
                Err(_) => {}
            }
        }
        // Redundant closed contacts: solve the regularized linearization.
        let known = &mut self.work.singular_sets;
        if !known.iter().any(redundant) {
            if known.len() == SINGULAR_SETS_KEPT {
                known.remove(0);
            }
            known.push(sets.clone());
        }
        self.regularize(eps);
        self.newton_direction(prune, Factor::Equilibrated, p, dx)?;
        if self.options.reuse_factorization && self.work.first_attempt {
            self.work.factored = Some(FactoredFor {
                sets: sets.clone(),
                prune: prune.cloned(),
                dt: self.options.dt,
                rho_inf: p.rho_inf,
                regularized: true,
            });
        }
        Ok(())
    }

    /// The simplified Newton update at `x` from the solver's kept factors into `dx`, when
    /// they were assembled for this prune map, Δt and ρ∞, and for these sets or (with
    /// [`Self::quick_updates`]) sets that differ in a few rows (the low-rank update of
    /// `low_rank`); false otherwise.
    fn kept_direction(
        &mut self,
        x: &[f64],
        sets: &IndexSets,
        p: &GenAlpha,
        prune: Option<&Pruning>,
        dx: &mut [f64],
    ) -> bool {
        let map = prune.map(|(map, _)| map);
        // A refused update is followed by an exact one, which counts why.
        self.refusal = None;
        let Some(kept) = self.work.factored.take() else {
            self.refusal = Some(Refusal::NoKeptFactors);
            return false;
        };
        let same_sets = &kept.sets == sets;
        let kept_map = kept.prune.as_ref().map(|(map, _)| map);
        let same_system = kept.dt == self.options.dt && kept.rho_inf == p.rho_inf;
        let fits = same_system
            && (kept_map == map || same_sets && keeps_all_of(kept_map, map.map(Vec::as_slice)));
        if !fits {
            self.work.factored = Some(kept);
            self.refusal = Some(Refusal::OtherSystem);
            return false;
        }
        let taken = if same_sets {
            // With more contacts pruned now than in the kept factors, the extra ones are
            // open in both sets with a zero residual: their rows, an open contact's, hold
            // only their own unknowns and give them a zero update, so the factors solve
            // the reduced system of the point they were made at.
            let factor = if kept.regularized {
                Factor::KeptEquilibrated
            } else {
                Factor::Kept
            };
            let update = self
                .newton_direction(kept.prune.as_ref(), factor, p, dx)
                .and_then(|()| numerically_regular(x, dx));
            self.work.factored = Some(kept);
            update.is_ok()
        } else {
            let plain = !kept.regularized;
            self.work.factored = Some(kept);
            plain
                && self.quick_updates()
                && self.low_rank_direction(x, sets, p, prune, dx)
                && numerically_regular(x, dx).is_ok()
        };
        let work = &mut self.newton_work;
        match (taken, same_sets) {
            (false, _) => self.refusal = Some(Refusal::SetsChanged),
            (true, true) => work.kept_updates += 1,
            (true, false) => work.low_rank_updates += 1,
        }
        taken
    }

    /// The Newton update dx = −J⁻¹R from the assembled Jacobian and residual, or with
    /// `again` from the solver's kept factors (a simplified Newton update), on the reduced
    /// system when open contacts are pruned (their updates are 0). The matrix is
    /// assembled in the unknowns z of [`KinematicColumns`]; dx = T dz.
    fn newton_direction(
        &mut self,
        prune: Option<&Pruning>,
        factor: Factor,
        p: &GenAlpha,
        dx: &mut [f64],
    ) -> Result<(), crate::linalg::LinalgError> {
        let out = self.newton_direction_in_z(prune, factor, dx);
        KinematicColumns::new(self.options.dt, p).to_unknowns(&self.off, dx);
        out
    }

    /// [`Self::newton_direction`] before the change back to x: dz = −(∂R/∂x T)⁻¹ R.
    fn newton_direction_in_z(
        &mut self,
        prune: Option<&Pruning>,
        factor: Factor,
        dx: &mut [f64],
    ) -> Result<(), crate::linalg::LinalgError> {
        let w = &mut self.work;
        let again = matches!(factor, Factor::Kept | Factor::KeptEquilibrated);
        if !again {
            w.linear_solves += 1;
        }
        dx.iter_mut().zip(&w.res).for_each(|(d, r)| *d = -r);
        if factor == Factor::Equilibrated {
            equilibrate_rows(self.off.n, &mut w.jac, &w.regularized, &mut w.row_scale);
        }
        if matches!(factor, Factor::Equilibrated | Factor::KeptEquilibrated) {
            dx.iter_mut().zip(&w.row_scale).for_each(|(d, s)| *d *= s);
        }
        let Some((map, n_red)) = prune else {
            return if again {
                w.solver.solve_again(dx)
            } else {
                w.solver.solve(self.off.n, &w.jac, dx)
            };
        };
        w.rhs_red.clear();
        w.rhs_red.resize(*n_red, 0.0);
        restrict(Some(map), dx, &mut w.rhs_red);
        let out = if again {
            w.solver.solve_again(&mut w.rhs_red)
        } else {
            // Renumbered without a branch per entry: about one entry in seven is pruned,
            // in no predictable order.
            let pruned = &mut w.jac_pruned;
            pruned.resize(w.jac.len(), (0, 0, 0.0));
            let mut kept = 0;
            for &(r, c, v) in &w.jac {
                let (r, c) = (map[r], map[c]);
                pruned[kept] = (r, c, v);
                kept += usize::from(r != usize::MAX && c != usize::MAX);
            }
            pruned.truncate(kept);
            w.solver.solve(*n_red, pruned, &mut w.rhs_red)
        };
        expand(Some(map), &w.rhs_red, dx);
        out
    }

    #[allow(clippy::fn_params_excessive_bools)]
    pub(super) fn make_trial(
        &mut self,
        x: Vec<f64>,
        sets: IndexSets,
        iterations: usize,
        residual: f64,
        rho_inf: f64,
        converged: bool,
        visited: Vec<IndexSets>,
        cycling: bool,
    ) -> Trial {
        let o = self.off;
        if converged {
            // The attempt ended on an evaluation of this x.
            let (k, t) = (self.state.k + 1, self.t_next());
            let w = &mut self.work;
            w.trial_levels.record(k, t, &x, &w.it);
        }
        // Into the buffers of the state the last commit replaced (its x went on to the
        // predictor): a step allocates no state of its own. The literal below names
        // every field, so none keeps a value of that older state.
        let State {
            mut q,
            mut u,
            mut a,
            mut a_bar,
            mut lambda_n,
            mut lambda_n_bar,
            mut lambda_f,
            mut lambda_f_bar,
            mut p_n,
            mut p_f,
            ..
        } = std::mem::take(&mut self.work.spare_state);
        let it = &self.work.it;
        q.clone_from(&it.q1);
        u.clone_from(&it.u1);
        copy_into(&mut a, &x[o.a..o.a + o.nu]);
        a_bar.clone_from(&it.a_bar1);
        copy_into(&mut lambda_n, &x[o.ln..o.ln + o.nn]);
        lambda_n_bar.clone_from(&it.lbar_n1);
        copy_into(&mut lambda_f, &x[o.lf..o.lf + o.nf]);
        lambda_f_bar.clone_from(&it.lbar_f1);
        p_n.clone_from(&it.p_n);
        p_f.clone_from(&it.p_f);
        let state = State {
            k: self.state.k + 1,
            t: self.t_next(),
            q,
            u,
            a,
            a_bar,
            lambda_n,
            lambda_n_bar,
            lambda_f,
            lambda_f_bar,
            p_n,
            p_f,
            x,
        };
        let stats = StepStats {
            last_resort: None,
            t: state.t,
            iterations,
            residual,
            rho_inf,
            sets,
            retries: 0,
            converged,
            branch: None,
            solver: self.work.solver.name().to_owned(),
            substeps: 1,
            unshifted: false,
        };
        Trial {
            state,
            stats,
            visited,
            cycling,
        }
    }
}

/// Largest Newton update, relative to 1 + ‖x‖∞, that a factorization may give before its
/// matrix counts as singular up to round-off (docs/method.md §8.1, "Wild updates are
/// singular matrices"): such an update is round-off amplified by a tiny pivot that
/// passed the relative pivot test, not a Newton step. On a collapsing 20-block column
/// one came out at 2.7·10¹⁶ from a residual of 0.62; legitimate updates of the block
/// stack are many orders below the bound.
pub const WILD_UPDATE: f64 = 1e8;

/// An error when the update `dx` at `x` is larger than [`WILD_UPDATE`] (1 + ‖x‖∞): the
/// matrix is then treated as singular (the regularized linearization takes over), and
/// an update from kept factors is not taken.
fn numerically_regular(x: &[f64], dx: &[f64]) -> Result<(), crate::linalg::LinalgError> {
    let (size, scale) = (max_norm(dx), 1.0 + max_norm(x));
    if size <= WILD_UPDATE * scale {
        Ok(())
    } else {
        Err(crate::linalg::LinalgError(format!(
            "numerically singular matrix: an update of {size:.1e} at unknowns of {scale:.1e}"
        )))
    }
}

/// Numbers the unknowns `map` keeps (those not `usize::MAX`) 0, 1, … in order, making it
/// a prune map; returns how many it keeps, the reduced size.
fn number_kept(map: &mut [usize]) -> usize {
    let mut n_red = 0;
    for m in map.iter_mut().filter(|m| **m != usize::MAX) {
        *m = n_red;
        n_red += 1;
    }
    n_red
}

/// Whether the prune map `kept` (None: nothing pruned) keeps every unknown that `now`
/// keeps, so that factors made with `kept` hold all of `now`'s unknowns.
fn keeps_all_of(kept: Option<&Vec<usize>>, now: Option<&[usize]>) -> bool {
    match (kept, now) {
        (None, _) => true,
        (Some(kept), None) => kept.iter().all(|&m| m != usize::MAX),
        (Some(kept), Some(now)) => kept
            .iter()
            .zip(now)
            .all(|(&k, &n)| n == usize::MAX || k != usize::MAX),
    }
}

/// `to` becomes a copy of `from`, in `to`'s buffer.
fn copy_into(to: &mut Vec<f64>, from: &[f64]) {
    to.clear();
    to.extend_from_slice(from);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::systems::chain::Chain;
    use crate::Options;

    /// Kept factors made with a contact in the linear solve serve an attempt that
    /// prunes it (open, force-free, at the same sets): the contact's rows are those of an
    /// open contact with a zero residual, so the update is the exact update of the
    /// pruned system, with zeros for the pruned unknowns.
    #[test]
    fn kept_factors_serve_an_attempt_that_prunes_more_contacts() {
        let chain = Chain::benchmark(4);
        // The top block 5 cm above the next: its contact open and force-free.
        let (mut q0, u0) = chain.resting(0.0);
        q0[7] += 0.05;
        let options = Options {
            dt: 1e-3,
            reuse_factorization: true,
            ..Options::default()
        };
        let mut s = Stepper::new(chain, 0.0, &q0, &u0, options).unwrap();
        let p = GenAlpha::new(0.5);
        // Its unknowns are zero, as the pruning leaves them.
        let o = s.off;
        let top = o.nn - 1;
        let (f0, nc) = (s.law_off[top], s.layout.friction[top].components);
        let x = s.state().x.clone();
        let pruned: Vec<usize> = [o.kn + top, o.cn + top, o.ln + top]
            .into_iter()
            .chain((f0..f0 + nc).flat_map(|c| [o.cf + c, o.lf + c]))
            .collect();
        assert!(pruned.iter().all(|&i| x[i] == 0.0));
        let sets = s.sets_of(&x, 0.5);
        assert!(!sets.a[top] && sets.a[..top].iter().all(|&a| a));
        let mut map = vec![0; o.n];
        for &i in &pruned {
            map[i] = usize::MAX;
        }
        let n_red = number_kept(&mut map);
        let prune = (map, n_red);
        // Factors of the whole system at x.
        s.residual(&x, &sets, &p);
        let mut whole = vec![0.0; o.n];
        s.exact_direction(&x, &sets, &p, None, &mut whole).unwrap();
        let mut kept = vec![0.0; o.n];
        assert!(s.kept_direction(&x, &sets, &p, Some(&prune), &mut kept));
        assert!(pruned.iter().all(|&i| kept[i] == 0.0));
        let mut exact = vec![0.0; o.n];
        s.exact_direction(&x, &sets, &p, Some(&prune), &mut exact)
            .unwrap();
        let size = max_norm(&exact);
        let difference: Vec<f64> = exact.iter().zip(&kept).map(|(a, b)| a - b).collect();
        let diff = max_norm(&difference);
        assert!(size > 0.0 && diff <= 1e-12 * size, "{diff} against {size}");
        // The other way round (factors of the pruned system, the whole one asked for)
        // they cannot serve: they lack the contact's unknowns.
        assert!(!s.kept_direction(&x, &sets, &p, None, &mut kept));
    }
}
