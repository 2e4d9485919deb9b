//! The constraint levels at the current state, kept from the Newton iterate that became
//! it, so that the next step's pruning of open contacts need not evaluate the system
//! again (docs/method.md §7, "Pruned matrices").
//!
//! The converged iterate of a step is evaluated at (t_{n+1}, q_{n+1}, u_{n+1}) with the
//! accelerations a of its x: exactly the state the step commits. Its position levels p,
//! rates ṗ = W_pᵀu + χ_p and accelerations p̈ = W_pᵀa + ζ_p (the iterate's `p`,
//! `rate_new` and `acc_p`) are the numbers the pruning computed from a fresh evaluation
//! of the state, to the last bit. They serve only while nothing has changed the system
//! or the state since: [`Stepper::system_mut`](super::Stepper::system_mut), a replaced
//! state or a changed layout forget them.

use super::iterate::Iterate;
use crate::state::State;
use crate::system::Evaluation;

/// p, ṗ and p̈ of every position-level constraint at the state of step `k`, time `t` and
/// unknowns `x`, when `valid`.
#[derive(Debug, Clone, Default)]
pub(super) struct StateLevels {
    valid: bool,
    k: u64,
    t: f64,
    x: Vec<f64>,
    pub(super) position: Vec<f64>,
    pub(super) rate: Vec<f64>,
    pub(super) acceleration: Vec<f64>,
}

impl StateLevels {
    /// Copies the levels of an evaluated iterate whose state would be step `k` at time
    /// `t` with unknowns `x` (buffers reused from call to call).
    pub(super) fn record(&mut self, k: u64, t: f64, x: &[f64], it: &Iterate) {
        self.key(k, t, x);
        self.position.clone_from(&it.p);
        self.rate.clone_from(&it.rate_new);
        self.acceleration.clone_from(&it.acc_p);
    }

    /// Computes the levels of `state` from `e`, the system's evaluation there.
    pub(super) fn evaluate(&mut self, state: &State, e: &Evaluation<f64>) {
        self.key(state.k, state.t, &state.x);
        self.position.clone_from(&e.position);
        self.rate.clone_from(&e.position_chi);
        self.acceleration.clone_from(&e.position_zeta);
        // Each sum in the order of the iterate's (`Stepper::evaluate_iterate`), so that
        // both give the same bits.
        for &(r, c, v) in &e.position_w.entries {
            self.rate[c] += v * state.u[r];
            self.acceleration[c] += v * state.a[r];
        }
    }

    /// Marks the levels valid for the state of step `k`, time `t` and unknowns `x`.
    fn key(&mut self, k: u64, t: f64, x: &[f64]) {
        self.valid = true;
        self.k = k;
        self.t = t;
        self.x.clear();
        self.x.extend_from_slice(x);
    }

    /// Whether these are the levels of `state`.
    pub(super) fn describe(&self, state: &State) -> bool {
        self.valid && self.k == state.k && self.t == state.t && equal(&self.x, &state.x)
    }

    pub(super) fn forget(&mut self) {
        self.valid = false;
    }
}

/// `a == b`, without the early exit of the slices' `==`: it compares all entries in
/// pairs (it vectorizes) rather than one at a time (two such comparisons a step, in
/// the commit and in the pruning, cost 2 000 instructions of a six-block pile's).
fn equal(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).fold(true, |same, (x, y)| same & (x == y))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::system::System;
    use crate::systems::chain::Chain;
    use crate::{NewtonOptions, Options, Stepper};

    /// `equal` is the slices' `==`: −0 equals +0, NaN equals nothing.
    #[test]
    fn unknowns_compare_as_the_slices_do() {
        let cases: [(&[f64], &[f64]); 6] = [
            (&[1.0, -0.0, 3.0], &[1.0, 0.0, 3.0]),
            (&[1.0, 2.0], &[1.0, 2.0, 0.0]),
            (
                &[1.0, 2.0, 3.0, 4.0, 5.0],
                &[1.0, 2.0, 3.0, 4.0, 5.0f64.next_up()],
            ),
            (&[f64::NAN], &[f64::NAN]),
            (&[f64::INFINITY, 1.0], &[f64::INFINITY, 1.0]),
            (&[], &[]),
        ];
        for (a, b) in cases {
            assert_eq!(equal(a, b), a == b, "{a:?} {b:?}");
        }
    }

    /// The levels a step keeps are those a fresh evaluation of the committed state gives,
    /// to the bit; `system_mut` forgets them.
    #[test]
    fn kept_levels_equal_a_fresh_evaluation_of_the_state() {
        let chain = Chain::benchmark(4);
        // Open gaps that close as the blocks fall onto each other: pruned contacts, then
        // landings.
        let (q0, u0) = chain.spread(0.01, 0.3);
        let options = Options {
            newton: NewtonOptions {
                prune_open_contacts: true,
                ..NewtonOptions::default()
            },
            ..Options::default()
        };
        let mut s = Stepper::new(chain, 0.0, &q0, &u0, options).unwrap();
        let mut kept = 0;
        for _ in 0..200 {
            s.step().unwrap();
            if !s.work.state_levels.describe(&s.state) {
                continue;
            }
            kept += 1;
            let st = &s.state;
            let mut e = Evaluation::new(&s.layout);
            s.system.evaluate(st.t, &st.q, &st.u, &mut e);
            let mut fresh = StateLevels::default();
            fresh.evaluate(st, &e);
            let held = &s.work.state_levels;
            assert_eq!(held.position, fresh.position, "t = {}", st.t);
            assert_eq!(held.rate, fresh.rate, "t = {}", st.t);
            assert_eq!(held.acceleration, fresh.acceleration, "t = {}", st.t);
        }
        assert!(kept > 150, "levels kept after {kept} of 200 steps");
        s.system_mut();
        assert!(!s.work.state_levels.describe(&s.state));
    }
}
