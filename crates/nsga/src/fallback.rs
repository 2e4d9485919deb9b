//! A step that terminates where the generalized-α attempts fail: the last resort of a
//! step's policy (`Stage::LastResort`, docs/method.md §8.2), and the Moreau–Jean
//! baseline's step when its Newton iteration does not converge.
//!
//! Whether such a step takes a system is decided once, when a stepper is set up
//! ([`FallbackStep::refusal`]): the policy then knows that its last stage exists, and a
//! system it cannot take is refused there with the reason, not at a failing step.

use crate::lcp_step::{self, Activation, LcpStep};
use crate::system::{Layout, System};

/// A step from (t, q, u) to t1 that needs no Newton iteration.
pub(crate) trait FallbackStep {
    /// Why this step cannot take `system` (with `layout`) at (t, q, u); None when it
    /// can. Asked when a stepper is set up.
    fn refusal<S: System>(
        &self,
        system: &S,
        layout: &Layout,
        t: f64,
        state: (&[f64], &[f64]),
    ) -> Option<String>;

    /// The step from (t, q, u) to `t1` = t + `dt`.
    ///
    /// # Errors
    /// Why no step was found: the contact problem has no solution (a Painlevé-type
    /// inconsistency), M or the bilateral constraints' Delassus block is singular
    /// there, or the result is not finite.
    fn step<S: System>(
        &self,
        system: &S,
        layout: &Layout,
        times: (f64, f64),
        state: (&[f64], &[f64]),
        dt: f64,
    ) -> Result<LcpStep, String>;
}

/// One Moreau–Jean step whose contact problem Lemke's method solves
/// ([`crate::lcp_step`]): every contact law nsga offers, disk friction approximately
/// ([`crate::friction_polygon`]), bilateral constraints eliminated exactly
/// ([`crate::constrained_mass`]). It refuses a system whose bilateral constraints are
/// redundant at the state it is set up at.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct MoreauLemke {
    /// Which contacts take part.
    pub activation: Activation,
    /// Whether the positions are projected back onto g = 0, g_N ≥ 0 after the step.
    pub project: bool,
}

impl MoreauLemke {
    /// The generalized-α stepper's last resort: every contact within reach, positions
    /// projected.
    pub(crate) const LAST_RESORT: Self = Self {
        activation: Activation::GapAware,
        project: true,
    };
    /// The Moreau–Jean baseline's step by Lemke's method: the contacts closed at q_M,
    /// as its Newton iteration has them, no projection.
    pub(crate) const BASELINE: Self = Self {
        activation: Activation::ClosedAtMidpoint,
        project: false,
    };
}

impl FallbackStep for MoreauLemke {
    fn refusal<S: System>(
        &self,
        system: &S,
        layout: &Layout,
        t: f64,
        state: (&[f64], &[f64]),
    ) -> Option<String> {
        lcp_step::refusal(system, layout, t, state)
    }

    fn step<S: System>(
        &self,
        system: &S,
        layout: &Layout,
        times: (f64, f64),
        state: (&[f64], &[f64]),
        dt: f64,
    ) -> Result<LcpStep, String> {
        lcp_step::lcp_step(
            system,
            layout,
            times,
            state,
            dt,
            self.activation,
            self.project,
        )
    }
}
