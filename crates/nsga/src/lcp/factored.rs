//! Lemke's method on sparse LU factors of the basis instead of a tableau, for the large
//! LCPs of the last resort on tall columns.
//!
//! The tableau B⁻¹[I, −M, −e, q] holds B⁻¹ densely: for the contact problem of a column,
//! whose M is banded, B⁻¹ fills in as the pivots go, and a pivot costs up to n² (a
//! 1000-block column's first step, some 5000 unknowns, took about 300 s). Here each
//! pivot factors the basis afresh (sparse LU, faer) and solves with it for the basic
//! values and the entering column, and the lexicographic ties of the ratio test are
//! broken with rows of B⁻¹ from transposed solves, so the pivots are those of the
//! tableau method in exact arithmetic.
//!
//! The basis in factored form. Between pivots exactly one complementary pair (wᵢ, zᵢ),
//! the *open* pair, has neither variable basic, and z₀ is basic; every other pair has
//! one of its two basic. The unknowns are one per pair and z₀, with the matrix
//!
//! ```text
//! K = [ C    −e ]    C's column i: eᵢ (wᵢ basic, or i open), −M·ᵢ (zᵢ basic)
//!     [ eₒᵀ   0 ]    o: the open pair, whose unknown the last row holds at zero
//! ```
//!
//! K is regular exactly when the basis B is (its last row removes the open pair's
//! column, leaving B), and unlike B with z₀'s dense column in the open pair's place,
//! its pattern is that of M's basic columns plus one dense column that the column
//! ordering puts last.

use super::{LcpFailure, PIVOT_TOL};
use faer::linalg::solvers::SolveCore;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Conj, MatMut};

/// Unknowns from which [`super::lemke`] pivots on factors of the basis rather than on
/// the tableau ([`super::Pivoting::for_size`]). On the LCP of a chain (M tridiagonal,
/// `cargo bench -p nsga --bench nsga -- lemke_pivoting`) the two cost the same at about
/// 1000 unknowns: 112 ms on the tableau against 137 ms on factors at 800, 1.93 s against
/// 0.57 s at 1600 (medians). The tableau's pivots cost O(n²) once B⁻¹ has filled in,
/// those on factors O(n) for a banded M.
pub const FACTORED_FROM: usize = 1000;

/// The basis of Lemke's method in factored form (see the module docs).
struct Basis<'a> {
    n: usize,
    /// M's columns: its nonzero entries (row, value).
    columns: Vec<Vec<(usize, f64)>>,
    q: &'a [f64],
    /// Whether zᵢ (rather than wᵢ) is the basic variable of pair i.
    z_basic: Vec<bool>,
    /// The pair with neither variable basic.
    open: usize,
}

impl Basis<'_> {
    /// The LU factors of K. None: faer found K singular, which in exact arithmetic it
    /// is not (every pivot passes the [`PIVOT_TOL`] test): round-off, as a false ray of
    /// the tableau is.
    fn factor(&self) -> Option<faer::sparse::linalg::solvers::Lu<usize, f64>> {
        let n = self.n;
        let mut t: Vec<Triplet<usize, usize, f64>> = Vec::new();
        for (i, column) in self.columns.iter().enumerate() {
            if self.z_basic[i] && i != self.open {
                t.extend(column.iter().map(|&(r, v)| Triplet::new(r, i, -v)));
            } else {
                t.push(Triplet::new(i, i, 1.0));
            }
        }
        t.extend((0..n).map(|r| Triplet::new(r, n, -1.0)));
        t.push(Triplet::new(n, self.open, 1.0));
        let k = SparseColMat::try_new_from_triplets(n + 1, n + 1, &t).ok()?;
        k.sp_lu().ok()
    }

    /// The column of the entering variable of the open pair (z or w), with a zero for
    /// K's last row.
    fn entering_column(&self, z: bool) -> Vec<f64> {
        let mut a = vec![0.0; self.n + 1];
        if z {
            for &(r, v) in &self.columns[self.open] {
                a[r] = -v;
            }
        } else {
            a[self.open] = 1.0;
        }
        a
    }
}

/// K x = rhs (Kᵀ x = rhs with `transpose`) by the factors `lu`: x.
fn solve(lu: &impl SolveCore<f64>, mut rhs: Vec<f64>, transpose: bool) -> Vec<f64> {
    let len = rhs.len();
    let b = MatMut::from_column_major_slice_mut(&mut rhs, len, 1);
    if transpose {
        lu.solve_transpose_in_place_with_conj(Conj::No, b);
    } else {
        lu.solve_in_place_with_conj(Conj::No, b);
    }
    rhs
}

/// Lemke's method on LCP(M, q) (`m` row-major, n × n), some qᵢ < 0: the z part of the
/// solution and the pivots taken, as the tableau method of [`super::lemke`] gives them.
pub(super) fn pivot_to_solution(
    m: &[f64],
    q: &[f64],
    max_pivots: usize,
) -> Result<(Vec<f64>, usize), LcpFailure> {
    let n = q.len();
    let mut columns = vec![Vec::new(); n];
    for (r, row) in m.chunks_exact(n).enumerate() {
        for (c, &v) in row.iter().enumerate() {
            if v != 0.0 {
                columns[c].push((r, v));
            }
        }
    }
    // z₀ enters and the most negative q leaves (ties: the lowest index), as in the
    // tableau; then the complement of the variable that left enters.
    let first = (0..n)
        .min_by(|&a, &b| q[a].total_cmp(&q[b]))
        .expect("n > 0 here");
    let mut basis = Basis {
        n,
        columns,
        q,
        z_basic: vec![false; n],
        open: first,
    };
    let mut entering_z = true;
    // Pivot 1 (z₀ in, w_first out) is the basis above; each pass takes the next one.
    for pivots in 2..=max_pivots {
        let ray = LcpFailure::Ray { pivots: pivots - 1 };
        let Some(lu) = basis.factor() else {
            return Err(ray);
        };
        let mut rhs = basis.q.to_vec();
        rhs.push(0.0);
        let x = solve(&lu, rhs, false);
        let d = solve(&lu, basis.entering_column(entering_z), false);
        if x.iter().chain(&d).any(|v| !v.is_finite()) {
            return Err(ray);
        }
        let leaving = ratio_test(&lu, &x, &d, basis.open).ok_or(ray)?;
        let theta = x[leaving] / d[leaving];
        let entered = basis.open;
        if leaving == n {
            // z₀ left: the entering variable takes the open pair, and the basis is a
            // solution.
            let mut z = vec![0.0; n];
            for i in (0..n).filter(|&i| basis.z_basic[i] && i != entered) {
                z[i] = (x[i] - theta * d[i]).max(0.0);
            }
            if entering_z {
                z[entered] = theta.max(0.0);
            }
            return Ok((z, pivots));
        }
        // The variable of pair `leaving` left: the entering one takes the open pair,
        // `leaving` becomes the open pair, and the complement of what left enters.
        basis.z_basic[entered] = entering_z;
        entering_z = !basis.z_basic[leaving];
        basis.open = leaving;
    }
    Err(LcpFailure::PivotLimit(max_pivots))
}

/// The unknown of K (a pair, or n for z₀) that leaves when the column `d` = K⁻¹a enters
/// with the basic values `x` = K⁻¹q: the least ratio xᵢ/dᵢ over dᵢ > 0, ties broken
/// lexicographically on the rows of B⁻¹ (the first n entries of K⁻ᵀeᵢ) and in favour
/// of z₀, as in the tableau method. None: no dᵢ > 0 (a ray).
fn ratio_test(lu: &impl SolveCore<f64>, x: &[f64], d: &[f64], open: usize) -> Option<usize> {
    let n = x.len() - 1;
    let scale = d.iter().fold(0.0_f64, |s, v| s.max(v.abs()));
    let candidates: Vec<usize> = (0..=n)
        .filter(|&i| i != open && d[i] > PIVOT_TOL * scale.max(1.0))
        .collect();
    let ratio = |i: usize| x[i] / d[i];
    let least = candidates
        .iter()
        .map(|&i| ratio(i))
        .fold(f64::INFINITY, f64::min);
    let tied = |a: f64, b: f64| (a - b).abs() <= 1e-12 * (1.0 + a.abs().max(b.abs()));
    let ties: Vec<usize> = candidates
        .into_iter()
        .filter(|&i| tied(ratio(i), least))
        .collect();
    match ties.as_slice() {
        [] => None,
        [only] => Some(*only),
        _ if ties.contains(&n) => Some(n),
        _ => {
            // Rows of B⁻¹ over dᵢ, compared entry by entry.
            let rows: Vec<Vec<f64>> = ties
                .iter()
                .map(|&i| {
                    let mut e = vec![0.0; n + 1];
                    e[i] = 1.0;
                    let row = solve(lu, e, true);
                    row[..n].iter().map(|v| v / d[i]).collect()
                })
                .collect();
            let mut best = 0;
            for c in 1..ties.len() {
                for k in 0..n {
                    let (a, b) = (rows[c][k], rows[best][k]);
                    if !tied(a, b) {
                        if a < b {
                            best = c;
                        }
                        break;
                    }
                }
            }
            Some(ties[best])
        }
    }
}
