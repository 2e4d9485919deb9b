//! One Newton attempt at the step (eq. 143) on the crate's [`crate::newton`]
//! engine: the step as a [`NewtonProblem`] (docs/method.md §4), with open contacts pruned
//! from its linear solve ([`super::prune`]) and its updates from [`super::direction`].

use super::direction::Refusal;
use super::held::HeldSets;
use super::kinematic::KinematicColumns;
use super::prune::Pruning;
use super::scheme::Scheme;
use super::spec::AttemptSpec;
use super::Stepper;
use crate::attempt::{AttemptFailure, AttemptOutcome, RefusedBecause};
use crate::newton::{self, GiveUp, KeptUpdate, NewtonProblem, NewtonSettings, Outcome};
use crate::sets::IndexSets;
use crate::system::System;
use crate::tuning::Tuning;
use nalgebra::DMatrix;
use std::time::Instant;

/// The step seen by the Newton engine: the stepper at one ρ∞, with fixed index sets or
/// not, and the contacts pruned from this attempt.
struct StepProblem<'a, S: System> {
    stepper: &'a mut Stepper<S>,
    fixed: Option<&'a IndexSets>,
    params: Scheme,
    prune: Option<&'a Pruning>,
    /// The pruned contacts that closed at the iterate that asked for a restart.
    closing: Vec<bool>,
    /// The progress of a held-sets attempt ([`SetRule::Held`](super::spec::SetRule)).
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

/// How one run of the Newton engine within an attempt ended. One per run, moved once:
/// boxing the outcome would only add an allocation.
#[allow(clippy::large_enum_variant)]
enum Run {
    /// The attempt's outcome.
    Ended(AttemptOutcome),
    /// The pruned contacts flagged in `work.closing` closed: the attempt goes on
    /// `from` there.
    Restart { from: Resumed },
}

impl<S: System> NewtonProblem for StepProblem<'_, S> {
    type Sets = IndexSets;

    fn interrupted(&self) -> bool {
        self.stepper.interrupt.requested()
    }

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
    ///
    /// So does an island held at rest whose rows exceed the tolerance: it returns to the
    /// solve ([`Stepper::held_row_broken`]).
    fn restart(&mut self, sets: &IndexSets) -> bool {
        let Some((map, _)) = self.prune else {
            return false;
        };
        let st = &mut *self.stepper;
        let o = st.off;
        self.closing.clear();
        self.closing.extend(
            (0..o.nn)
                .map(|k| map[o.kn + k] == usize::MAX && sets.a[k] && !st.islands.holds_contact(k)),
        );
        st.held_row_broken(sets) | self.closing.iter().any(|&c| c)
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

    fn visited_list(&mut self) -> Vec<IndexSets> {
        let mut list = std::mem::take(&mut self.stepper.work.spare_visited);
        list.clear();
        list
    }

    fn copy_sets(&mut self, sets: &IndexSets) -> IndexSets {
        self.stepper.copy_sets(sets)
    }

    fn kept_direction(&mut self, x: &[f64], sets: &IndexSets, dx: &mut [f64]) -> KeptUpdate {
        let started = Instant::now();
        let kept = self
            .stepper
            .kept_direction(x, sets, &self.params, self.prune, dx);
        // Factors made before an island was held solve for its unknowns too: it stays
        // where it rests.
        for &i in self.stepper.islands.held() {
            dx[i] = 0.0;
        }
        self.stepper.newton_work.seconds.simplified += started.elapsed().as_secs_f64();
        if let (true, Some(held)) = (kept != KeptUpdate::Refused, &mut self.held) {
            held.updated(sets);
        }
        kept
    }
}

impl<S: System> Stepper<S> {
    /// One Newton attempt at the step as `spec` describes it (docs/method.md §4). Open
    /// contacts are pruned from its linear solve when
    /// [`NewtonOptions::prune_open_contacts`](crate::NewtonOptions::prune_open_contacts) asks for it
    /// (with fixed sets, only those the sets leave open); a pruned contact that closes
    /// restarts the run from its iterate with that contact kept ([`Resumed`]).
    pub(super) fn attempt(&mut self, mut spec: AttemptSpec) -> AttemptOutcome {
        // The iterates and the contacts kept from pruning in buffers that outlive the
        // attempt: the start's own unknowns (a prediction) or the predictor's spare
        // ones, and the work's flags.
        let mut x = spec.take_start(&self.state, || self.predictor.buffer());
        let spec = &spec;
        let fixed = spec.sets.fixed();
        let mut keep = std::mem::take(&mut self.work.keep);
        keep.clear();
        keep.extend((0..self.off.nn).map(|k| fixed.is_some_and(|f| f.a[k])));
        // A restart comes only from a pruned contact, so only with pruning.
        let pruning = self.options.newton.prune_open_contacts;
        let mut resumed = None;
        let outcome = loop {
            match self.newton_run(spec, &mut x, pruning.then_some(&keep[..]), resumed) {
                Run::Ended(outcome) => break outcome,
                Run::Restart { from } => {
                    // The iterate is the one the unpruned attempt would have reached (a
                    // pruned contact's unknowns stay zero while it is open): go on from
                    // it with the closing contacts kept, within what is left of the budget.
                    for (kk, c) in keep.iter_mut().zip(&self.work.closing) {
                        *kk |= c;
                    }
                    resumed = Some(from);
                }
            }
        };
        self.work.keep = keep;
        // A converged attempt's x went into its trial; a failed one's is free again.
        self.predictor.give_back(x);
        outcome
    }

    /// Whether an attempt with `scheme` takes the updates of
    /// [`LinearOptions::low_rank_updates`](crate::LinearOptions::low_rank_updates): a step's first
    /// attempt, when they are asked for.
    pub(super) fn quick_updates(&self, scheme: &Scheme) -> bool {
        self.options.linear.low_rank_updates && scheme.quick_updates
    }

    /// One run of the Newton engine for the attempt `spec` from the iterate `x`, with
    /// `keep` the contacts that may not be pruned (None: no pruning); `resumed` says how
    /// far the attempt went before, when the run continues it.
    fn newton_run(
        &mut self,
        spec: &AttemptSpec,
        x: &mut Vec<f64>,
        keep: Option<&[bool]>,
        resumed: Option<Resumed>,
    ) -> Run {
        let fixed = spec.sets.fixed();
        let prune = keep.and_then(|k| self.open_contacts(x, k));
        self.mark_unused(prune.as_ref().map(|(map, _)| map.as_slice()));
        let scheme = spec.scheme();
        let updates_before = resumed.as_ref().map_or(0, |r| r.updates);
        let settings = NewtonSettings {
            tol: self.options.tol,
            max_iter: spec.budget.saturating_sub(updates_before),
            line_search: spec.line_search,
            reuse_factorization: self.options.linear.reuse_factorization,
            resume_reuse: self.quick_updates(&scheme),
            new_factors: spec.new_factors,
            give_up: if fixed.is_some() {
                GiveUp::Stall
            } else {
                GiveUp::SettledCycle
            },
            follow_sets: spec.kept.follow_sets,
            contracting_extra: spec.contracting_extra,
            start_limit: spec.start_limit,
            tuning: Tuning {
                reuse_contraction: spec.kept.contraction,
                ..self.options.tuning
            },
        };
        self.prepare_step();
        let mut scratch = std::mem::take(&mut self.work.newton);
        let closing = std::mem::take(&mut self.work.closing);
        let (held, resuming) = match resumed {
            Some(r) => (r.held, true),
            None => (spec.sets.held_start(), false),
        };
        let mut problem = StepProblem {
            stepper: self,
            fixed,
            params: scheme,
            prune: prune.as_ref(),
            closing,
            held,
            resuming,
        };
        let outcome = newton::solve(&mut problem, x, &settings, &mut scratch);
        let held = problem.held;
        self.work.closing = problem.closing;
        self.give_back_pruning(prune);
        self.newton_work.line_search_trials += scratch.line_search_trials();
        // Updates this run made: one fewer than its evaluations.
        let updates = updates_before + scratch.evaluations().saturating_sub(1);
        self.work.newton = scratch;
        Run::Ended(match outcome {
            Outcome::Restart => {
                let from = Resumed { updates, held };
                return Run::Restart { from };
            }
            Outcome::Converged {
                sets,
                iterations,
                residual,
                visited,
            } => {
                let converged = (sets, updates_before + iterations, residual);
                self.converged(x, converged, visited, spec.rho_inf)
            }
            Outcome::NonFinite => Err(AttemptFailure::NonFinite),
            Outcome::Interrupted => Err(AttemptFailure::Interrupted),
            Outcome::Singular(message) => Err(AttemptFailure::Singular { message }),
            Outcome::NotConverged {
                visited,
                cycling,
                best,
            } => {
                let best = best.map(|b| {
                    // Re-derive the best iterate's state.
                    self.derive(&b.x, &scheme);
                    let at = (b.sets, b.iteration, b.residual);
                    Box::new(self.make_trial(b.x, at, spec.rho_inf, false, Vec::new(), cycling))
                });
                Err(AttemptFailure::NotConverged {
                    visited,
                    cycling,
                    best,
                })
            }
        })
    }

    /// The outcome of a run that converged at `x` with (sets, updates, residual): the
    /// step, or refused when it is a far solution ([`Stepper::is_far`]).
    fn converged(
        &mut self,
        x: &mut Vec<f64>,
        (sets, iterations, residual): (IndexSets, usize, f64),
        mut visited: Vec<IndexSets>,
        rho_inf: f64,
    ) -> AttemptOutcome {
        if self.is_far(x) {
            // Refused as an attempt without a solution, not as a cycling one: the
            // fixed-set re-solves of the sets it wandered through cost more than the
            // policy's later stages, which found the near solution (docs/method.md §8.1).
            self.newton_work.far_solutions += 1;
            if !visited.contains(&sets) {
                visited.push(sets);
            }
            return Err(AttemptFailure::Refused {
                reason: RefusedBecause::FarSolution,
                visited,
            });
        }
        let at = (sets, iterations, residual);
        Ok(self.make_trial(std::mem::take(x), at, rho_inf, true, visited, false))
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
        p: &Scheme,
        update_prox: bool,
        limit: Option<(&IndexSets, usize)>,
    ) -> (IndexSets, f64) {
        self.derive(x, p);
        self.evaluate_iterate(x, update_prox);
        let sets = match fixed {
            Some(s) => self.copy_sets(s),
            None => self.compute_sets(x, None, update_prox),
        };
        self.residual(x, &sets, p);
        let res = self.residual_norm(&sets);
        if let Some(limit) = limit.filter(|_| fixed.is_none() && res > self.options.tol) {
            let limited = self.compute_sets(x, Some(limit), update_prox);
            if limited != sets {
                self.residual(x, &limited, p);
                self.recycle_sets(sets);
                return (limited, res);
            }
            self.recycle_sets(limited);
        }
        (sets, res)
    }

    /// The index sets the contact laws give at unknowns `x` (no Newton update).
    pub fn sets_of(&mut self, x: &[f64], rho_inf: f64) -> IndexSets {
        let p = self.scheme(rho_inf);
        self.prepare_step();
        self.derive(x, &p);
        self.evaluate_iterate(x, true);
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
        let p = self.scheme(rho_inf);
        // The derivative rows are replaced: the kept factors no longer fit them.
        self.work.factored = None;
        self.prepare_step();
        self.derive(x, &p);
        self.evaluate_iterate(x, update_prox);
        self.residual(x, sets, &p);
        // The full matrix: nothing pruned.
        self.mark_unused(None);
        self.jacobian(x, sets, &p);
        let n = self.off.n;
        let mut j = DMatrix::zeros(n, n);
        for &(r, c, v) in &self.work.jac {
            j[(r, c)] += v;
        }
        KinematicColumns::new(self.options.dt, &p.alpha).to_unknown_columns(&self.off, &mut j);
        (self.work.res.clone(), j)
    }
}

#[cfg(test)]
mod tests {
    use crate::systems::chain::Chain;
    use crate::{Options, Stepper};

    /// An iterate evaluated with fixed sets or with a limit on openings hands back the
    /// sets it does not return, and copies fixed sets into spent ones.
    #[test]
    fn an_evaluation_takes_and_gives_back_spent_sets() {
        let chain = Chain::benchmark(4);
        let (q0, u0) = chain.resting(0.0);
        let mut s = Stepper::new(chain, 0.0, &q0, &u0, Options::default()).unwrap();
        let p = s.scheme(0.5);
        let x = s.state().x.clone();
        let sets = s.sets_of(&x, 0.5);
        s.work.spare_sets.clear();
        s.recycle_sets(sets.clone());
        let spare = s.work.spare_sets[0].a.as_ptr();
        let (fixed, _) = s.evaluate_at(&x, Some(&sets), &p, false, None);
        assert_eq!((&fixed, fixed.a.as_ptr()), (&sets, spare));
        assert!(s.work.spare_sets.is_empty());
        // Away from the solution, with a limit on openings: the laws' sets or the limited
        // ones, whichever are not returned, go back.
        let mut off = x.clone();
        off[s.off.a] += 1.0;
        let (_, res) = s.evaluate_at(&off, None, &p, false, Some((&sets, 0)));
        assert!(res > s.options.tol);
        assert_eq!(s.work.spare_sets.len(), 1);
    }
}
