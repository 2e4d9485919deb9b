//! A point mass falling under gravity: y(t) = y0 + v0 t − ½ g t², integrated exactly.

use crate::system::{Evaluation, Layout, Scalar, System};

/// Vertical free fall of a point mass m under gravity g (q = y, u = ẏ).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FreeFall {
    /// Mass m > 0.
    pub mass: f64,
    /// Gravity g.
    pub gravity: f64,
}

impl FreeFall {
    /// The exact height at time t from (y0, v0) at t = 0.
    #[must_use]
    pub fn exact(&self, y0: f64, v0: f64, t: f64) -> (f64, f64) {
        (
            y0 + v0 * t - 0.5 * self.gravity * t * t,
            v0 - self.gravity * t,
        )
    }
}

impl System for FreeFall {
    fn layout(&self) -> Layout {
        Layout {
            nq: 1,
            nu: 1,
            ..Layout::default()
        }
    }
    fn evaluate<T: Scalar>(&self, _t: f64, _q: &[T], _u: &[T], out: &mut Evaluation<T>) {
        out.mass.push(0, 0, T::from(self.mass));
        out.forces[0] = T::from(-self.mass * self.gravity);
    }
}
