//! The contact states a flip probe tries ([`PolicyOptions::probe_flips`]), and how each is
//! solved (docs/exploration.md, "The flip probe").
//!
//! A step whose contacts sit at a transition (Painlevé's corner, App. I: sliding with
//! B < 0 and A > 0) can have several solutions, and Newton converges to one of them at
//! once. With at most [`MAX_ENUMERATED`] touching normal contacts, every combination of
//! their states is tried: each contact open or closed (on every level), each friction law
//! one of them bounds sliding or sticking (App. H): at most 2ᵏ · 2ᵏ = 4ᵏ ≤ 64 sets. With
//! more, each contact is flipped alone ([`flipped_sets`]), as the probe did before.
//!
//! A fixed-set solve may miss the solution of its sets, or find it with sets that differ
//! on one level only; two repairs, each one more solve at most:
//! - a closed contact pulling (a negative normal multiplier) carries no friction, so the
//!   sets' equations have a second root, pushing, with friction on (Painlevé's sliding
//!   contact, n = −A/B, where the pulling root is n = −A/B₀ with B₀ the frictionless B):
//!   the solve is restarted from the unknowns with those multipliers' signs reversed;
//! - a solution whose recomputed sets differ from the fixed ones (a jam whose contact is
//!   closed on velocity level but not on acceleration level) seeds a free Newton attempt
//!   ([`Stepper::quick_check`]), kept when it converges.
//!
//! [`PolicyOptions::probe_flips`]: crate::PolicyOptions::probe_flips

use super::branch::flipped_sets;
use super::spec::{AttemptSpec, SetRule, StartAt};
use super::Stepper;
use crate::attempt::{AttemptOutcome, Trial};
use crate::sets::IndexSets;
use crate::system::{FrictionLaw, System};

/// The most touching normal contacts whose states are enumerated (4³ = 64 sets at most).
///
/// Why 3, an argument (the probe is off in every reference workload, so the harness
/// cannot measure it): Painlevé's corner (App. I) is one contact, 4 states; a block
/// that also touches a neighbour or the floor with one more corner is two or three.
/// Each state is one fixed-set solve, so the probe's cost grows as 4^k: at 3, 64 solves
/// at most per probed step; beyond it each contact is flipped alone (4k solves).
pub const MAX_ENUMERATED: usize = 3;

/// The sets a flip probe of a step solved with `sets` tries, `sets` itself left out: every
/// combination of states of the `touching` contacts when there are at most
/// [`MAX_ENUMERATED`], else each contact flipped alone.
pub(super) fn probe_sets(
    sets: &IndexSets,
    touching: &[usize],
    laws: &[FrictionLaw],
) -> Vec<IndexSets> {
    if touching.len() > MAX_ENUMERATED {
        return flipped_sets(sets, touching, laws);
    }
    let mut out = Vec::new();
    for closed in 0..1_usize << touching.len() {
        let mut s = sets.clone();
        for (i, &k) in touching.iter().enumerate() {
            let on = closed >> i & 1 == 1;
            (s.a[k], s.b[k], s.c[k]) = (on, on, on);
        }
        // The friction laws a closed touching contact bounds: slide or stick each.
        let bound: Vec<usize> = (0..laws.len())
            .filter(|&j| {
                laws[j]
                    .normals
                    .iter()
                    .any(|k| touching.contains(k) && s.a[*k])
            })
            .collect();
        for stick in 0..1_usize << bound.len() {
            let mut f = s.clone();
            for (i, &j) in bound.iter().enumerate() {
                let on = stick >> i & 1 == 1;
                (f.d[j], f.e[j]) = (on, on);
            }
            if &f != sets && !out.contains(&f) {
                out.push(f);
            }
        }
    }
    out
}

impl<S: System> Stepper<S> {
    /// A solution of the step found from the fixed sets `sets` (see the module docs), with
    /// the sets it satisfies; None when none is found.
    pub(super) fn probe_solution(&mut self, sets: &IndexSets, rho0: f64) -> Option<Trial> {
        let fixed = self
            .attempt(self.retry_spec(SetRule::Fixed(sets.clone()), rho0))
            .ok()?;
        if &self.sets_of(&fixed.state.x, rho0) == sets {
            return Some(fixed);
        }
        if let Some(pushing) = self.pushing_start(&fixed.state.x, sets) {
            let again = AttemptSpec {
                start: StartAt::Unknowns(pushing),
                ..self.retry_spec(SetRule::Fixed(sets.clone()), rho0)
            };
            if let Ok(t) = self.attempt(again) {
                if &self.sets_of(&t.state.x, rho0) == sets {
                    return Some(t);
                }
            }
        }
        self.quick_check(fixed.state.x, rho0).ok()
    }

    /// Does a free Newton attempt started from the unknowns `x` of a fixed-set solution
    /// converge within [`Tuning::quick_check_iterations`](crate::Tuning::quick_check_iterations) updates (or a free attempt's budget of
    /// [`NewtonOptions::max_iter_per_contact`](crate::NewtonOptions::max_iter_per_contact), when that
    /// is larger)? The time grid is counted from the step's start from then on, and what
    /// the last solutions left for the next steps is forgotten, as after any restart
    /// from a state ([`Stepper::set_state`]).
    pub(super) fn quick_check(&mut self, x: Vec<f64>, rho: f64) -> AttemptOutcome {
        self.time_base = (self.state.t, self.state.k);
        self.forget_solutions();
        let check = AttemptSpec {
            start: StartAt::Unknowns(x),
            budget: self.free_budget_over(self.options.tuning.quick_check_iterations),
            ..self.spec(SetRule::Free, rho)
        };
        let free = self.attempt(check);
        self.forget_solutions();
        free
    }

    /// The unknowns `x` with the normal multipliers (κ_N, Λ_N, λ_N) of the contacts closed
    /// in `sets` made non-negative; None when none was negative.
    fn pushing_start(&self, x: &[f64], sets: &IndexSets) -> Option<Vec<f64>> {
        let mut y = x.to_vec();
        let mut changed = false;
        for k in (0..self.off.nn).filter(|&k| sets.a[k]) {
            for i in [self.off.kn + k, self.off.cn + k, self.off.ln + k] {
                if y[i] < 0.0 {
                    y[i] = -y[i];
                    changed = true;
                }
            }
        }
        changed.then_some(y)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn law(normals: Vec<usize>) -> FrictionLaw {
        FrictionLaw {
            components: 1,
            mu: 1.0,
            e_f: 0.0,
            normals,
        }
    }

    #[test]
    fn one_touching_corner_gives_open_slide_and_stick() {
        let sets = IndexSets::empty(2, 1);
        let laws = [law(vec![0, 1])];
        let tried = probe_sets(&sets, &[0], &laws);
        // Open is the converged sets themselves: closed sliding and closed sticking remain.
        assert_eq!(tried.len(), 2);
        assert!(tried.iter().all(|s| s.a[0] && s.b[0] && s.c[0] && !s.a[1]));
        assert!(tried.iter().any(|s| !s.d[0]) && tried.iter().any(|s| s.d[0] && s.e[0]));
    }

    #[test]
    fn the_enumeration_is_bounded_by_four_to_the_touching_contacts() {
        let sets = IndexSets::empty(3, 3);
        let laws = [law(vec![0]), law(vec![1]), law(vec![2])];
        // Each contact open, closed sliding or closed sticking: 3³ sets, the open one
        // (the converged sets) left out; 4³ bounds every layout of laws.
        assert_eq!(probe_sets(&sets, &[0, 1, 2], &laws).len(), 3 * 3 * 3 - 1);
        // Beyond the bound, one flip per contact.
        let sets = IndexSets::empty(4, 4);
        let laws = [law(vec![0]), law(vec![1]), law(vec![2]), law(vec![3])];
        assert!(probe_sets(&sets, &[0, 1, 2, 3], &laws).len() <= 4 * 3);
    }
}
