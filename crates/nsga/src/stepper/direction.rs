//! The Newton update of an attempt (eq. 143): exact from a factored Jacobian, regularized
//! when it is singular (docs/method.md §7), or simplified from kept factors, whole or
//! with a low-rank update for changed index sets.

use super::kinematic::KinematicColumns;
use super::prune::{expand, keeps_all_of, restrict, Pruning};
use super::scheme::Scheme;
use super::{FactoredFor, Stepper};
use crate::linalg::{equilibrate_rows, max_norm};
use crate::newton::KeptUpdate;
use crate::sets::IndexSets;
use crate::system::System;
use std::time::Instant;

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

impl<S: System> Stepper<S> {
    /// The exact Newton update at `x` (eq. 143) into `dx`: assembles and factors the
    /// Jacobian, regularized ([`LinearOptions::regularization`](crate::LinearOptions::regularization))
    /// when it is singular.
    pub(super) fn exact_direction(
        &mut self,
        x: &[f64],
        sets: &IndexSets,
        p: &Scheme,
        prune: Option<&Pruning>,
        dx: &mut [f64],
    ) -> Result<(), crate::linalg::LinalgError> {
        let eps = self.options.linear.regularization;
        // The factors made below replace the kept ones (whose record lends its buffers to
        // theirs); a regularized matrix's serve the same sets only, and only in a step's
        // first attempt (docs/method.md §7).
        let spent = self.work.factored.take();
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
                    if self.options.linear.low_rank_updates {
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
                    self.record_factors(spent, sets, prune, p, false);
                    return Ok(());
                }
                Err(e) if eps <= 0.0 => return Err(e),
                Err(_) => {}
            }
        }
        // Redundant closed contacts: solve the regularized linearization.
        let known = &mut self.work.singular_sets;
        let kept = self.options.tuning.singular_sets_kept;
        if kept > 0 && !known.iter().any(redundant) {
            if known.len() >= kept {
                known.remove(0);
            }
            known.push(sets.clone());
        }
        self.regularize(eps);
        self.newton_direction(prune, Factor::Equilibrated, p, dx)?;
        if self.options.linear.reuse_factorization && p.quick_updates {
            self.record_factors(spent, sets, prune, p, true);
        }
        Ok(())
    }

    /// Keeps what the factors just made were assembled for (`work.factored`), written
    /// into the buffers of `spent`, the record of the factors they replaced.
    fn record_factors(
        &mut self,
        spent: Option<FactoredFor>,
        sets: &IndexSets,
        prune: Option<&Pruning>,
        p: &Scheme,
        regularized: bool,
    ) {
        let (mut kept_sets, mut kept_prune) =
            spent.map_or_else(Default::default, |f| (f.sets, f.prune));
        kept_sets.clone_from(sets);
        match (prune, &mut kept_prune) {
            (Some((map, n_red)), Some((kept_map, kept_n))) => {
                kept_map.clone_from(map);
                *kept_n = *n_red;
            }
            (prune, kept) => *kept = prune.cloned(),
        }
        self.work.factored = Some(FactoredFor {
            sets: kept_sets,
            prune: kept_prune,
            dt: self.options.dt,
            rho_inf: p.alpha.rho_inf,
            regularized,
        });
    }

    /// The simplified Newton update at `x` from the solver's kept factors into `dx`, when
    /// they were assembled for this prune map, Δt and ρ∞, and for these sets or (with
    /// [`Self::quick_updates`]) sets that differ in a few rows (the low-rank update of
    /// `low_rank`); false otherwise.
    pub(super) fn kept_direction(
        &mut self,
        x: &[f64],
        sets: &IndexSets,
        p: &Scheme,
        prune: Option<&Pruning>,
        dx: &mut [f64],
    ) -> KeptUpdate {
        let map = prune.map(|(map, _)| map);
        // A refused update is followed by an exact one, which counts why.
        self.refusal = None;
        let Some(kept) = self.work.factored.take() else {
            self.refusal = Some(Refusal::NoKeptFactors);
            return KeptUpdate::Refused;
        };
        let same_sets = &kept.sets == sets;
        let kept_map = kept.prune.as_ref().map(|(map, _)| map);
        let same_system = kept.dt == self.options.dt && kept.rho_inf == p.alpha.rho_inf;
        let fits = same_system
            && (kept_map == map || same_sets && keeps_all_of(kept_map, map.map(Vec::as_slice)));
        if !fits {
            self.work.factored = Some(kept);
            self.refusal = Some(Refusal::OtherSystem);
            return KeptUpdate::Refused;
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
                && self.quick_updates(p)
                && self.low_rank_direction(x, sets, p, prune, dx)
                && numerically_regular(x, dx).is_ok()
        };
        let work = &mut self.newton_work;
        match (taken, same_sets) {
            (false, _) => {
                self.refusal = Some(Refusal::SetsChanged);
                KeptUpdate::Refused
            }
            (true, true) => {
                work.kept_updates += 1;
                KeptUpdate::SameSets
            }
            (true, false) => {
                work.low_rank_updates += 1;
                KeptUpdate::ChangedRows
            }
        }
    }

    /// The Newton update dx = −J⁻¹R from the assembled Jacobian and residual, or with
    /// `again` from the solver's kept factors (a simplified Newton update), on the reduced
    /// system when open contacts are pruned (their updates are 0). The matrix is
    /// assembled in the unknowns z of [`KinematicColumns`]; dx = T dz.
    fn newton_direction(
        &mut self,
        prune: Option<&Pruning>,
        factor: Factor,
        p: &Scheme,
        dx: &mut [f64],
    ) -> Result<(), crate::linalg::LinalgError> {
        let out = self.newton_direction_in_z(prune, factor, dx);
        KinematicColumns::new(self.options.dt, &p.alpha).to_unknowns(&self.off, dx);
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

#[cfg(test)]
mod tests {
    use super::super::prune::number_kept;
    use super::*;
    use crate::systems::chain::Chain;
    use crate::{LinearOptions, Options};

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
            linear: LinearOptions {
                reuse_factorization: true,
                ..LinearOptions::default()
            },
            ..Options::default()
        };
        let mut s = Stepper::new(chain, 0.0, &q0, &u0, options).unwrap();
        let p = s.scheme(0.5);
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
        assert_eq!(
            s.kept_direction(&x, &sets, &p, Some(&prune), &mut kept),
            KeptUpdate::SameSets
        );
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
        assert_eq!(
            s.kept_direction(&x, &sets, &p, None, &mut kept),
            KeptUpdate::Refused
        );
        // New factors are recorded in the buffers of the record they replace (given
        // room to spare here, which a new buffer would not have).
        let room = 4 * o.n;
        let old = s.work.factored.as_mut().unwrap();
        old.sets.a.reserve(room);
        old.prune.as_mut().unwrap().0.reserve(room);
        s.exact_direction(&x, &sets, &p, Some(&prune), &mut exact)
            .unwrap();
        let new = s.work.factored.as_ref().unwrap();
        assert_eq!((&new.sets, &new.prune), (&sets, &Some(prune.clone())));
        assert!(new.sets.a.capacity() >= room);
        assert!(new.prune.as_ref().unwrap().0.capacity() >= room);
    }
}
