//! The linear solves of the Newton iteration behind one small trait.
//!
//! Dense LU for small systems, sparse LU for large ones (both faer; [`SparseLu`] keeps
//! what depends only on the sparsity pattern), [`MarkowitzLu`] (sparse elimination on
//! dense storage) for small systems that are mostly zeros, and [`BandLu`] (banded LU
//! after a bandwidth-reducing ordering) for the large matrices of chains; [`AutoSolver`]
//! switches at a size threshold (measured with the `nsga` bench `linear_solve`, see the
//! crate docs).

mod band;
mod markowitz;
mod sparse;
pub use band::{BandLu, MAX_BAND};
pub use markowitz::{
    MarkowitzLu, DENSE_VERDICT_UP_TO, MAX_UNKNOWNS as MARKOWITZ_MAX_UNKNOWNS, PIVOT_THRESHOLD,
};
pub use sparse::{SparseLu, SYMBOLIC_CACHE};

/// A linear solve failed (singular or non-finite matrix).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("linear solve failed: {0}")]
pub struct LinalgError(pub String);

/// Solves J x = b for a square J given as (row, col, value) triplets (duplicates summed).
pub trait LinearSolver: std::fmt::Debug + Send {
    /// Overwrites `rhs` with the solution of J x = rhs, J of size n × n.
    ///
    /// # Errors
    /// [`LinalgError`] when J is singular or the solution is not finite.
    fn solve(
        &mut self,
        n: usize,
        triplets: &[(usize, usize, f64)],
        rhs: &mut [f64],
    ) -> Result<(), LinalgError>;
    /// Overwrites `rhs` with the solution of J x = rhs for the J of the last successful
    /// [`LinearSolver::solve`], from its kept factors (a simplified Newton update).
    ///
    /// # Errors
    /// [`LinalgError`] when no factorization is kept (the default) or the solution is
    /// not finite.
    fn solve_again(&mut self, rhs: &mut [f64]) -> Result<(), LinalgError> {
        let _ = rhs;
        Err(LinalgError("no factorization kept".into()))
    }
    /// A short name for statistics ("dense", "markowitz", "band" or "sparse").
    fn name(&self) -> &'static str;
}

/// The ∞-norm max |xᵢ| of a residual, NaN when an entry is NaN: `f64::max` alone skips a
/// NaN, which let a residual of NaN entries read as converged.
///
/// It runs on every Newton iterate's residual: four lanes of maxima, because one running
/// maximum makes each entry wait for the last (a chain of dependent `max`es that cost
/// the Lire collapse about 3 % of its time). `max` is exact, so the lanes give the
/// one-accumulator value to the bit.
pub(crate) fn max_norm(v: &[f64]) -> f64 {
    let mut lanes = [0.0_f64; 4];
    let mut nan = false;
    let chunks = v.chunks_exact(4);
    let rest = chunks.remainder();
    for chunk in chunks {
        for (lane, x) in lanes.iter_mut().zip(chunk) {
            *lane = lane.max(x.abs());
            nan |= x.is_nan();
        }
    }
    for x in rest {
        lanes[0] = lanes[0].max(x.abs());
        nan |= x.is_nan();
    }
    if nan {
        f64::NAN
    } else {
        lanes.into_iter().fold(0.0, f64::max)
    }
}

/// Euclidean norm of a short slice.
pub(crate) fn norm(v: &[f64]) -> f64 {
    if let [x] = v {
        // √(x²) is |x| except where x² is subnormal or zero: a round-off slip of an
        // interval friction law (about 1e-160) then had a norm off by far more than an
        // ulp, its direction was not ±1, and the Jacobian's projector 1 − d² (exactly 0
        // for one component) became round-off over ‖v‖, entries of 1e150 that made the
        // Newton matrix singular (docs/method.md §7).
        return x.abs();
    }
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// An error naming the first triplet outside an n × n matrix, if any.
fn inside(n: usize, triplets: &[(usize, usize, f64)]) -> Result<(), LinalgError> {
    match triplets.iter().find(|&&(r, c, _)| r >= n || c >= n) {
        Some(&(r, c, _)) => Err(LinalgError(format!(
            "entry ({r}, {c}) outside a {n} × {n} matrix"
        ))),
        None => Ok(()),
    }
}

fn finite(rhs: &[f64], what: &str) -> Result<(), LinalgError> {
    if rhs.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(LinalgError(format!("non-finite solution ({what})")))
    }
}

/// Grows a faer scratch buffer to at least `bytes` (it is kept between solves).
fn grow_scratch(scratch: &mut Vec<std::mem::MaybeUninit<u8>>, bytes: usize) {
    if scratch.len() < bytes {
        scratch.resize(bytes, std::mem::MaybeUninit::new(0));
    }
}

/// Relative pivot size below which an LU reports the matrix as singular: a solve
/// through such a pivot returns round-off amplified by 1/pivot, not a Newton step.
///
/// Why 10⁻¹³: the eliminated entries carry round-off of ε ≈ 2.2·10⁻¹⁶ relative to the
/// largest, which a pivot of relative size p amplifies by 1/p: at 10⁻¹³ the update's
/// relative error is about 2·10⁻³, still a direction that contracts the residual (the
/// convergence test is on the residual, so an inexact update costs iterations, not
/// accuracy); much below, the update is round-off. The rows are equilibrated first
/// ([`equilibrate_rows`]), so the ratio measures the conditioning, not the units of
/// impulses against velocities.
pub const SINGULAR_PIVOT: f64 = 1e-13;

/// Equilibrates the rows of an n × n matrix (triplets) whose entries at the positions
/// `added` (ascending) were added to it: `scale` gets, per row, the power of two that
/// brings the row's largest entry *among the others* into [½, 1), and every entry of the
/// row is multiplied by it. Exact in floating point, so the solution of the scaled system
/// (right-hand side scaled alike) is unchanged; the relative [`SINGULAR_PIVOT`] test then
/// weighs each row against its own scale. A row without any other nonzero entry gets
/// scale 0: what was added cannot stand in for a row that the original matrix does not
/// have (a constraint that no unknown moves), so that matrix stays singular.
pub fn equilibrate_rows(
    n: usize,
    triplets: &mut [(usize, usize, f64)],
    added: &[usize],
    scale: &mut Vec<f64>,
) {
    scale.clear();
    scale.resize(n, 0.0);
    let mut skip = added.iter().peekable();
    for (i, &(r, _, v)) in triplets.iter().enumerate() {
        if skip.next_if_eq(&&i).is_none() {
            scale[r] = scale[r].max(v.abs());
        }
    }
    for s in scale.iter_mut() {
        *s = if *s > 0.0 && s.is_finite() {
            inverse_power_of_two(*s)
        } else if *s == 0.0 {
            0.0
        } else {
            1.0
        };
    }
    for t in triplets.iter_mut() {
        t.2 *= scale[t.0];
    }
}

/// 2^-(e+1) for a finite s = f·2^e > 0 with f ∈ [1, 2): the power of two that brings s
/// into [½, 1). Read from the exponent bits of a normal s (e = field − 1023, so the
/// result's field is 2045 − field): the same powers as `powi(−(⌊log2 s⌋ + 1))`, whose
/// libm calls took most of `equilibrate_rows`'s time on the matrix's pile rows. Subnormal
/// s, and results below the normal range, go through `powi`, which is exact there.
fn inverse_power_of_two(s: f64) -> f64 {
    let field = (s.to_bits() >> 52) & 0x7ff;
    if (1..=2044).contains(&field) {
        f64::from_bits((2045 - field) << 52)
    } else {
        let e = if field == 0 {
            // Subnormal: f·2^e with e below −1022.
            s.log2().floor() as i32
        } else {
            field as i32 - 1023
        };
        2.0_f64.powi(-(e + 1))
    }
}

/// Whether an LU's pivots pass the [`SINGULAR_PIVOT`] test: the least in magnitude above
/// that fraction of the largest. NaN pivots fail (`f64::min` would skip them); no pivots
/// (n = 0) pass.
fn regular_pivots(pivots: impl IntoIterator<Item = f64>) -> bool {
    let (mut lo, mut hi) = (f64::INFINITY, 0.0_f64);
    for p in pivots {
        if p.is_nan() {
            return false;
        }
        lo = lo.min(p.abs());
        hi = hi.max(p.abs());
    }
    lo > SINGULAR_PIVOT * hi
}

/// Dense LU with partial pivoting (faer's blocked kernel, sequential), with the
/// matrix, permutation and scratch buffers kept between solves.
#[derive(Debug, Clone)]
pub struct DenseLu {
    matrix: faer::Mat<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    scratch: Vec<std::mem::MaybeUninit<u8>>,
    /// Whether `matrix` holds the factors of a regular matrix.
    factored: bool,
    /// Substitution buffer.
    y: Vec<f64>,
}

impl Default for DenseLu {
    fn default() -> Self {
        Self {
            matrix: faer::Mat::zeros(0, 0),
            perm: Vec::new(),
            perm_inv: Vec::new(),
            scratch: Vec::new(),
            factored: false,
            y: Vec::new(),
        }
    }
}

impl LinearSolver for DenseLu {
    fn solve(
        &mut self,
        n: usize,
        triplets: &[(usize, usize, f64)],
        rhs: &mut [f64],
    ) -> Result<(), LinalgError> {
        use faer::dyn_stack::MemStack;
        use faer::linalg::lu::partial_pivoting::factor;
        let par = faer::Par::Seq;
        self.factored = false;
        if self.matrix.nrows() != n {
            self.matrix = faer::Mat::zeros(n, n);
            self.perm.resize(n, 0);
            self.perm_inv.resize(n, 0);
        } else {
            self.matrix.fill(0.0);
        }
        for &(r, c, v) in triplets {
            self.matrix[(r, c)] += v;
        }
        let req = factor::lu_in_place_scratch::<usize, f64>(n, n, par, faer::prelude::default());
        grow_scratch(&mut self.scratch, req.unaligned_bytes_required());
        factor::lu_in_place(
            self.matrix.as_mut(),
            &mut self.perm,
            &mut self.perm_inv,
            par,
            MemStack::new(&mut self.scratch),
            faer::prelude::default(),
        );
        let diag = self.matrix.as_ref().diagonal();
        if !regular_pivots((0..n).map(|i| diag[i])) {
            return Err(LinalgError("singular matrix (dense LU)".into()));
        }
        self.factored = true;
        self.solve_again(rhs)
    }
    /// P J = L U: b ← P b, then L and U by column-oriented substitution (one
    /// contiguous update per column, skipped where the solution entry is zero; faer's
    /// blocked triangular solves cost several times more for one right-hand side).
    fn solve_again(&mut self, rhs: &mut [f64]) -> Result<(), LinalgError> {
        if !self.factored {
            return Err(LinalgError("no factorization kept (dense LU)".into()));
        }
        let n = self.matrix.nrows();
        let y = &mut self.y;
        y.clear();
        y.extend(self.perm.iter().map(|&p| rhs[p]));
        for j in 0..n {
            let yj = y[j];
            if yj != 0.0 {
                let l = &self.matrix.col_as_slice(j)[j + 1..];
                y[j + 1..]
                    .iter_mut()
                    .zip(l)
                    .for_each(|(yi, lij)| *yi -= lij * yj);
            }
        }
        for j in (0..n).rev() {
            let u = self.matrix.col_as_slice(j);
            y[j] /= u[j];
            let xj = y[j];
            if xj != 0.0 {
                y[..j]
                    .iter_mut()
                    .zip(&u[..j])
                    .for_each(|(yi, uij)| *yi -= uij * xj);
            }
        }
        rhs[..n].copy_from_slice(y);
        finite(rhs, "dense LU")
    }
    fn name(&self) -> &'static str {
        "dense"
    }
}

/// The solver of [`AutoSolver`] for matrices up to its threshold.
#[derive(Debug, Clone)]
enum SmallLu {
    Dense(DenseLu),
    Markowitz(Box<MarkowitzLu>),
}

impl SmallLu {
    fn solver(&mut self) -> &mut dyn LinearSolver {
        match self {
            Self::Dense(s) => s,
            Self::Markowitz(s) => s.as_mut(),
        }
    }
}

/// The solver of [`AutoSolver`] for matrices above its threshold.
#[derive(Debug, Clone)]
enum LargeLu {
    Sparse(SparseLu),
    Band(BandLu),
}

impl LargeLu {
    fn solver(&mut self) -> &mut dyn LinearSolver {
        match self {
            Self::Sparse(s) => s,
            Self::Band(s) => s,
        }
    }

    fn name(&self) -> &'static str {
        match self {
            Self::Sparse(s) => s.name(),
            Self::Band(s) => s.name(),
        }
    }
}

/// Dense LU up to `threshold` unknowns and faer's sparse LU above ([`AutoSolver::new`]),
/// or Markowitz LU up to `threshold` and banded LU above ([`AutoSolver::markowitz`]).
#[derive(Debug, Clone)]
pub struct AutoSolver {
    /// Largest size solved by the small-matrix solver.
    pub threshold: usize,
    small: SmallLu,
    large: LargeLu,
    last_small: bool,
}

/// Default dense/sparse crossover (unknowns). Measured with
/// `cargo bench -p nsga --bench nsga -- --quick linear_solve` on Newton matrices of the
/// chain (symbolic analysis cached): dense 4.6 µs vs sparse 5.2 µs at 22 unknowns,
/// 14.4 µs vs 6.4 µs at 44, 56 µs vs 18 µs at 88. 40 sits near the crossover.
pub const DEFAULT_SPARSE_THRESHOLD: usize = 40;

/// Default Markowitz/sparse crossover (unknowns) of [`SolverChoice::Markowitz`], the
/// stepper's default solver. Measured like [`DEFAULT_SPARSE_THRESHOLD`]: Markowitz LU
/// 1.1 µs vs dense 2.7 µs at 22 unknowns, 11 µs vs 48 µs (sparse 20 µs) at 88, 27 µs vs
/// sparse 40 µs at 176, even with sparse LU at 264 (58 µs vs 57 µs), 183 µs vs 95 µs
/// at 440.
///
/// [`SolverChoice::Markowitz`]: crate::SolverChoice::Markowitz
pub const MARKOWITZ_SPARSE_THRESHOLD: usize = 256;

impl AutoSolver {
    /// A solver switching from dense to sparse LU above `threshold` unknowns.
    #[must_use]
    pub fn new(threshold: usize) -> Self {
        Self {
            threshold,
            small: SmallLu::Dense(DenseLu::default()),
            large: LargeLu::Sparse(SparseLu::default()),
            last_small: true,
        }
    }
    /// A solver switching from [`MarkowitzLu`] to [`BandLu`] above `threshold` unknowns
    /// (at most [`MARKOWITZ_MAX_UNKNOWNS`]).
    #[must_use]
    pub fn markowitz(threshold: usize) -> Self {
        Self {
            small: SmallLu::Markowitz(Box::default()),
            large: LargeLu::Band(BandLu::default()),
            ..Self::new(threshold.min(MARKOWITZ_MAX_UNKNOWNS))
        }
    }
    /// The same solver with [`MarkowitzLu`]'s pivot test at `threshold` (see
    /// [`MarkowitzLu::with_threshold`]; no effect on dense LU).
    #[must_use]
    pub fn with_pivot_threshold(mut self, threshold: f64) -> Self {
        if let SmallLu::Markowitz(_) = self.small {
            self.small = SmallLu::Markowitz(Box::new(MarkowitzLu::with_threshold(threshold)));
        }
        self
    }
    /// The same solver with its large-matrix solver keeping `sizes` matrix sizes (see
    /// [`SparseLu::keeping`], [`BandLu::keeping`]).
    #[must_use]
    pub fn keeping(mut self, sizes: usize) -> Self {
        self.large = match self.large {
            LargeLu::Sparse(_) => LargeLu::Sparse(SparseLu::keeping(sizes)),
            LargeLu::Band(_) => LargeLu::Band(BandLu::keeping(sizes)),
        };
        self
    }
}

impl Default for AutoSolver {
    fn default() -> Self {
        Self::new(DEFAULT_SPARSE_THRESHOLD)
    }
}

impl LinearSolver for AutoSolver {
    fn solve(
        &mut self,
        n: usize,
        triplets: &[(usize, usize, f64)],
        rhs: &mut [f64],
    ) -> Result<(), LinalgError> {
        self.last_small = n <= self.threshold;
        if self.last_small {
            self.small.solver().solve(n, triplets, rhs)
        } else {
            self.large.solver().solve(n, triplets, rhs)
        }
    }
    fn solve_again(&mut self, rhs: &mut [f64]) -> Result<(), LinalgError> {
        if self.last_small {
            self.small.solver().solve_again(rhs)
        } else {
            self.large.solver().solve_again(rhs)
        }
    }
    fn name(&self) -> &'static str {
        match (&self.small, self.last_small) {
            (_, false) => self.large.name(),
            (SmallLu::Dense(s), true) => s.name(),
            (SmallLu::Markowitz(s), true) => s.name(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The row scale brings every finite positive entry into [½, 1) with a power of two,
    /// from the exponent bits: checked against halving and doubling one at a time (exact
    /// in the normal range), across the exponent range, on entries an ulp below powers
    /// of two, and on the largest subnormals.
    #[test]
    fn the_row_scale_is_the_power_of_two_into_half_to_one() {
        let by_steps = |s: f64| {
            let mut k = 1.0_f64;
            while s * k >= 1.0 {
                k *= 0.5;
            }
            while s * k < 0.5 {
                k *= 2.0;
            }
            k
        };
        let mut entries = vec![1.0, 0.5, 3.0, 1e-300, 1e300, f64::MIN_POSITIVE];
        for e in -1020..1020 {
            let p = 2.0_f64.powi(e);
            entries.extend([p, f64::from_bits(p.to_bits() - 1), 1.37 * p]);
        }
        for s in entries {
            let k = inverse_power_of_two(s);
            assert_eq!(k.to_bits(), by_steps(s).to_bits(), "{s:e}");
            assert!((0.5..1.0).contains(&(s * k)), "{s:e}");
        }
        // Subnormal entries of exponents −1023 and −1024 (below, 2^-(e+1) overflows).
        for s in [f64::MIN_POSITIVE * 0.75, f64::MIN_POSITIVE * 0.3] {
            assert!((0.5..1.0).contains(&(s * inverse_power_of_two(s))), "{s:e}");
        }
    }

    #[test]
    fn max_norm_is_the_largest_magnitude_or_nan() {
        let v: Vec<f64> = (0..11).map(|i| f64::from(i * 7 % 11) - 5.5).collect();
        for len in 0..=v.len() {
            let one_by_one = v[..len].iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            assert_eq!(max_norm(&v[..len]).to_bits(), one_by_one.to_bits());
            let mut with_nan = v[..len].to_vec();
            with_nan.push(f64::NAN);
            with_nan.rotate_right(len / 2 + 1);
            assert!(
                max_norm(&with_nan).is_nan(),
                "NaN at {} of {}",
                len / 2,
                len + 1
            );
        }
        assert_eq!(max_norm(&[-0.0]).to_bits(), 0.0_f64.to_bits());
    }

    #[test]
    fn dense_and_sparse_agree_with_duplicates() {
        // Tridiagonal 30×30 with the diagonal given in two halves.
        let n = 30;
        let mut t = Vec::new();
        for i in 0..n {
            t.push((i, i, 2.0));
            t.push((i, i, 2.0));
            if i + 1 < n {
                t.push((i, i + 1, -1.0));
                t.push((i + 1, i, -1.5));
            }
        }
        let b: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
        let mut x1 = b.clone();
        let mut x2 = b.clone();
        DenseLu::default().solve(n, &t, &mut x1).unwrap();
        SparseLu::default().solve(n, &t, &mut x2).unwrap();
        for i in 0..n {
            assert!((x1[i] - x2[i]).abs() < 1e-12);
        }
    }

    #[test]
    fn kept_factors_solve_again_like_a_new_solve() {
        let t = vec![(0, 0, 4.0), (0, 1, 1.0), (1, 0, 2.0), (1, 1, 3.0)];
        let solvers: [Box<dyn LinearSolver>; 3] = [
            Box::new(DenseLu::default()),
            Box::new(SparseLu::default()),
            Box::new(AutoSolver::new(1)),
        ];
        for mut s in solvers {
            let mut none = vec![1.0, 1.0];
            assert!(s.solve_again(&mut none).is_err(), "nothing factored yet");
            s.solve(2, &t, &mut [1.0, 0.0]).unwrap();
            let mut x = vec![3.0, -1.0];
            s.solve_again(&mut x).unwrap();
            // 4x + y = 3, 2x + 3y = −1: x = 1, y = −1.
            assert!((x[0] - 1.0).abs() < 1e-14 && (x[1] + 1.0).abs() < 1e-14);
        }
        // Row pivoting: a zero leading entry.
        let p = vec![
            (0, 1, 2.0),
            (0, 2, 1.0),
            (1, 0, 1.0),
            (1, 2, 3.0),
            (2, 0, 4.0),
            (2, 1, 1.0),
            (2, 2, 1.0),
        ];
        let exact = [1.0, -2.0, 3.0];
        let mut b = vec![-1.0, 10.0, 5.0];
        let mut d = DenseLu::default();
        d.solve(3, &p, &mut b).unwrap();
        let mut again = vec![-1.0, 10.0, 5.0];
        d.solve_again(&mut again).unwrap();
        for ((x, y), e) in b.iter().zip(&again).zip(exact) {
            assert!((x - e).abs() < 1e-14 && (y - e).abs() < 1e-14);
        }
        // A singular matrix leaves nothing to solve again with.
        let mut d = DenseLu::default();
        d.solve(2, &t, &mut [1.0, 0.0]).unwrap();
        let singular = vec![(0, 0, 1.0), (0, 1, 1.0), (1, 0, 1.0), (1, 1, 1.0)];
        assert!(d.solve(2, &singular, &mut [1.0, 2.0]).is_err());
        assert!(d.solve_again(&mut [1.0, 2.0]).is_err());
    }

    #[test]
    fn a_nan_entry_makes_the_max_norm_nan() {
        assert_eq!(max_norm(&[1.0, -3.0, 2.0]), 3.0);
        assert!(max_norm(&[1.0, f64::NAN, 2.0]).is_nan());
        assert!(max_norm(&[f64::NAN, 0.0]).is_nan());
        assert_eq!(max_norm(&[]), 0.0);
    }

    #[test]
    fn singular_is_an_error() {
        let t = vec![(0, 0, 1.0), (0, 1, 1.0), (1, 0, 1.0), (1, 1, 1.0)];
        let mut b = vec![1.0, 2.0];
        assert!(DenseLu::default().solve(2, &t, &mut b).is_err());
        let mut b = vec![1.0, 2.0];
        assert!(SparseLu::default().solve(2, &t, &mut b).is_err());
    }

    #[test]
    fn equilibrated_rows_pass_the_singular_test_only_where_the_matrix_has_them() {
        // Rows of scales 1e3 and 1e-3 (as the κ and λ rows of a step at small Δt), two
        // redundant λ rows regularized by ε·1e-3 at positions 3 and 6: unscaled, the
        // regularized pivots fall below SINGULAR_PIVOT; equilibrated, they pass and the
        // solution is that of the unscaled system.
        let eps = 1e-8;
        let reg = vec![
            (0, 0, 1e3),
            (1, 1, 1e-3),
            (1, 2, 1e-3),
            (1, 1, eps * 1e-3),
            (2, 1, 1e-3),
            (2, 2, 1e-3),
            (2, 2, eps * 1e-3),
        ];
        let added = [3, 6];
        let rhs = [1e3, 2e-3, 2e-3];
        let mut b = rhs.to_vec();
        assert!(DenseLu::default().solve(3, &reg, &mut b).is_err());
        let (mut t, mut scale) = (reg.clone(), Vec::new());
        equilibrate_rows(3, &mut t, &added, &mut scale);
        assert!(scale.iter().all(|s| s.log2().fract() == 0.0), "{scale:?}");
        let mut b: Vec<f64> = rhs.iter().zip(&scale).map(|(r, s)| r * s).collect();
        DenseLu::default().solve(3, &t, &mut b).unwrap();
        // The least-norm share of the redundant pair: x₁ = x₂ ≈ 1.
        assert!((b[0] - 1.0).abs() < 1e-12, "{b:?}");
        assert!(
            (b[1] - 1.0).abs() < 1e-6 && (b[2] - 1.0).abs() < 1e-6,
            "{b:?}"
        );
        // A row made of added entries only is a row the matrix does not have: it is
        // zeroed, and the matrix stays singular.
        let mut t = vec![(0, 0, 1.0), (1, 1, eps)];
        equilibrate_rows(2, &mut t, &[1], &mut scale);
        assert_eq!(scale, [0.5, 0.0]);
        let mut b = vec![0.5, 0.0];
        assert!(DenseLu::default().solve(2, &t, &mut b).is_err());
    }
}
