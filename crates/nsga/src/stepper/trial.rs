//! The uncommitted step a Newton attempt ends on: its state at t_{n+1}, written into the
//! buffers of the state the last commit replaced, and its statistics.

use super::Stepper;
use crate::attempt::Trial;
use crate::report::StepStats;
use crate::sets::IndexSets;
use crate::state::State;
use crate::system::System;

impl<S: System> Stepper<S> {
    /// The step an attempt at ρ∞ = `rho_inf` ended on at the evaluated unknowns `x`,
    /// with its (sets, updates, residual): converged, or its best iterate (`cycling`:
    /// whether its sets cycled).
    #[allow(clippy::fn_params_excessive_bools)]
    pub(super) fn make_trial(
        &mut self,
        x: Vec<f64>,
        (sets, iterations, residual): (IndexSets, usize, f64),
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
        let mut solver = std::mem::take(&mut self.work.spare_solver_name);
        solver.clear();
        solver.push_str(self.work.solver.name());
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
            solver,
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

/// `to` becomes a copy of `from`, in `to`'s buffer.
fn copy_into(to: &mut Vec<f64>, from: &[f64]) {
    to.clear();
    to.extend_from_slice(from);
}
