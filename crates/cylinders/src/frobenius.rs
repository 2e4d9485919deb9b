//! Frobenius' integrability test, numerically (App. D, F).
//!
//! A system of constraints linear in the velocities, Π(q, q̇) = W(q) q̇ (+ terms free of q̇,
//! which do not change the distribution), is described by its matrix W ([`PfaffianSystem`]).
//! The test builds the skew matrices (D.1.5)
//!
//! S^Γ_{L,K} = ∂W_{ΓL}/∂q^K − ∂W_{ΓK}/∂q^L,
//!
//! with exact derivatives (forward-mode automatic differentiation with
//! [`num_dual::Dual64`]: one pass per coordinate), a basis of the null space of W from
//! its SVD, and evaluates aᵀ S^Γ b over it (D.1.7). The constraints are integrable iff
//! every aᵀ S^Γ b vanishes for all a, b in the null space (and all q).
//!
//! As a basis-independent measure, [`FrobeniusReport::max_abs_asb`] is the largest
//! |aᵀ S^Γ b| over *unit* vectors a, b of the null space: the spectral norm of Nᵀ S^Γ N for
//! an orthonormal null basis N. (aᵀ S^Γ b is the Γ-th component of W [a, b], [a, b] the
//! Lie bracket of the two admissible velocity fields: the test asks whether the bracket
//! stays admissible.)

use crate::error::CylinderError;
use input::InputError;
use nalgebra::{DMatrix, DVector, RealField};
use num_dual::Dual64;
use serde::{Deserialize, Serialize};

/// Constraints Π = W(q) q̇ on n coordinates.
pub trait PfaffianSystem {
    /// Number of coordinates n.
    fn coordinate_count(&self) -> usize;
    /// Number of constraints (rows of W).
    fn constraint_count(&self) -> usize;
    /// W(q), constraint_count × coordinate_count, for any real scalar (f64 or a dual
    /// number). `q` has `coordinate_count` entries.
    fn constraint_matrix<T: RealField + Copy>(&self, q: &[T]) -> DMatrix<T>;
}

/// W and the skew matrices S^Γ at one configuration.
#[derive(Debug, Clone, PartialEq)]
pub struct SkewMatrices {
    /// W(q).
    pub w: DMatrix<f64>,
    /// S^Γ for Γ = 1..=constraint_count, each n × n and skew, (D.1.5).
    pub s: Vec<DMatrix<f64>>,
}

fn check_dimension<S: PfaffianSystem>(system: &S, q: &[f64]) -> Result<(), CylinderError> {
    if q.len() != system.coordinate_count() {
        return Err(CylinderError::Dimension {
            expected: system.coordinate_count(),
            got: q.len(),
        });
    }
    if q.iter().any(|v| !v.is_finite()) {
        return Err(InputError::NonFinite("coordinates q".into()).into());
    }
    Ok(())
}

/// Assembles S^Γ_{L,K} = ∂_K W_{ΓL} − ∂_L W_{ΓK} from the derivative matrices ∂W/∂q^K,
/// after checking that W and its derivatives are finite: an SVD of NaN has rank 0, and
/// the test would then call the system "not integrable" instead of failing.
fn assemble(w: DMatrix<f64>, dw: &[DMatrix<f64>]) -> Result<SkewMatrices, CylinderError> {
    all_finite("W(q)", &w)?;
    for (k, d) in dw.iter().enumerate() {
        all_finite(&format!("the derivative of W(q) by q[{k}]"), d)?;
    }
    let (m, n) = w.shape();
    let s = (0..m)
        .map(|gamma| DMatrix::from_fn(n, n, |l, k| dw[k][(gamma, l)] - dw[l][(gamma, k)]))
        .collect();
    Ok(SkewMatrices { w, s })
}

/// Refuses a matrix `what` with a NaN or infinite entry, naming the entry (row and
/// column from 0, as the system's W(q) is indexed).
fn all_finite(what: &str, a: &DMatrix<f64>) -> Result<(), CylinderError> {
    match a.iter().position(|v| !v.is_finite()) {
        Some(k) => {
            let (row, column) = (k % a.nrows(), k / a.nrows());
            Err(InputError::NonFinite(format!("{what} at row {row}, column {column}")).into())
        }
        None => Ok(()),
    }
}

/// W and S^Γ with exact derivatives (forward-mode dual numbers, one pass per coordinate).
///
/// # Errors
/// When `q` has the wrong length or a non-finite entry, or W(q) or a derivative has one.
pub fn skew_matrices<S: PfaffianSystem>(
    system: &S,
    q: &[f64],
) -> Result<SkewMatrices, CylinderError> {
    check_dimension(system, q)?;
    let n = q.len();
    let mut w = None;
    let mut dw = Vec::with_capacity(n);
    let mut qd: Vec<Dual64> = q.iter().map(|&v| Dual64::from_re(v)).collect();
    for k in 0..n {
        qd[k].eps = 1.0;
        let wd = system.constraint_matrix(&qd);
        qd[k].eps = 0.0;
        if w.is_none() {
            w = Some(wd.map(|d| d.re));
        }
        dw.push(wd.map(|d| d.eps));
    }
    let w = w.unwrap_or_else(|| system.constraint_matrix(q));
    assemble(w, &dw)
}

/// W and S^Γ with central differences of step `step`: a test oracle for
/// [`skew_matrices`], never used by the test itself, and the derivatives of a system
/// that only evaluates in `f64` (Python's).
///
/// # Errors
/// When `q` has the wrong length or a non-finite entry, or W or a difference quotient
/// has one.
pub fn skew_matrices_central_difference<S: PfaffianSystem>(
    system: &S,
    q: &[f64],
    step: f64,
) -> Result<SkewMatrices, CylinderError> {
    check_dimension(system, q)?;
    let mut qp = q.to_vec();
    let dw: Vec<DMatrix<f64>> = (0..q.len())
        .map(|k| {
            qp[k] = q[k] + step;
            let plus = system.constraint_matrix(&qp);
            qp[k] = q[k] - step;
            let minus = system.constraint_matrix(&qp);
            qp[k] = q[k];
            (plus - minus) / (2.0 * step)
        })
        .collect();
    assemble(system.constraint_matrix(q), &dw)
}

/// aᵀ S b.
#[must_use]
pub fn bilinear(s: &DMatrix<f64>, a: &DVector<f64>, b: &DVector<f64>) -> f64 {
    a.dot(&(s * b))
}

/// The outcome of the Frobenius test at one configuration.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FrobeniusReport {
    /// Number of coordinates n.
    pub coordinates: usize,
    /// Number of constraints.
    pub constraints: usize,
    /// Rank of W: singular values above `rank_tolerance` × σ_max.
    pub rank: usize,
    /// n − rank: dimension of the admissible velocities.
    pub nullity: usize,
    /// All singular values of W, descending (n of them, padded with zeros).
    pub singular_values: Vec<f64>,
    /// Relative threshold used for the rank.
    pub rank_tolerance: f64,
    /// Per constraint Γ: max |aᵀ S^Γ b| over unit a, b in the null space of W.
    pub max_abs_asb: Vec<f64>,
    /// Per constraint Γ: whether `max_abs_asb[Γ]` ≤ `integrability_tolerance` × (1 + max |S^Γ|).
    pub integrable: Vec<bool>,
    /// Threshold used for `integrable`.
    pub integrability_tolerance: f64,
    /// An orthonormal basis of the null space of W, one column per vector.
    #[serde(skip)]
    pub null_basis: DMatrix<f64>,
}

impl FrobeniusReport {
    /// Whether the whole system passes the test (every Γ integrable).
    #[must_use]
    pub fn system_integrable(&self) -> bool {
        self.integrable.iter().all(|&b| b)
    }

    /// The smallest non-zero singular value (the `rank`-th), a measure of how far W is
    /// from losing rank.
    #[must_use]
    pub fn smallest_nonzero_singular_value(&self) -> f64 {
        self.rank
            .checked_sub(1)
            .map_or(0.0, |i| self.singular_values[i])
    }
}

/// Default relative threshold for the rank of W.
pub const RANK_TOLERANCE: f64 = 1e-10;
/// Default threshold for "aᵀ S^Γ b = 0".
pub const INTEGRABILITY_TOLERANCE: f64 = 1e-9;

/// Runs the test at configuration `q` with the default tolerances.
///
/// # Errors
/// When `q` has the wrong length or a non-finite entry, or W(q) or a derivative has one
/// (never a rank-0 "not integrable" from NaN).
pub fn frobenius_test<S: PfaffianSystem>(
    system: &S,
    q: &[f64],
) -> Result<FrobeniusReport, CylinderError> {
    let skew = skew_matrices(system, q)?;
    Ok(report_from(&skew, RANK_TOLERANCE, INTEGRABILITY_TOLERANCE))
}

/// The report for given W and S^Γ (from [`skew_matrices`] or the oracle).
#[must_use]
pub fn report_from(
    skew: &SkewMatrices,
    rank_tolerance: f64,
    integrability_tolerance: f64,
) -> FrobeniusReport {
    let (m, n) = skew.w.shape();
    let (singular_values, null_basis, rank) = null_space(&skew.w, rank_tolerance);
    let (max_abs_asb, integrable) = skew
        .s
        .iter()
        .map(|s| {
            let reduced = null_basis.transpose() * s * &null_basis;
            let value = if reduced.is_empty() {
                0.0
            } else {
                reduced.singular_values().max()
            };
            let scale = 1.0 + s.amax();
            (value, value <= integrability_tolerance * scale)
        })
        .unzip();
    FrobeniusReport {
        coordinates: n,
        constraints: m,
        rank,
        nullity: n - rank,
        singular_values,
        rank_tolerance,
        max_abs_asb,
        integrable,
        integrability_tolerance,
        null_basis,
    }
}

/// Singular values (descending, n of them), an orthonormal null-space basis and the rank
/// of an m × n matrix, from the SVD of W padded with zero rows to n × n (so that all n
/// right singular vectors are available).
#[must_use]
pub fn null_space(w: &DMatrix<f64>, rank_tolerance: f64) -> (Vec<f64>, DMatrix<f64>, usize) {
    let (m, n) = w.shape();
    let mut padded = DMatrix::zeros(m.max(n), n);
    padded.view_mut((0, 0), (m, n)).copy_from(w);
    let svd = padded.svd(false, true);
    let Some(v_t) = svd.v_t else {
        unreachable!("SVD computed with v_t")
    };
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&i, &j| svd.singular_values[j].total_cmp(&svd.singular_values[i]));
    let sigma: Vec<f64> = order.iter().map(|&i| svd.singular_values[i]).collect();
    let smax = sigma.first().copied().unwrap_or(0.0);
    let rank = sigma
        .iter()
        .filter(|&&s| s > rank_tolerance * smax.max(f64::MIN_POSITIVE))
        .count();
    let columns: Vec<DVector<f64>> = order[rank..]
        .iter()
        .map(|&i| v_t.row(i).transpose())
        .collect();
    let basis = if columns.is_empty() {
        DMatrix::zeros(n, 0)
    } else {
        DMatrix::from_columns(&columns)
    };
    (sigma, basis, rank)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The classic non-holonomic example: the knife edge / unicycle in the plane,
    /// q = (x, y, θ), constraint −sin θ ẋ + cos θ ẏ = 0; and an integrable one, ẋ = 0.
    struct KnifeEdge;
    impl PfaffianSystem for KnifeEdge {
        fn coordinate_count(&self) -> usize {
            3
        }
        fn constraint_count(&self) -> usize {
            2
        }
        fn constraint_matrix<T: RealField + Copy>(&self, q: &[T]) -> DMatrix<T> {
            let (s, c) = q[2].sin_cos();
            let z = T::zero();
            DMatrix::from_row_slice(2, 3, &[-s, c, z, z, z, T::one()])
        }
    }

    #[test]
    fn knife_edge() {
        // Rows: −sin θ ẋ + cos θ ẏ = 0 and θ̇ = 0: together integrable (θ = const makes
        // the first the derivative of −sin θ x + cos θ y).
        let report = frobenius_test(&KnifeEdge, &[0.3, -0.2, 0.7]).unwrap();
        assert_eq!((report.rank, report.nullity), (2, 1));
        assert!(report.system_integrable());
        // Alone, the first row is not integrable: nullity 2, aᵀ S b = ±1.
        struct One;
        impl PfaffianSystem for One {
            fn coordinate_count(&self) -> usize {
                3
            }
            fn constraint_count(&self) -> usize {
                1
            }
            fn constraint_matrix<T: RealField + Copy>(&self, q: &[T]) -> DMatrix<T> {
                let (s, c) = q[2].sin_cos();
                DMatrix::from_row_slice(1, 3, &[-s, c, T::zero()])
            }
        }
        let report = frobenius_test(&One, &[0.3, -0.2, 0.7]).unwrap();
        assert_eq!(report.nullity, 2);
        assert!((report.max_abs_asb[0] - 1.0).abs() < 1e-14);
        assert!(!report.integrable[0]);
        assert!(frobenius_test(&One, &[0.3]).is_err());
        assert!(frobenius_test(&One, &[0.3, f64::NAN, 0.0]).is_err());
    }

    /// W(q) = [√q0, 0]: NaN for q0 < 0, an infinite derivative at q0 = 0.
    struct Singular;
    impl PfaffianSystem for Singular {
        fn coordinate_count(&self) -> usize {
            2
        }
        fn constraint_count(&self) -> usize {
            1
        }
        fn constraint_matrix<T: RealField + Copy>(&self, q: &[T]) -> DMatrix<T> {
            DMatrix::from_row_slice(1, 2, &[q[0].sqrt(), T::zero()])
        }
    }

    #[test]
    fn a_non_finite_constraint_matrix_is_an_error_not_a_verdict() {
        let err = frobenius_test(&Singular, &[-1.0, 1.0]).unwrap_err();
        assert_eq!(err.to_string(), "W(q) at row 0, column 0 is not finite");
        let derivative = "the derivative of W(q) by q[0] at row 0, column 0 is not finite";
        let err = frobenius_test(&Singular, &[0.0, 1.0]).unwrap_err();
        assert_eq!(err.to_string(), derivative);
        let err = skew_matrices_central_difference(&Singular, &[0.0, 1.0], 1e-6).unwrap_err();
        assert_eq!(err.to_string(), derivative);
        assert!(frobenius_test(&Singular, &[1.0, 1.0]).is_ok());
    }
}
