//! Read access to the bilateral multipliers of the last accepted step.

use super::Stepper;
use crate::system::System;

impl<S: System> Stepper<S> {
    /// The forces λ_g of the ng bilateral position constraints and λ_γ of the nγ
    /// bilateral velocity constraints at the current state (the unknowns of eq. 126 that
    /// [`State`](crate::State) keeps only inside `x`). A system whose bilateral
    /// constraint holds a body (a prescribed height, a prescribed spin) reads the
    /// supporting force or moment here.
    #[must_use]
    pub fn bilateral_forces(&self) -> (&[f64], &[f64]) {
        let (o, x) = (&self.off, &self.state.x);
        (&x[o.lg..o.lg + o.ng], &x[o.lga..o.lga + o.nga])
    }
}
