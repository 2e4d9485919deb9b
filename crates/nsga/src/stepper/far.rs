//! Far solutions: a converged step whose position correction Q (eq. 125) moves the
//! bodies much farther than their motion over the step could (docs/method.md §8.1,
//! "Far solutions").
//!
//! The position correction exists to take out what the smooth prediction of q_{n+1}
//! overshoots: a contact arriving at speed v goes at most about vΔt into its surface,
//! and the friction percussions' half-step shift moves a body by ½Δt times the velocity
//! jump. So Q is of the size of what velocities and accelerations cover in one step.
//! The gap functions of the contact laws are, however, valid only near the step's
//! start: a corner is measured against the line of a face, whatever the rest of the
//! bodies do. Far from it the step's equations have other solutions, in which a block
//! turns by a large angle inside a column with no velocity to turn it; a Newton attempt
//! that wandered over many index sets can end on one.

use super::Stepper;
use crate::system::System;

impl<S: System> Stepper<S> {
    /// The size of the position correction Q of the evaluated iterate `x` relative to
    /// the motion of the step,
    ///
    /// ‖Q‖ / (Δt(‖u_n‖ + ‖u_{n+1}‖) + Δt²(‖ā_n‖ + ‖ā_{n+1}‖ + ‖M⁻¹h‖)),
    ///
    /// in the norm ‖v‖ = maxᵢ √Mᵢᵢ |vᵢ| of the mass diagonal, which weighs translations
    /// and rotations alike (units of √mass × length) and, unlike a sum over the bodies,
    /// does not grow with their number. The free acceleration M⁻¹h (Mᵢᵢ⁻¹hᵢ) keeps the
    /// scale of a body at rest under gravity, whose correction only takes out drift.
    /// It reads M and h at q_{n+1} from the last evaluation, which must be that of `x`.
    pub(super) fn correction_ratio(&mut self, x: &[f64]) -> f64 {
        let o = self.off;
        let dt = self.options.dt;
        let w = &mut self.work;
        let root_mass = &mut w.root_mass_diagonal;
        root_mass.clear();
        root_mass.resize(o.nu, 0.0);
        for &(r, c, v) in &w.eval.mass.entries {
            if r == c {
                root_mass[r] += v;
            }
        }
        root_mass.iter_mut().for_each(|m| *m = m.max(0.0).sqrt());
        let norm = |v: &[f64]| {
            v.iter()
                .zip(root_mass.iter())
                .fold(0.0_f64, |most, (vi, m)| most.max(m * vi.abs()))
        };
        let free_acceleration = w
            .eval
            .forces
            .iter()
            .zip(root_mass.iter())
            .filter(|(_, &m)| m > 0.0)
            .fold(0.0_f64, |most, (h, m)| most.max(h.abs() / m));
        let (st, it) = (&self.state, &w.it);
        let motion = dt * (norm(&st.u) + norm(&it.u1))
            + dt * dt * (norm(&st.a_bar) + norm(&it.a_bar1) + free_acceleration);
        let correction = norm(&x[o.qq..o.qq + o.nu]);
        if correction == 0.0 {
            0.0
        } else {
            correction / motion
        }
    }

    /// Whether the evaluated iterate `x` is a far solution: its position correction is
    /// more than [`Tuning::far_correction`](crate::Tuning::far_correction) times the step's motion.
    pub(super) fn is_far(&mut self, x: &[f64]) -> bool {
        self.correction_ratio(x) > self.options.tuning.far_correction
    }
}
