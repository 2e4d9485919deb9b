//! The last resort of a step that every other stage of its policy failed
//! (`Stage::LastResort`, docs/method.md §8.2): one Moreau–Jean step of the same system
//! whose contact problem Lemke's method solves, with every contact taking part and the
//! gaps projected back to zero after it ([`crate::lcp_step`]). The generalized-α state
//! then restarts from the consistent accelerations and forces at the new state, as at t0.

use super::Stepper;
use crate::error::StepError;
use crate::lcp_step::{lcp_step, Activation, LcpStepError};
use crate::report::{LastResort, StepStats};
use crate::sets::IndexSets;
use crate::start::{consistent_start, Start};
use crate::state::State;
use crate::system::System;

impl<S: System> Stepper<S> {
    /// Takes the step by the last resort and commits it.
    ///
    /// # Errors
    /// [`StepError::NoSolution`] when the step's contact problem has no solution (Lemke's
    /// method ends on a ray: a Painlevé-type inconsistency) or its result is not finite;
    /// [`StepError::InvalidInput`] for systems it does not cover (bilateral constraints,
    /// spatial friction laws). The stepper stays where it was.
    pub(super) fn last_resort(&mut self) -> Result<(), StepError> {
        let st = &self.state;
        let k = st.k + 1;
        let t1 = self.grid_time(k);
        let step = lcp_step(
            &self.system,
            &self.layout,
            (st.t, t1),
            (&st.q, &st.u),
            self.options.dt,
            Activation::GapAware,
            true,
        )
        .map_err(|e| match e {
            LcpStepError::Unsupported(m) => StepError::InvalidInput(m),
            LcpStepError::NoSolution(message) => StepError::NoSolution {
                t: st.t,
                message,
                state: Box::new(st.clone()),
            },
        })?;
        let stats = StepStats {
            t: t1,
            iterations: 0,
            residual: step.residual,
            rho_inf: self.options.rho_inf,
            sets: IndexSets::default(),
            retries: 1,
            converged: true,
            branch: None,
            solver: "lemke".into(),
            substeps: 1,
            last_resort: Some(LastResort {
                pivots: step.pivots,
                residual: step.residual,
                projection: step.projection,
            }),
            unshifted: false,
        };
        let mut state = self.restarted_state(k, t1, step.q, step.u, step.p_n, step.p_f);
        state.flush_subnormals();
        self.account(&stats);
        self.state = state;
        self.forget_solutions();
        self.last = Some(stats);
        Ok(())
    }

    /// The generalized-α state at (t, q, u) after a last-resort step: accelerations and
    /// forces from the consistent start there (docs/method.md §5), or, if that fails,
    /// the free acceleration M⁻¹h and no forces.
    fn restarted_state(
        &self,
        k: u64,
        t: f64,
        q: Vec<f64>,
        u: Vec<f64>,
        p_n: Vec<f64>,
        p_f: Vec<f64>,
    ) -> State {
        let start = consistent_start(&self.system, &self.layout, t, &q, &u, &self.options)
            .unwrap_or_else(|_| Start::unforced(&self.system, &self.layout, t, &q, &u));
        super::started_state(&self.off, (k, t, q, u), start, p_n, p_f)
    }
}
