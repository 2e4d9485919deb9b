//! The unknowns z in which the Newton matrix is assembled and factored, and the change
//! back to the step's unknowns x (docs/method.md §4, "The Jacobian").

use super::unknowns::Offsets;
use crate::params::GenAlpha;

/// The unknowns in which the Newton matrix is assembled and factored:
/// z = (a, y_u, y_q, the multipliers) with y_u = U + c_u a and y_q = Q + c_q a, where
/// c_u = ∂u_{n+1}/∂a = Δt γ α_r and c_q B(q_n) = ∂q_{n+1}/∂a = Δt² β α_r B(q_n) (eqs. 73,
/// 125). Then u_{n+1} depends on z through y_u alone and q_{n+1} through y_q alone, so
/// every derivative of the system enters the matrix once, in the columns of y, instead of
/// once in y's and once in a's columns: a's columns keep only the explicit M a, M U, M Q
/// and Wᵀa. That halves the entries the system's derivatives put in the matrix and leaves
/// a's columns nearly empty, which the sparse elimination's fill follows
/// (docs/method.md §4, "The Jacobian"). The update dx = T dz is recovered by
/// [`KinematicColumns::to_unknowns`].
#[derive(Debug, Clone, Copy)]
pub(super) struct KinematicColumns {
    /// c_u = ∂u_{n+1}/∂a.
    pub c_ua: f64,
    /// c_q = ∂q_{n+1}/∂a, times B(q_n).
    pub c_qa: f64,
}

impl KinematicColumns {
    pub(super) fn new(dt: f64, p: &GenAlpha) -> Self {
        let ar = p.alpha_r();
        Self {
            c_ua: dt * p.gamma * ar,
            c_qa: dt * dt * p.beta * ar,
        }
    }

    /// dx = T dz: dU = dy_u − c_u da and dQ = dy_q − c_q da, in place.
    pub(super) fn to_unknowns(self, o: &Offsets, dz: &mut [f64]) {
        for i in 0..o.nu {
            let da = dz[o.a + i];
            dz[o.uu + i] -= self.c_ua * da;
            dz[o.qq + i] -= self.c_qa * da;
        }
    }

    /// The columns of ∂R/∂x from those of ∂R/∂x · T (`j`, dense), in place:
    /// ∂R/∂a = (∂R/∂z)_a + c_u (∂R/∂z)_{y_u} + c_q (∂R/∂z)_{y_q}.
    pub(super) fn to_unknown_columns(self, o: &Offsets, j: &mut nalgebra::DMatrix<f64>) {
        for i in 0..o.nu {
            let col = j.column(o.uu + i) * self.c_ua + j.column(o.qq + i) * self.c_qa;
            let mut a = j.column_mut(o.a + i);
            a += col;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::system::{FrictionLaw, Layout};
    use nalgebra::{DMatrix, DVector};

    /// The matrix the stepper factors, J T, and the update it returns, T dz, are those
    /// of the Jacobian in x: (J T) dz = J (T dz) for any J T and dz. With the
    /// finite-difference check of `to_unknown_columns` (crates/nsga/tests/jacobian.rs),
    /// this makes the update an exact Newton update in x.
    #[test]
    fn the_update_in_x_solves_the_system_in_z() {
        let layout = Layout {
            nq: 3,
            nu: 3,
            n_bilateral_position: 1,
            n_bilateral_velocity: 0,
            e_n: vec![0.0, 0.5],
            friction: vec![FrictionLaw {
                mu: 0.3,
                e_f: 0.0,
                normals: vec![1],
                components: 1,
            }],
        };
        let o = Offsets::new(&layout);
        let columns = KinematicColumns::new(0.01, &GenAlpha::new(0.5));
        let entry = |i: usize, j: usize| ((7 * i + 3 * j) as f64).sin();
        let j_z = DMatrix::from_fn(o.n, o.n, entry);
        let dz = DVector::from_fn(o.n, |i, _| (i as f64).cos());
        let mut j_x = j_z.clone();
        columns.to_unknown_columns(&o, &mut j_x);
        let mut dx = dz.clone();
        columns.to_unknowns(&o, dx.as_mut_slice());
        let (lhs, rhs) = (&j_z * &dz, &j_x * &dx);
        assert!((lhs - rhs).amax() < 1e-12);
        assert!(
            (&dx - &dz).amax() > 1e-6,
            "the change of unknowns is not the identity"
        );
    }
}
