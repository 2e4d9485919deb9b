//! The Newton matrix by forward differences of the residual, as the thesis's code forms
//! it (§4.2: "the finite difference parameter ε = 1e-6"), for
//! [`JacobianChoice::FiniteDifference`](crate::JacobianChoice::FiniteDifference).
//!
//! Column i of the matrix is (R(x + ε T eᵢ) − R(x))/ε with the index sets held, in the
//! unknowns z the exact matrix is assembled in ([`KinematicColumns`]): the linear solve
//! and the change back to x are then those of the exact update. ε is absolute, as in the
//! thesis's code. Each column costs one evaluation of the system, so a matrix costs as
//! many evaluations as there are unknowns: this is for reproducing the thesis, where
//! the exact matrix and the one differenced here differ by O(ε) (a test checks it on a
//! blocks step), not for speed. A singular differenced matrix is regularized on the
//! rows the exact matrix marks ([`LinearOptions::regularization`]): rollstack's corner
//! contacts can close redundantly where the thesis's two gaps per interface cannot; with
//! a regularization of 0 a singular matrix fails the attempt and the ρ∞ retries take it
//! up, as in the thesis's code.
//!
//! [`LinearOptions::regularization`]: crate::LinearOptions::regularization

use super::assemble::EpsScale;
use super::kinematic::KinematicColumns;
use super::scheme::Scheme;
use super::Stepper;
use crate::sets::IndexSets;
use crate::system::System;

impl<S: System> Stepper<S> {
    /// Replaces the exact matrix in `work.jac` by the forward-difference matrix at `x`
    /// for the fixed `sets` (step `eps` in each unknown z), keeping the regularization
    /// entries the exact one marked, and leaves the iterate buffers and `work.res` as the
    /// evaluation at `x` left them.
    pub(super) fn finite_difference_jacobian(
        &mut self,
        x: &[f64],
        sets: &IndexSets,
        p: &Scheme,
        eps: f64,
    ) {
        let o = self.off;
        let w = &self.work;
        let marked: Vec<(usize, EpsScale)> = w
            .regularized
            .iter()
            .zip(&w.regularization_scale)
            .map(|(&at, &scale)| (w.jac[at].0, scale))
            .collect();
        let columns = KinematicColumns::new(self.options.dt, &p.alpha);
        self.residual_at(x, sets, p);
        let at_x = self.work.res.clone();
        let mut jac = std::mem::take(&mut self.work.jac);
        jac.clear();
        let mut moved = x.to_vec();
        let mut step = vec![0.0; o.n];
        for i in 0..o.n {
            // x + ε T eᵢ: a unit step in z is a step in x along T's column i.
            step.fill(0.0);
            step[i] = eps;
            columns.to_unknowns(&o, &mut step);
            for ((m, xi), s) in moved.iter_mut().zip(x).zip(&step) {
                *m = xi + s;
            }
            self.residual_at(&moved, sets, p);
            for (row, (plus, base)) in self.work.res.iter().zip(&at_x).enumerate() {
                let entry = (plus - base) / eps;
                if entry != 0.0 {
                    jac.push((row, i, entry));
                }
            }
        }
        // The caller reads the iterate's buffers and residual after the matrix.
        self.residual_at(x, sets, p);
        let w = &mut self.work;
        w.regularized.clear();
        w.regularization_scale.clear();
        for (row, scale) in marked {
            w.regularized.push(jac.len());
            w.regularization_scale.push(scale);
            jac.push((row, row, 0.0));
        }
        w.jac = jac;
    }

    /// R(x) for the fixed `sets` into `work.res`, the prox parameters kept.
    fn residual_at(&mut self, x: &[f64], sets: &IndexSets, p: &Scheme) {
        self.derive(x, p);
        self.evaluate_iterate(x, false);
        self.residual(x, sets, p);
    }
}
