//! M⁻¹ on the motions that the bilateral constraints allow: how the last resort
//! ([`crate::lcp_step`]) eliminates its equality constraints before Lemke's method.
//!
//! A velocity-level step with bilateral constraints B (position constraints g = 0 taken
//! on their rates, and velocity constraints γ = 0) is a mixed LCP:
//!
//! u⁺ = ũ + M⁻¹(W_B P_B + F y),  W_Bᵀu⁺ + c_B = 0 (P_B free),  y complementary as before.
//!
//! The equality block is solved for its multipliers with the Schur complement of the
//! Delassus matrix on the bilateral block, G_BB = W_BᵀM⁻¹W_B:
//! P_B = −G_BB⁻¹(W_Bᵀ(ũ + M⁻¹F y) + c_B), which leaves
//!
//! u⁺ = Π(ũ) + M̃⁻¹ F y,  Π(v) = v − M⁻¹W_B G_BB⁻¹(W_Bᵀv + c_B),
//! M̃⁻¹ = M⁻¹ − M⁻¹W_B G_BB⁻¹ W_BᵀM⁻¹,
//!
//! the same LCP over y with M⁻¹ replaced by M̃⁻¹ (symmetric positive semidefinite, so the
//! contact problem's matrix stays copositive-plus) and ũ by the free motion projected
//! onto the constraints. G_BB is singular exactly when the constraints are redundant;
//! the elimination then refuses, naming the constraint.

use crate::mass_inverse::MassInverse;
use nalgebra::{DMatrix, DVector};

/// A constraint whose Cholesky pivot of G_BB is below this fraction of its own
/// diagonal entry is redundant: its row of W_BᵀM⁻¹ is, to that relative size, a
/// combination of the rows before it (the pivot is the squared sine of the angle between
/// them in the M⁻¹ inner product, so the test does not depend on the constraints'
/// units). Round-off in G_BB is about 10⁻¹⁶ relative; 10⁻¹² leaves four digits above it.
pub const REDUNDANT_PIVOT: f64 = 1e-12;

/// v ↦ M⁻¹v, by whichever form of the inverse mass a contact problem is posed with.
pub(crate) trait InverseMass {
    /// The number of velocities.
    fn dim(&self) -> usize;
    /// M⁻¹v (or M̃⁻¹v).
    fn apply(&self, v: &[f64]) -> DVector<f64>;
}

impl InverseMass for MassInverse {
    fn dim(&self) -> usize {
        MassInverse::dim(self)
    }
    fn apply(&self, v: &[f64]) -> DVector<f64> {
        MassInverse::apply(self, v)
    }
}

/// M̃⁻¹ and the projection Π of the module docs, over the bilateral constraints whose
/// W columns it was built with (none: M⁻¹ and the identity, to the bit).
pub(crate) struct ConstrainedInverse<'a> {
    m_inv: &'a MassInverse,
    /// W_B, one column per constraint.
    w_b: Vec<DVector<f64>>,
    /// M⁻¹W_B.
    y: Vec<DVector<f64>>,
    /// The Cholesky factor L of G_BB = LLᵀ.
    l: DMatrix<f64>,
}

impl<'a> ConstrainedInverse<'a> {
    /// The elimination of the constraints with the columns `w_b` (named by `name(i)` in
    /// a refusal).
    ///
    /// # Errors
    /// The first constraint that is redundant with those before it
    /// ([`REDUNDANT_PIVOT`]).
    pub(crate) fn new(
        m_inv: &'a MassInverse,
        w_b: Vec<DVector<f64>>,
        name: impl Fn(usize) -> String,
    ) -> Result<Self, String> {
        let y: Vec<DVector<f64>> = w_b.iter().map(|w| m_inv.apply(w.as_slice())).collect();
        let nb = w_b.len();
        let g = DMatrix::from_fn(nb, nb, |r, c| w_b[r].dot(&y[c]));
        let l = cholesky(&g).map_err(|i| {
            format!(
                "{} is redundant: the Delassus matrix W_BᵀM⁻¹W_B of the bilateral \
                 constraints is singular there, so their multipliers are not determined",
                name(i)
            )
        })?;
        Ok(Self { m_inv, w_b, y, l })
    }

    /// Π(v): `v` less M⁻¹W_B G_BB⁻¹(W_Bᵀv + `c`), after which W_Bᵀv + c = 0.
    pub(crate) fn project(&self, v: &DVector<f64>, c: &[f64]) -> DVector<f64> {
        if self.w_b.is_empty() {
            return v.clone();
        }
        let residual = DVector::from_fn(self.w_b.len(), |i, _| self.w_b[i].dot(v) + c[i]);
        let mut out = v.clone();
        for (y, p) in self.y.iter().zip(self.solve(&residual).iter()) {
            out.axpy(-p, y, 1.0);
        }
        out
    }

    /// G_BB⁻¹ r by the Cholesky factor.
    fn solve(&self, r: &DVector<f64>) -> DVector<f64> {
        let l = &self.l;
        let forward = l
            .solve_lower_triangular(r)
            .expect("the Cholesky factor has positive pivots");
        l.tr_solve_lower_triangular(&forward)
            .expect("the Cholesky factor has positive pivots")
    }
}

impl InverseMass for ConstrainedInverse<'_> {
    fn dim(&self) -> usize {
        self.m_inv.dim()
    }
    /// M̃⁻¹v = Π(M⁻¹v) with c = 0.
    fn apply(&self, v: &[f64]) -> DVector<f64> {
        let free = self.m_inv.apply(v);
        if self.w_b.is_empty() {
            return free;
        }
        self.project(&free, &vec![0.0; self.w_b.len()])
    }
}

/// The Cholesky factor of the symmetric positive semidefinite `g`, or the first row
/// whose pivot is below [`REDUNDANT_PIVOT`] times its diagonal entry.
fn cholesky(g: &DMatrix<f64>) -> Result<DMatrix<f64>, usize> {
    let n = g.nrows();
    let mut l = DMatrix::zeros(n, n);
    for j in 0..n {
        let pivot = g[(j, j)] - (0..j).map(|k| l[(j, k)] * l[(j, k)]).sum::<f64>();
        // NaN fails the test too.
        if pivot.is_nan() || pivot <= REDUNDANT_PIVOT * g[(j, j)].abs() {
            return Err(j);
        }
        let d = pivot.sqrt();
        l[(j, j)] = d;
        for i in j + 1..n {
            let s = g[(i, j)] - (0..j).map(|k| l[(i, k)] * l[(j, k)]).sum::<f64>();
            l[(i, j)] = s / d;
        }
    }
    Ok(l)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two unit masses on a line joined by a rod (u₁ = u₂): M̃⁻¹ moves them together, Π
    /// takes out their relative speed, and a second, identical rod is refused.
    #[test]
    fn a_rod_between_two_masses_is_eliminated_and_a_second_one_refused() {
        let m_inv = MassInverse::of(2, &[(0, 0, 1.0), (1, 1, 1.0)]).expect("regular");
        let rod = DVector::from_vec(vec![1.0, -1.0]);
        let c = ConstrainedInverse::new(&m_inv, vec![rod.clone()], |i| format!("rod {i}"))
            .expect("one rod is not redundant");
        // A push on mass 0 moves both by half of it.
        let pushed = c.apply(&[1.0, 0.0]);
        assert!((pushed - DVector::from_vec(vec![0.5, 0.5])).amax() < 1e-15);
        // u = (3, 1) with the rod's rate u₁ − u₂ + 0 = 0: both at the mean, 2.
        let v = c.project(&DVector::from_vec(vec![3.0, 1.0]), &[0.0]);
        assert!((v - DVector::from_vec(vec![2.0, 2.0])).amax() < 1e-15);
        let twice =
            ConstrainedInverse::new(&m_inv, vec![rod.clone(), rod * 2.0], |i| format!("rod {i}"));
        let why = twice.err().expect("redundant");
        assert!(why.starts_with("rod 1 is redundant"), "{why}");
        // Without constraints, M⁻¹ itself.
        let none = ConstrainedInverse::new(&m_inv, Vec::new(), |_| String::new()).unwrap();
        assert_eq!(none.apply(&[1.0, 2.0]).as_slice(), &[1.0, 2.0]);
    }
}
