//! Linear complementarity problems solved by Lemke's complementary pivoting method: the
//! last resort of a step (docs/method.md §8), because pivoting terminates.
//!
//! LCP(M, q): find z ≥ 0 with w = M z + q ≥ 0 and zᵀw = 0. Lemke's method adds an
//! artificial variable z₀ with covering vector e = (1, …, 1): w − M z − e z₀ = q. It
//! starts at z₀ = −min qᵢ, where all w are basic, and then pivots the complement of the
//! variable that just left into the basis, each time keeping every basic variable
//! non-negative (the minimum-ratio test), until z₀ leaves (a solution) or the entering
//! column has no positive entry (a secondary ray). Ties in the ratio test are broken
//! lexicographically, which rules out cycling, so the method ends after finitely many
//! pivots. It ends on a solution whenever M is copositive-plus and the LCP is feasible
//! (Cottle, Pang and Stone, *The Linear Complementarity Problem*, Thm. 4.4.9): the
//! contact problem of a Moreau–Jean step in the form of Anitescu and Potra (1997) has such
//! a matrix, so in exact arithmetic a ray there means the step's contact problem has no
//! solution. In floating point a rank-deficient M can end on a false ray;
//! [`lemke_regularized`] retries such a problem with εI added.
//!
//! The basis is carried either as the dense tableau B⁻¹[I, −M, −e, q] or, for large
//! problems, as sparse LU factors computed afresh at each pivot ([`Pivoting`]); both
//! take the same pivots in exact arithmetic.

mod factored;
pub use factored::FACTORED_FROM;

/// A solution of LCP(M, q).
#[derive(Debug, Clone, PartialEq)]
pub struct LcpSolution {
    /// z ≥ 0.
    pub z: Vec<f64>,
    /// w = M z + q ≥ 0, computed from z.
    pub w: Vec<f64>,
    /// Pivots taken.
    pub pivots: usize,
    /// max over i of |min(zᵢ, wᵢ)|: 0 for an exact solution.
    pub residual: f64,
}

/// Why Lemke's method ended without a solution.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LcpFailure {
    /// The entering column had no positive entry: no solution is reachable (for a
    /// copositive-plus M, the LCP is infeasible).
    #[error("Lemke's method ended on a ray after {pivots} pivots: the problem has no solution")]
    Ray {
        /// Pivots taken.
        pivots: usize,
    },
    /// The pivot limit was reached (only with degenerate data close to round-off).
    #[error("Lemke's method took more than {0} pivots")]
    PivotLimit(usize),
    /// M is not square of the size of q, or an entry is not finite.
    #[error("bad LCP data: {0}")]
    BadData(String),
}

/// Pivot entries below this, relative to the largest entry of their column, count as
/// zero.
///
/// Why 10⁻¹²: after k pivots an entry of the tableau that should be zero holds
/// round-off of about k ε relative to its column (ε ≈ 2.2·10⁻¹⁶); 10⁻¹² covers the
/// pivots of the largest contact problems the last resort meets (a few thousand) with a
/// margin. Taking such an entry as the pivot would divide by round-off: the basis that
/// follows describes no solution, and the method ends on a false ray.
const PIVOT_TOL: f64 = 1e-12;

/// How Lemke's method carries its basis from pivot to pivot.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Pivoting {
    /// The dense tableau B⁻¹[I, −M, −e, q], updated by Gauss–Jordan pivots: O(n²) per
    /// pivot once B⁻¹ has filled in, and cheap while it has not.
    Tableau,
    /// Sparse LU factors of the basis, computed afresh at each pivot: O(nnz) per pivot
    /// for a banded M, with a larger constant (see [`FACTORED_FROM`]).
    FactoredBasis,
}

impl Pivoting {
    /// The faster for an LCP of `n` unknowns: the tableau below [`FACTORED_FROM`].
    #[must_use]
    pub fn for_size(n: usize) -> Self {
        if n < FACTORED_FROM {
            Self::Tableau
        } else {
            Self::FactoredBasis
        }
    }
}

/// Solves LCP(M, q) by Lemke's method; `m` is row-major, n × n with n = q.len(). The
/// basis is carried as [`Pivoting::for_size`] says.
///
/// # Errors
/// [`LcpFailure::Ray`] when the method ends on a secondary ray,
/// [`LcpFailure::PivotLimit`] after `max_pivots`, [`LcpFailure::BadData`] for wrong
/// sizes or non-finite entries.
///
/// # Examples
/// ```
/// // Two unit masses pressed together: w = M z + q with M = [[2, -1], [-1, 2]].
/// let sol = nsga::lcp::lemke(&[2.0, -1.0, -1.0, 2.0], &[-1.0, 1.0], 100)?;
/// assert!((sol.z[0] - 0.5).abs() < 1e-12 && sol.z[1] == 0.0);
/// assert!(sol.residual < 1e-12);
/// # Ok::<(), nsga::lcp::LcpFailure>(())
/// ```
pub fn lemke(m: &[f64], q: &[f64], max_pivots: usize) -> Result<LcpSolution, LcpFailure> {
    lemke_with(Pivoting::for_size(q.len()), m, q, max_pivots)
}

/// [`lemke`] with the basis carried as `pivoting` says. Both take the same pivots in
/// exact arithmetic.
///
/// # Errors
/// As [`lemke`].
pub fn lemke_with(
    pivoting: Pivoting,
    m: &[f64],
    q: &[f64],
    max_pivots: usize,
) -> Result<LcpSolution, LcpFailure> {
    let n = q.len();
    if m.len() != n * n {
        return Err(LcpFailure::BadData(format!(
            "M has {} entries for q of length {n}",
            m.len()
        )));
    }
    if m.iter().chain(q).any(|x| !x.is_finite()) {
        return Err(LcpFailure::BadData("an entry is not finite".into()));
    }
    let (z, pivots) = if q.iter().all(|&qi| qi >= 0.0) {
        (vec![0.0; n], 0)
    } else {
        match pivoting {
            Pivoting::Tableau => Tableau::new(m, q).pivot_to_solution(max_pivots)?,
            Pivoting::FactoredBasis => factored::pivot_to_solution(m, q, max_pivots)?,
        }
    };
    Ok(on_problem(m, q, z, pivots))
}

/// The regularizations ε that [`lemke_regularized`] adds to the diagonal of M, in turn,
/// relative to the largest diagonal entry.
///
/// Why these: a regularized solution's residual on the original problem is at most
/// ε‖z‖∞ (see [`lemke_regularized`]), so the smallest ε that removes the false ray is
/// the most accurate and is tried first; 10⁻¹⁰ is a thousand times round-off of the
/// diagonal, enough to make M + εI strictly copositive in floating point. Each next
/// value is a hundred times larger, so that three solves span the range up to 10⁻⁶,
/// beyond which even impulses of the size of the problem's scale would miss the
/// acceptance test of the step's contact problem (10⁻⁸, `lcp_step`). The tries are
/// work only in the last resort, which no step of the reference workload reaches.
pub const REGULARIZATIONS: [f64; 3] = [1e-10, 1e-8, 1e-6];

/// Lemke's method that survives round-off on rank-deficient M: solves LCP(M, q) and, if
/// that ends on a ray or at the pivot limit, LCP(M + εI, q) for ε from
/// [`REGULARIZATIONS`] in turn, accepting the first solution whose residual on the
/// original problem (max |min(zᵢ, wᵢ)| with w = M z + q) is at most `accept`. Returns
/// the solution (w and residual those of the original problem) and the ε it needed
/// (0 when none).
///
/// Why: the Moreau–Jean contact problem of a block column has far more contacts than
/// degrees of freedom (a 50-block column: 300 normal contacts, a normal Delassus block
/// of rank 149). Such an LCP has solutions (Anitescu and Potra 1997), but the
/// Gauss–Jordan tableau of a rank-deficient M loses them to round-off and ends on a
/// false secondary ray. With M copositive, M + εI is strictly copositive: every q is
/// feasible and Lemke's method ends on a solution (the theorem cited in the module
/// docs), whose residual on the original problem is at most ε‖z‖∞. Where the original
/// problem has no solution, ‖z‖ grows like 1/ε and the test on that residual rejects it.
///
/// # Errors
/// The first attempt's [`LcpFailure`] when no regularized solution passes.
///
/// # Examples
/// ```
/// // w = −z − 1 ≥ 0 has no solution, regularized or not.
/// assert!(nsga::lcp::lemke_regularized(&[-1.0], &[-1.0], 10, 1e-6).is_err());
/// let (sol, eps) = nsga::lcp::lemke_regularized(&[2.0], &[-1.0], 10, 1e-6)?;
/// assert_eq!((sol.z, eps), (vec![0.5], 0.0));
/// # Ok::<(), nsga::lcp::LcpFailure>(())
/// ```
pub fn lemke_regularized(
    m: &[f64],
    q: &[f64],
    max_pivots: usize,
    accept: f64,
) -> Result<(LcpSolution, f64), LcpFailure> {
    let first = match lemke(m, q, max_pivots) {
        Ok(sol) => return Ok((sol, 0.0)),
        Err(e @ LcpFailure::BadData(_)) => return Err(e),
        Err(e) => e,
    };
    let n = q.len();
    let diag = (0..n).map(|i| m[i * n + i].abs()).fold(0.0, f64::max);
    for rel in REGULARIZATIONS {
        let eps = rel * diag.max(f64::MIN_POSITIVE);
        let mut shifted = m.to_vec();
        for i in 0..n {
            shifted[i * n + i] += eps;
        }
        if let Ok(sol) = lemke(&shifted, q, max_pivots) {
            let sol = on_problem(m, q, sol.z, sol.pivots);
            if sol.residual <= accept {
                return Ok((sol, eps));
            }
        }
    }
    Err(first)
}

/// z with w = M z + q and the residual of LCP(M, q) at z.
fn on_problem(m: &[f64], q: &[f64], z: Vec<f64>, pivots: usize) -> LcpSolution {
    let n = q.len();
    let w: Vec<f64> = (0..n)
        .map(|i| q[i] + (0..n).map(|j| m[i * n + j] * z[j]).sum::<f64>())
        .collect();
    let residual = z
        .iter()
        .zip(&w)
        .map(|(a, b)| a.min(*b).abs())
        .fold(0.0, f64::max);
    LcpSolution {
        z,
        w,
        pivots,
        residual,
    }
}

/// The tableau B⁻¹ [I, −M, −e, q] over the variables w₁…wₙ, z₁…zₙ, z₀ (columns 0..2n+1)
/// and the right-hand side (column 2n+1), with the basic variable of each row.
struct Tableau {
    n: usize,
    rows: Vec<Vec<f64>>,
    basis: Vec<usize>,
}

impl Tableau {
    fn new(m: &[f64], q: &[f64]) -> Self {
        let n = q.len();
        let rows = (0..n)
            .map(|i| {
                let mut r = vec![0.0; 2 * n + 2];
                r[i] = 1.0;
                for j in 0..n {
                    r[n + j] = -m[i * n + j];
                }
                r[2 * n] = -1.0;
                r[2 * n + 1] = q[i];
                r
            })
            .collect();
        Self {
            n,
            rows,
            basis: (0..n).collect(),
        }
    }

    /// The z part of the solution and the pivots taken.
    fn pivot_to_solution(mut self, max_pivots: usize) -> Result<(Vec<f64>, usize), LcpFailure> {
        let n = self.n;
        let z0 = 2 * n;
        // z₀ enters; the most negative q leaves (ties: the lowest index).
        let mut leaving_row = (0..n)
            .min_by(|&a, &b| self.rhs(a).total_cmp(&self.rhs(b)))
            .expect("n > 0 here");
        let mut entering = z0;
        for pivots in 1..=max_pivots {
            let left = self.basis[leaving_row];
            self.pivot(leaving_row, entering);
            if left == z0 {
                return Ok((self.z_values(), pivots));
            }
            // The complement of the variable that left enters.
            entering = if left < n { left + n } else { left - n };
            leaving_row = self
                .ratio_test(entering)
                .ok_or(LcpFailure::Ray { pivots })?;
        }
        Err(LcpFailure::PivotLimit(max_pivots))
    }

    fn rhs(&self, row: usize) -> f64 {
        self.rows[row][2 * self.n + 1]
    }

    /// The row that leaves when `col` enters: the least ratio rhs/entry over positive
    /// entries, ties broken lexicographically on the rows of B⁻¹ (columns 0..n) and in
    /// favour of z₀, so that no basis repeats.
    fn ratio_test(&self, col: usize) -> Option<usize> {
        let n = self.n;
        let scale = self.rows.iter().map(|r| r[col].abs()).fold(0.0, f64::max);
        let candidates: Vec<usize> = (0..n)
            .filter(|&i| self.rows[i][col] > PIVOT_TOL * scale.max(1.0))
            .collect();
        let key = |i: usize, k: usize| {
            let a = self.rows[i][col];
            if k == 0 {
                self.rhs(i) / a
            } else {
                self.rows[i][k - 1] / a
            }
        };
        let mut best = *candidates.first()?;
        for &i in &candidates[1..] {
            for k in 0..=n {
                let (a, b) = (key(i, k), key(best, k));
                let tie = (a - b).abs() <= 1e-12 * (1.0 + a.abs().max(b.abs()));
                if !tie {
                    if a < b {
                        best = i;
                    }
                    break;
                }
                // A tie on the ratio itself goes to z₀ whichever row holds it.
                if k == 0 && (self.basis[i] == 2 * n || self.basis[best] == 2 * n) {
                    if self.basis[i] == 2 * n {
                        best = i;
                    }
                    break;
                }
            }
        }
        Some(best)
    }

    /// Gauss–Jordan pivot on (row, col): `col` becomes basic in `row`.
    fn pivot(&mut self, row: usize, col: usize) {
        let p = self.rows[row][col];
        for x in &mut self.rows[row] {
            *x /= p;
        }
        // The tableau of a contact problem stays mostly zeros for many pivots (B⁻¹ starts
        // as I, and a contact's row of M has only the entries of the contacts that share
        // a body with it): the update runs over the pivot row's nonzeros only, which
        // changes no result (x − f·0 = x).
        let pivot_row: Vec<(usize, f64)> = self.rows[row]
            .iter()
            .copied()
            .enumerate()
            .filter(|e| e.1 != 0.0)
            .collect();
        for (i, r) in self.rows.iter_mut().enumerate() {
            let f = r[col];
            if i != row && f != 0.0 {
                for &(k, y) in &pivot_row {
                    r[k] -= f * y;
                }
            }
        }
        self.basis[row] = col;
    }

    /// z₁…zₙ from the basis (non-basic ones are zero; round-off negatives clamped).
    fn z_values(&self) -> Vec<f64> {
        let n = self.n;
        let mut z = vec![0.0; n];
        for (row, &var) in self.basis.iter().enumerate() {
            if (n..2 * n).contains(&var) {
                z[var - n] = self.rhs(row).max(0.0);
            }
        }
        z
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A reproducible pseudo-random sequence in [−1, 1) (no dependency needed).
    fn sequence(seed: u64) -> impl FnMut() -> f64 {
        let mut s = seed;
        move || {
            s = s
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            ((s >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        }
    }

    #[test]
    fn positive_definite_problems_are_solved_exactly() {
        for seed in 0..50 {
            let mut r = sequence(seed);
            let n = 1 + (seed as usize % 12);
            // M = AᵀA + I: positive definite, so the LCP has exactly one solution.
            let a: Vec<f64> = (0..n * n).map(|_| r()).collect();
            let mut m = vec![0.0; n * n];
            for i in 0..n {
                for j in 0..n {
                    m[i * n + j] = (0..n).map(|k| a[k * n + i] * a[k * n + j]).sum::<f64>()
                        + f64::from(u8::from(i == j));
                }
            }
            let q: Vec<f64> = (0..n).map(|_| r()).collect();
            let sol = lemke(&m, &q, 10 * n + 10).unwrap();
            assert!(sol.residual < 1e-12, "seed {seed}: {sol:?}");
            assert!(sol.z.iter().chain(&sol.w).all(|&x| x >= -1e-12));
        }
    }

    /// LCP(M, q) with M = AᵀA + I (n × n) or, `singular`, AᵀA of a 2 × n matrix A.
    fn random_problem(seed: u64, n: usize, singular: bool) -> (Vec<f64>, Vec<f64>) {
        let mut r = sequence(seed);
        let rows = if singular { 2 } else { n };
        let a: Vec<f64> = (0..rows * n).map(|_| r()).collect();
        let mut m = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                let identity = f64::from(u8::from(i == j && !singular));
                m[i * n + j] =
                    (0..rows).map(|k| a[k * n + i] * a[k * n + j]).sum::<f64>() + identity;
            }
        }
        let q: Vec<f64> = (0..n).map(|_| r()).collect();
        (m, q)
    }

    #[test]
    fn the_factored_basis_takes_the_pivots_of_the_tableau() {
        let mut compared = 0;
        for seed in 0..60 {
            let n = 2 + (seed as usize % 25);
            let (m, q) = random_problem(seed, n, seed % 3 == 0);
            if q.iter().all(|&x| x >= 0.0) {
                continue;
            }
            let tableau = Tableau::new(&m, &q).pivot_to_solution(50 * n);
            let factored = factored::pivot_to_solution(&m, &q, 50 * n);
            match (tableau, factored) {
                (Ok((zt, pt)), Ok((zf, pf))) => {
                    assert_eq!(pt, pf, "seed {seed}");
                    let gap = zt
                        .iter()
                        .zip(&zf)
                        .map(|(a, b)| (a - b).abs())
                        .fold(0.0, f64::max);
                    assert!(gap < 1e-9, "seed {seed}: {gap}");
                    compared += 1;
                }
                (t, f) => assert_eq!(t.is_ok(), f.is_ok(), "seed {seed}: {t:?} {f:?}"),
            }
        }
        assert!(compared >= 40, "{compared}");
        // Degenerate ties (equal q, singular M) and an infeasible problem.
        let ones = [1.0; 9];
        let (z, _) = factored::pivot_to_solution(&ones, &[-1.0, -1.0, -1.0], 50).unwrap();
        assert!((z.iter().sum::<f64>() - 1.0).abs() < 1e-12, "{z:?}");
        assert!(matches!(
            factored::pivot_to_solution(&[-1.0], &[-1.0], 10),
            Err(LcpFailure::Ray { pivots: 1 })
        ));
    }

    #[test]
    fn a_nonnegative_q_needs_no_pivot_and_degenerate_ties_do_not_cycle() {
        let sol = lemke(&[1.0, 0.0, 0.0, 1.0], &[0.0, 2.0], 10).unwrap();
        assert_eq!((sol.z, sol.pivots), (vec![0.0, 0.0], 0));
        // Equal q entries and a singular M: ties at every ratio test.
        let m = [1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0];
        let sol = lemke(&m, &[-1.0, -1.0, -1.0], 50).unwrap();
        assert!(sol.residual < 1e-12, "{sol:?}");
        assert!((sol.z.iter().sum::<f64>() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn an_infeasible_problem_ends_on_a_ray() {
        // w = −z − 1 ≥ 0 cannot hold for z ≥ 0.
        assert!(matches!(
            lemke(&[-1.0], &[-1.0], 10),
            Err(LcpFailure::Ray { .. })
        ));
        assert!(matches!(
            lemke(&[1.0, 2.0], &[1.0], 10),
            Err(LcpFailure::BadData(_))
        ));
        assert!(matches!(
            lemke(&[f64::NAN], &[1.0], 10),
            Err(LcpFailure::BadData(_))
        ));
    }

    #[test]
    fn regularized_solutions_are_accepted_only_on_the_original_residual() {
        // Solvable: the first attempt answers, with no regularization.
        let m = [1.0, 1.0, 1.0, 1.0];
        let (sol, eps) = lemke_regularized(&m, &[-1.0, -1.0], 20, 1e-9).unwrap();
        assert_eq!(eps, 0.0);
        assert!(sol.residual < 1e-12);
        // No solution (w₂ = −1 whatever z): the regularized problems have one, with
        // z ~ 1/ε, but it is not a solution of this one, so the ray stands.
        let m = [1.0, 0.0, 0.0, 0.0];
        assert!(matches!(
            lemke_regularized(&m, &[0.0, -1.0], 20, 1e-9),
            Err(LcpFailure::Ray { .. })
        ));
    }

    #[test]
    fn a_block_on_a_rough_floor_sticks_or_slides_as_coulomb_says() {
        // Unit mass, one contact, pushed sideways by f = 0.5 (impulse over dt = 1),
        // pressed down by 1: μ = 0.8 sticks, μ = 0.3 slides with P_T = −0.3.
        // Unknowns (P_N, β⁺, β⁻, λ); velocities u⁺ = (0.5 + β⁺ − β⁻, −1 + P_N).
        for (mu, p_t) in [(0.8, -0.5), (0.3, -0.3)] {
            #[rustfmt::skip]
            let m = [
                1.0, 0.0, 0.0, 0.0,
                0.0, 1.0, -1.0, 1.0,
                0.0, -1.0, 1.0, 1.0,
                mu, -1.0, -1.0, 0.0,
            ];
            let q = [-1.0, 0.5, -0.5, 0.0];
            let sol = lemke(&m, &q, 50).unwrap();
            assert!(sol.residual < 1e-12, "{sol:?}");
            assert!((sol.z[0] - 1.0).abs() < 1e-12);
            assert!(
                (sol.z[1] - sol.z[2] - p_t).abs() < 1e-12,
                "μ = {mu}: {sol:?}"
            );
        }
    }
}
