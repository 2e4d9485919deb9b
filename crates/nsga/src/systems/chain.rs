//! A vertical chain of n blocks (translation only) resting on each other and on the
//! ground, with one frictional contact per interface: the size-scaling benchmark.
//!
//! q = (x_0, y_0, …, x_{n−1}, y_{n−1}); gaps g_0 = y_0 − H/2, g_k = y_k − y_{k−1} − H;
//! slips γ_0 = ẋ_0, γ_k = ẋ_k − ẋ_{k−1}. Each contact couples two neighbours, so the
//! Newton matrix is banded and sparse LU costs O(n) per step. The derivatives are
//! given analytically from that structure (the default automatic differentiation would
//! cost one evaluation per coordinate, O(n²)).

use crate::system::{Derivatives, Evaluation, FrictionLaw, Layout, Probes, Scalar, System};

/// The chain.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Chain {
    /// Number of blocks n ≥ 1.
    pub n: usize,
    /// Mass of each block.
    pub mass: f64,
    /// Height H of each block.
    pub height: f64,
    /// Gravity g.
    pub gravity: f64,
    /// Friction coefficient μ.
    pub mu: f64,
}

impl Chain {
    /// The chain of the benchmarks, tests and examples: n unit masses of height 0.1,
    /// g = 9.81, μ = 0.3.
    #[must_use]
    pub fn benchmark(n: usize) -> Self {
        Self {
            n,
            mass: 1.0,
            height: 0.1,
            gravity: 9.81,
            mu: 0.3,
        }
    }

    /// The resting stack, the top block sliding at `v_top`.
    #[must_use]
    pub fn resting(&self, v_top: f64) -> (Vec<f64>, Vec<f64>) {
        let mut q = vec![0.0; 2 * self.n];
        for k in 0..self.n {
            q[2 * k + 1] = (k as f64 + 0.5) * self.height;
        }
        let mut u = vec![0.0; 2 * self.n];
        u[2 * (self.n - 1)] = v_top;
        (q, u)
    }

    /// The stack with an open gap `gap` above every block (the bottom one on the
    /// ground), at rest, the top block sliding at `v_top`: all blocks fall together, so
    /// every gap but the ground contact stays open.
    #[must_use]
    pub fn spread(&self, gap: f64, v_top: f64) -> (Vec<f64>, Vec<f64>) {
        let (mut q, u) = self.resting(v_top);
        for k in 0..self.n {
            q[2 * k + 1] += k as f64 * gap;
        }
        (q, u)
    }
}

impl System for Chain {
    fn layout(&self) -> Layout {
        Layout {
            nq: 2 * self.n,
            nu: 2 * self.n,
            e_n: vec![0.0; self.n],
            friction: (0..self.n)
                .map(|k| FrictionLaw {
                    components: 1,
                    mu: self.mu,
                    e_f: 0.0,
                    normals: vec![k],
                })
                .collect(),
            ..Layout::default()
        }
    }
    fn evaluate<T: Scalar>(&self, _t: f64, q: &[T], _u: &[T], out: &mut Evaluation<T>) {
        for k in 0..self.n {
            out.mass.push(2 * k, 2 * k, T::from(self.mass));
            out.mass.push(2 * k + 1, 2 * k + 1, T::from(self.mass));
            out.forces[2 * k + 1] = T::from(-self.mass * self.gravity);
            out.position_w.push(2 * k + 1, k, T::from(1.0));
            out.velocity_w.push(2 * k, k, T::from(1.0));
            if k == 0 {
                out.position[0] = q[1] - 0.5 * self.height;
            } else {
                out.position[k] = q[2 * k + 1] - q[2 * k - 1] - self.height;
                out.position_w.push(2 * k - 1, k, T::from(-1.0));
                out.velocity_w.push(2 * k - 2, k, T::from(-1.0));
            }
        }
    }
    /// Constant W and M: only ∂g_N/∂q, one or two entries per gap.
    fn derivatives(&self, _t: f64, _q: &[f64], _u: &[f64], _p: &Probes<'_>, out: &mut Derivatives) {
        for k in 0..self.n {
            out.position_q.push(k, 2 * k + 1, 1.0);
            if k > 0 {
                out.position_q.push(k, 2 * k - 1, -1.0);
            }
        }
    }
}
