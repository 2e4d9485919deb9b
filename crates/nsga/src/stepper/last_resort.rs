//! The last resort of a step that every other stage of its policy failed
//! (`Stage::LastResort`, docs/method.md §8.2): one Moreau–Jean step of the same system
//! whose contact problem Lemke's method solves, with every contact taking part and the
//! positions projected back onto the constraints after it ([`MoreauLemke::LAST_RESORT`],
//! [`crate::fallback`]). The generalized-α state then restarts from the consistent
//! accelerations and forces at the new state, as at t0.
//!
//! Whether the last resort takes the system is decided when the stepper is set up
//! ([`Stepper::new`], [`Stepper::set_options`]): a system it cannot take, with
//! [`PolicyOptions::last_resort`](crate::PolicyOptions::last_resort) on, is refused there.

use super::Stepper;
use crate::error::StepError;
use crate::fallback::{FallbackStep, MoreauLemke};
use crate::report::{LastResort, StepStats};
use crate::sets::IndexSets;
use crate::start::{consistent_start, Start};
use crate::state::State;
use crate::system::{Layout, System};

/// The refusal of a stepper whose options ask for the last resort on a system it cannot
/// take at (t, q, u); Ok where they do not ask for it or it can.
pub(super) fn check_coverage<S: System>(
    system: &S,
    layout: &Layout,
    asked: bool,
    t: f64,
    state: (&[f64], &[f64]),
) -> Result<(), StepError> {
    match MoreauLemke::LAST_RESORT.refusal(system, layout, t, state) {
        Some(why) if asked => Err(StepError::InvalidInput(format!(
            "Options::last_resort: the last resort cannot take this system at t = {t}: \
             {why}; remove the redundant constraint or set last_resort = false"
        ))),
        _ => Ok(()),
    }
}

impl<S: System> Stepper<S> {
    /// Takes the next step by the last resort alone, skipping the generalized-α
    /// attempts: a diagnostic, to see what the last resort makes of a system (its
    /// statistics are those of a last-resort step, [`StepStats::last_resort`]). It
    /// runs whatever [`PolicyOptions::last_resort`](crate::PolicyOptions::last_resort) says.
    ///
    /// # Errors
    /// [`StepError::InvalidInput`] where the last resort cannot take the system at the
    /// current state; otherwise as the last resort within [`Stepper::step`]
    /// ([`StepError::NoSolution`]). The stepper stays where it was.
    pub fn step_by_last_resort(&mut self) -> Result<&StepStats, StepError> {
        let st = &self.state;
        check_coverage(&self.system, &self.layout, true, st.t, (&st.q, &st.u))?;
        self.last_resort()?;
        Ok(self.committed())
    }

    /// Takes the step by the last resort and commits it.
    ///
    /// # Errors
    /// [`StepError::NoSolution`] when the step's contact problem has no solution (Lemke's
    /// method ends on a ray: a Painlevé-type inconsistency), the mass matrix or the
    /// bilateral constraints' Delassus block is singular, or the result is not finite.
    /// The stepper stays where it was.
    pub(super) fn last_resort(&mut self) -> Result<(), StepError> {
        let st = &self.state;
        let k = st.k + 1;
        let t1 = self.grid_time(k);
        let step = MoreauLemke::LAST_RESORT
            .step(
                &self.system,
                &self.layout,
                (st.t, t1),
                (&st.q, &st.u),
                self.options.dt,
            )
            .map_err(|message| StepError::NoSolution {
                t: st.t,
                message,
                state: Box::new(st.clone()),
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
