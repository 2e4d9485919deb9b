//! A linear oscillator m ẍ = −k x: its error shows the order of the scheme (free fall
//! is integrated exactly and cannot).

use crate::system::{Evaluation, Layout, Scalar, System};

/// Linear oscillator (q = x, u = ẋ), force −k x; ∂h/∂q = −k comes from automatic
/// differentiation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Oscillator {
    /// Mass m > 0.
    pub mass: f64,
    /// Stiffness k > 0.
    pub stiffness: f64,
}

impl Oscillator {
    /// Angular frequency ω = √(k/m).
    #[must_use]
    pub fn omega(&self) -> f64 {
        (self.stiffness / self.mass).sqrt()
    }
    /// The exact (x, ẋ) at t from (x0, v0).
    #[must_use]
    pub fn exact(&self, x0: f64, v0: f64, t: f64) -> (f64, f64) {
        let w = self.omega();
        let (s, c) = (w * t).sin_cos();
        (x0 * c + v0 / w * s, -x0 * w * s + v0 * c)
    }
}

impl System for Oscillator {
    fn layout(&self) -> Layout {
        Layout {
            nq: 1,
            nu: 1,
            ..Layout::default()
        }
    }
    fn evaluate<T: Scalar>(&self, _t: f64, q: &[T], _u: &[T], out: &mut Evaluation<T>) {
        out.mass.push(0, 0, T::from(self.mass));
        out.forces[0] = q[0] * (-self.stiffness);
    }
}
