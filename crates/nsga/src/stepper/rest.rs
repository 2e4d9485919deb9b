//! A state at rest held without solving (docs/method.md §8.2, "At rest").
//!
//! A system whose equations no longer depend on time ([`System::autonomous_from`]) and
//! whose bodies have come to rest still has velocities and accelerations of round-off
//! size: the step's equations are solved to the tolerance, not to zero, and what is
//! left integrates into a drift of the positions (10⁻¹² in a thousand seconds of a
//! pile). Two steps find the rest:
//!
//! 1. **Settling.** A step that converged at its start without a Newton update, kept its
//!    index sets, moved no coordinate by more than the resolution of the largest
//!    (ε max_j |q_j|), and left velocities and accelerations that weigh less than the
//!    tolerance in the step's rows (|Mᵢᵢ uᵢ| and Δt |Mᵢᵢ aᵢ| at most the tolerance, the
//!    units of the U and a rows of eq. 127) is set to rest exactly: u, a, ā and the
//!    impulsive unknowns U, Q, κ, Λ of its solution are zeroed, the smooth forces λ kept.
//! 2. **At rest.** If the next step, started from that solution, converges at its start
//!    without an update and keeps its sets, its equations hold at the rest to the
//!    tolerance and it commits the same state: q + Δt·0 = q, and every later step would
//!    be this one again. The stepper repeats the state one Δt later instead of solving,
//!    until the system stops being autonomous or the caller changes the state, the
//!    system or the options.
//!
//! A pile at rest then costs its record, not a residual per step. The settling changes
//! the state by less than the solver can tell from zero; a system that is still moving
//! fails the second step's test and goes on from the settled state as from any other.

use super::Stepper;
use crate::system::System;

/// How a step moved the coordinates q.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Moved {
    /// Not at all: q is the same to the bit.
    Not,
    /// By round-off: no coordinate by more than the resolution of the largest,
    /// ε max_j |q_j| (ε = `f64::EPSILON`).
    RoundOff,
    /// By more.
    Beyond,
}

impl Moved {
    pub(super) fn between(q0: &[f64], q1: &[f64]) -> Self {
        if q0 == q1 {
            return Self::Not;
        }
        let resolution = resolution(q1);
        if q0.iter().zip(q1).all(|(a, b)| (a - b).abs() <= resolution) {
            Self::RoundOff
        } else {
            Self::Beyond
        }
    }
}

/// The resolution of the coordinates q: ε max_j |q_j| (ε = `f64::EPSILON`), the most a
/// coordinate can move by round-off.
pub(super) fn resolution(q: &[f64]) -> f64 {
    f64::EPSILON * q.iter().fold(0.0, |m: f64, x| m.max(x.abs()))
}

/// Whether a velocity `u` and an acceleration `a` of a coordinate whose mass-matrix
/// diagonal entry is `m` weigh at most the tolerance `tol` in the U and a rows of the
/// step's residual (eq. 127: M U in impulse units, Δt M a).
pub(super) fn round_off_rates(m: f64, u: f64, a: f64, tol: f64, dt: f64) -> bool {
    m.abs() * u.abs() <= tol && dt * m.abs() * a.abs() <= tol
}

/// Where the stepper stands on the way to a state at rest (module docs).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(super) enum Rest {
    /// Steps are solved.
    #[default]
    Moving,
    /// The last step set its state to rest exactly; the next one tests it.
    Settling,
    /// The state is at rest for good: steps repeat it.
    Held,
}

impl<S: System> Stepper<S> {
    /// Whether the step just committed, from time `t0`, converged at its start without
    /// an update and kept its index sets, for a system autonomous from `t0` on.
    fn quiet_step(&self, t0: f64) -> bool {
        let Some(s) = self.last.as_ref() else {
            return false;
        };
        self.options.policy.rest
            && self.same_sets
            && s.iterations == 0
            && s.retries == 0
            && s.converged
            && s.substeps == 1
            && s.last_resort.is_none()
            && s.branch.is_none()
            && !s.unshifted
            && self.system.autonomous_from(t0)
    }

    /// Whether the state's velocities and accelerations weigh at most the tolerance in
    /// the U and a rows of the step's residual (eq. 127: M U in impulse units, Δt M a).
    fn round_off_motion(&self) -> bool {
        let (tol, dt, st) = (self.options.tol, self.options.dt, &self.state);
        self.work
            .eval
            .mass
            .entries
            .iter()
            .all(|&(i, j, m)| i != j || round_off_rates(m, st.u[i], st.a[i], tol, dt))
    }

    /// The stage on the way to rest after a step from time `t0`, taken at stage `before`
    /// (module docs); settles the state when it starts settling.
    pub(super) fn rest_after_step(&mut self, before: Rest, t0: f64) -> Rest {
        if !self.quiet_step(t0) {
            return Rest::Moving;
        }
        match (before, self.moved) {
            (Rest::Settling, Moved::Not) => Rest::Held,
            (_, Moved::Not | Moved::RoundOff) if self.round_off_motion() => {
                self.settle();
                Rest::Settling
            }
            _ => Rest::Moving,
        }
    }

    /// Sets the state to rest exactly: u, a, ā and the solution's impulsive unknowns
    /// zero, its smooth forces kept, and the next step started from that solution.
    fn settle(&mut self) {
        let o = self.off;
        let st = &mut self.state;
        for v in [&mut st.u, &mut st.a, &mut st.a_bar] {
            v.fill(0.0);
        }
        let forces = o.forces();
        for (i, x) in st.x.iter_mut().enumerate() {
            if !forces.iter().any(|r| r.contains(&i)) {
                *x = 0.0;
            }
        }
        self.predictor.clear();
        self.work.state_levels.forget();
    }

    /// The state at rest again, one Δt later, with the statistics of the step that
    /// found it.
    pub(super) fn rest_step(&mut self) {
        let t = self.t_next();
        self.state.k += 1;
        self.state.t = t;
        let mut stats = self
            .last
            .take()
            .expect("a state at rest was found by a step");
        stats.t = t;
        self.account(&stats);
        self.last = Some(stats);
        self.stats.resting_steps += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::Moved;

    /// A step moves q not at all, by round-off (no coordinate by more than ε times the
    /// largest), or by more; a coordinate at zero is measured on the largest's scale.
    #[test]
    fn a_step_moves_q_not_at_all_by_round_off_or_by_more() {
        let q = [2.0, 0.0, -0.5];
        assert_eq!(Moved::between(&q, &q), Moved::Not);
        let ulp = f64::EPSILON * 2.0;
        assert_eq!(Moved::between(&q, &[2.0, ulp, -0.5]), Moved::RoundOff);
        assert_eq!(Moved::between(&q, &[2.0 + ulp, 0.0, -0.5]), Moved::RoundOff);
        assert_eq!(Moved::between(&q, &[2.0, 3.0 * ulp, -0.5]), Moved::Beyond);
        assert_eq!(Moved::between(&q, &[2.0, 0.0, -0.5 + 1e-12]), Moved::Beyond);
    }
}
