//! Tests of the Markowitz LU: against dense LU, on reuse, fill, singular and oversized input.

use super::*;

/// A deterministic pseudo-random sequence in [−1, 1).
fn lcg(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6_364_136_223_846_793_005)
        .wrapping_add(1_442_695_040_888_963_407);
    // The top 53 bits as a fraction.
    #[allow(clippy::cast_precision_loss)]
    let f = (*seed >> 11) as f64 / (1u64 << 53) as f64;
    2.0 * f - 1.0
}

/// A sparse matrix with a strong diagonal block (like the mass blocks of eq. 143)
/// and coupling rows and columns, of size n, as triplets with duplicates.
fn saddle(n: usize, seed: u64) -> Vec<(usize, usize, f64)> {
    let mut s = seed;
    let mut t = Vec::new();
    let m = n.div_ceil(2);
    for i in 0..m {
        t.push((i, i, 2.0 + lcg(&mut s)));
    }
    for i in 0..n {
        for _ in 0..3 {
            let j = ((lcg(&mut s) + 1.0) * 0.5 * n as f64) as usize % n;
            t.push((i, j, lcg(&mut s)));
            t.push((j, i, lcg(&mut s)));
        }
    }
    // Multiplier rows with a zero diagonal: pivoting must look elsewhere.
    for i in m..n {
        t.push((i, i % m, 1.0));
        t.push((i % m, i, -1.0));
    }
    t
}

fn residual(n: usize, t: &[(usize, usize, f64)], x: &[f64], b: &[f64]) -> f64 {
    let mut r = b.to_vec();
    for &(i, j, v) in t {
        r[i] -= v * x[j];
    }
    r.iter().fold(0.0_f64, |m, v| m.max(v.abs())) / n as f64
}

#[test]
fn agrees_with_dense_lu_on_sparse_matrices() {
    for (n, seed) in [
        (1, 1),
        (5, 2),
        (40, 3),
        (63, 4),
        (64, 5),
        (65, 6),
        (150, 7),
        (200, 8),
        (256, 10),
        (300, 11),
        (MAX_UNKNOWNS, 9),
    ] {
        let t = saddle(n, seed);
        let mut s = seed + 100;
        let b: Vec<f64> = (0..n).map(|_| lcg(&mut s)).collect();
        let (mut xd, mut xm) = (b.clone(), b.clone());
        DenseLu::default().solve(n, &t, &mut xd).unwrap();
        let mut lu = MarkowitzLu::default();
        lu.solve(n, &t, &mut xm).unwrap();
        assert!(residual(n, &t, &xm, &b) < 1e-12, "n = {n}");
        let diff = xd
            .iter()
            .zip(&xm)
            .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
        let size = xd.iter().fold(0.0_f64, |m, a| m.max(a.abs()));
        assert!(diff <= 1e-9 * size, "n = {n}: {diff} vs {size}");
        // The kept factors solve another right-hand side.
        let c: Vec<f64> = (0..n).map(|_| lcg(&mut s)).collect();
        let (mut yd, mut ym) = (c.clone(), c.clone());
        DenseLu::default().solve(n, &t, &mut yd).unwrap();
        lu.solve_again(&mut ym).unwrap();
        assert!(residual(n, &t, &ym, &c) < 1e-12, "n = {n}");
    }
}

#[test]
fn a_reused_solver_solves_like_a_fresh_one() {
    // The storage is zeroed entry by entry, not per matrix: sizes that shrink and grow,
    // a singular matrix and bad input in between must leave nothing behind.
    let mut reused = MarkowitzLu::default();
    let mut b = vec![1.0; 2];
    let cancelled = [(0, 0, 1.0), (0, 1, 1.0), (1, 0, 1.0), (1, 1, 1.0 + 1e-16)];
    for (k, (n, seed)) in [(150, 7), (5, 2), (64, 5), (40, 3), (65, 6), (1, 1), (63, 4)]
        .into_iter()
        .enumerate()
    {
        let t = saddle(n, seed);
        let x: Vec<f64> = (0..n).map(|i| i as f64).collect();
        let (mut fresh, mut again) = (x.clone(), x);
        MarkowitzLu::default().solve(n, &t, &mut fresh).unwrap();
        reused.solve(n, &t, &mut again).unwrap();
        assert_eq!(fresh, again, "n = {n}");
        if k % 2 == 0 {
            assert!(reused.solve(2, &cancelled, &mut b).is_err());
        } else {
            assert!(reused
                .solve(2, &[(0, 0, 1.0), (5, 0, 1.0)], &mut b)
                .is_err());
        }
    }
}

#[test]
fn every_factorization_leaves_the_storage_zeroed() {
    // A whole elimination zeroes each entry as its pivot row or column retires; one that
    // stops (a column without entries, a pivot too small, the retry with partial
    // pivoting above the dense verdict's size) clears what it left.
    let mut lu = MarkowitzLu::default();
    let empty_column = [(0, 0, 1.0), (1, 0, 2.0), (2, 2, 1.0)];
    let cancelled = [(0, 0, 1.0), (0, 1, 1.0), (1, 0, 1.0), (1, 1, 1.0 + 1e-16)];
    for (n, t) in [
        (150, saddle(150, 7)),
        (3, empty_column.to_vec()),
        (64, saddle(64, 5)),
        (2, cancelled.to_vec()),
        (300, saddle(300, 9)),
    ] {
        let mut b = vec![1.0; n];
        let _ = lu.solve(n, &t, &mut b);
        assert!(lu.a.iter().all(|&v| v == 0.0), "n = {n}");
    }
}

#[test]
fn fill_is_followed() {
    // An arrow matrix eliminated from its dense corner fills completely; the
    // solution must still be exact.
    let n = 70;
    let mut t = vec![(0, 0, 1.0)];
    for i in 1..n {
        t.push((0, i, 1.0));
        t.push((i, 0, 1.0));
        t.push((i, i, 3.0));
    }
    let b: Vec<f64> = (0..n).map(|i| i as f64).collect();
    let mut x = b.clone();
    MarkowitzLu::default().solve(n, &t, &mut x).unwrap();
    assert!(residual(n, &t, &x, &b) < 1e-13);
}

#[test]
fn singular_matrices_are_errors() {
    let mut lu = MarkowitzLu::default();
    let mut b = vec![1.0, 1.0];
    assert!(lu.solve_again(&mut b).is_err(), "nothing factorized yet");
    // An empty column.
    assert!(lu.solve(2, &[(0, 0, 1.0), (1, 0, 2.0)], &mut b).is_err());
    // Dependent rows whose entries cancel to round-off.
    let t = [(0, 0, 1.0), (0, 1, 1.0), (1, 0, 1.0), (1, 1, 1.0 + 1e-16)];
    assert!(lu.solve(2, &t, &mut b).is_err());
    assert!(
        lu.solve_again(&mut b).is_err(),
        "singular factors are not kept"
    );
    // Entries that sum to zero are not in the pattern.
    let t = [(0, 0, 1.0), (1, 1, 1.0), (1, 1, -1.0)];
    assert!(lu.solve(2, &t, &mut b).is_err());
    assert!(lu.solve(2, &[(2, 0, 1.0)], &mut b).is_err(), "outside");
}

#[test]
fn an_entry_outside_leaves_no_values_behind() {
    let mut lu = MarkowitzLu::default();
    let mut b = vec![1.0, 1.0];
    // The entries before the one outside were written, and must be undone.
    let bad = [(0, 0, 1.0), (1, 1, 1.0), (0, 1, 5.0), (2, 0, 1.0)];
    let err = lu.solve(2, &bad, &mut b).unwrap_err();
    assert!(err.0.contains("outside"), "{}", err.0);
    let mut x = vec![2.0, 4.0];
    lu.solve(2, &[(0, 0, 2.0), (1, 1, 4.0)], &mut x).unwrap();
    assert_eq!(x, [1.0, 1.0]);
}

#[test]
fn too_many_unknowns_are_an_error_not_an_allocation() {
    let n = super::MAX_UNKNOWNS + 1;
    let mut b = vec![1.0; n];
    let err = MarkowitzLu::default()
        .solve(n, &[(0, 0, 1.0)], &mut b)
        .unwrap_err();
    assert!(err.0.contains("at most"), "{}", err.0);
    // The automatic choice hands such sizes to sparse LU instead.
    let t: Vec<_> = (0..n).map(|i| (i, i, 2.0)).collect();
    crate::AutoSolver::markowitz(usize::MAX)
        .solve(n, &t, &mut b)
        .unwrap();
    assert!(b.iter().all(|&x| (x - 0.5).abs() < 1e-15));
}

/// Above [`DENSE_VERDICT_UP_TO`] unknowns a matrix the threshold pivots leave
/// numerically singular is factored again with partial pivoting, without dense LU:
/// a singular one (two equal rows) is an error from that factorization, and the
/// partial-pivoting factors of a regular one solve it as dense LU does.
#[test]
fn above_the_dense_verdict_size_partial_pivoting_decides() {
    let n = DENSE_VERDICT_UP_TO + 50;
    let regular = saddle(n, 12);
    let mut equal_rows: Vec<_> = regular.iter().copied().filter(|t| t.0 != 1).collect();
    equal_rows.extend(
        regular
            .iter()
            .filter(|t| t.0 == 0)
            .map(|&(_, c, v)| (1, c, v)),
    );
    let mut lu = MarkowitzLu::default();
    let mut b = vec![1.0; n];
    let err = lu.solve(n, &equal_rows, &mut b).unwrap_err();
    assert!(err.0.contains("partial pivoting"), "{}", err.0);
    assert!(!lu.by_dense);
    assert!(
        lu.solve_again(&mut b).is_err(),
        "singular factors are not kept"
    );

    let mut s = 7;
    let b: Vec<f64> = (0..n).map(|_| lcg(&mut s)).collect();
    lu.size_for(n);
    lu.load_and_factor_any(&regular, 1.0).unwrap().unwrap();
    lu.factored = true;
    let mut x = b.clone();
    lu.solve_again(&mut x).unwrap();
    assert!(residual(n, &regular, &x, &b) < 1e-12);
    let mut xd = b.clone();
    DenseLu::default().solve(n, &regular, &mut xd).unwrap();
    let diff = x
        .iter()
        .zip(&xd)
        .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(diff <= 1e-9 * xd.iter().fold(0.0_f64, |m, a| m.max(a.abs())));
}

/// A column the elimination leaves without entries is singular whatever the values
/// (here the third: rows 0 and 1 hold it, and they are pivoted on the first two
/// columns; row 2's only entry, a regularization slot at 0, leaves the pattern), and
/// it is reported without the dense LU that numerical singularity asks.
#[test]
fn a_column_left_without_entries_is_singular_at_once() {
    let t = [
        (0, 0, 2.0),
        (1, 1, 3.0),
        (0, 2, 1.0),
        (1, 2, 1.0),
        (2, 2, 0.0),
    ];
    let mut lu = MarkowitzLu::default();
    let mut b = vec![1.0; 3];
    let err = lu.solve(3, &t, &mut b).unwrap_err();
    assert!(err.0.contains("without entries"), "{}", err.0);
    assert!(!lu.by_dense);
    // Dense LU agrees (row 2 is zero).
    let mut b = vec![1.0; 3];
    assert!(DenseLu::default().solve(3, &t, &mut b).is_err());
    // A numerically zero column (entries that cancel) is still left to dense LU.
    let cancelling = [(0, 0, 1.0), (1, 0, 1.0), (0, 1, 1.0), (1, 1, 1.0)];
    assert!(lu.solve(2, &cancelling, &mut b).is_err());
    assert!(lu.by_dense);
}
