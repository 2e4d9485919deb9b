//! Criterion benches of the solver core: one step, a whole ball run, step cost against
//! the size of a chain, the dense/sparse LU crossover, and Lemke's method on its
//! tableau against on factors of its basis.
//!
//! `cargo bench -p nsga --bench nsga -- --quick`

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use nsga::lcp::{lemke_with, Pivoting};
use nsga::studies::ball::{run_ball, Scheme};
use nsga::systems::ball::BallCase;
use nsga::systems::chain::Chain;
use nsga::{
    BandLu, DenseLu, IndexSets, LinearOptions, LinearSolver, MarkowitzLu, Options, Prox,
    SolverChoice, SparseLu, Stepper,
};
use std::hint::black_box;

fn one_step(c: &mut Criterion) {
    let case = BallCase::new(2).unwrap();
    let mut s = Stepper::new(case.ball, 0.0, &case.q0, &case.u0, Options::default()).unwrap();
    // Into the sliding phase (impact at 0.43 s, rolling from 0.73 s).
    s.run(300, |_, _| {}).unwrap();
    let saved = s.state().clone();
    c.bench_function("ball_one_step_sliding", |b| {
        b.iter(|| {
            s.set_state(saved.clone());
            black_box(s.step().unwrap().iterations)
        });
    });
}

fn ball_run(c: &mut Criterion) {
    let mut g = c.benchmark_group("ball_run");
    for case in [1u8, 2] {
        let bc = BallCase::new(case).unwrap();
        g.bench_with_input(BenchmarkId::new("nsga_case", case), &bc, |b, bc| {
            b.iter(|| {
                black_box(
                    run_ball(bc, Scheme::Nsga, 2e-3, 0.5, Prox::Scaled(1.0))
                        .unwrap()
                        .min_gap,
                )
            });
        });
        g.bench_with_input(BenchmarkId::new("moreau_case", case), &bc, |b, bc| {
            b.iter(|| {
                black_box(
                    run_ball(bc, Scheme::Moreau, 2e-3, 0.5, Prox::Scaled(1.0))
                        .unwrap()
                        .min_gap,
                )
            });
        });
    }
    g.finish();
}

fn chain_scaling(c: &mut Criterion) {
    let mut g = c.benchmark_group("chain_step");
    g.sample_size(10);
    for n in [10usize, 30, 100, 300, 1000] {
        let chain = Chain::benchmark(n);
        let (q0, u0) = chain.resting(1.0);
        let mut s = Stepper::new(chain, 0.0, &q0, &u0, Options::default()).unwrap();
        s.run(2, |_, _| {}).unwrap();
        // Start Newton from zero unknowns, so that every size iterates (the previous
        // step's unknowns would already solve this smooth step).
        let mut saved = s.state().clone();
        saved.x.iter_mut().for_each(|v| *v = 0.0);
        g.bench_with_input(BenchmarkId::new("blocks", n), &n, |b, _| {
            b.iter(|| {
                s.set_state(saved.clone());
                black_box(s.step().unwrap().iterations)
            });
        });
    }
    g.finish();
}

fn linear_solve(c: &mut Criterion) {
    let mut g = c.benchmark_group("linear_solve");
    for n in [2usize, 4, 8, 12, 16, 24, 40, 100] {
        let chain = Chain::benchmark(n);
        let (q0, u0) = chain.resting(1.0);
        let opts = Options {
            linear: LinearOptions {
                solver: SolverChoice::Dense,
                ..LinearOptions::default()
            },
            ..Options::default()
        };
        let mut s = Stepper::new(chain, 0.0, &q0, &u0, opts).unwrap();
        let x = s.state().x.clone();
        let sets: IndexSets = s.sets_of(&x, 0.5);
        let (r, j) = s.newton_system(&x, &sets, 0.5, true);
        let size = r.len();
        let mut trip = Vec::new();
        for col in 0..size {
            for row in 0..size {
                if j[(row, col)] != 0.0 {
                    trip.push((row, col, j[(row, col)]));
                }
            }
        }
        let rhs: Vec<f64> = (0..size).map(|i| 1.0 + i as f64 * 1e-3).collect();
        g.bench_with_input(BenchmarkId::new("dense", size), &size, |b, _| {
            b.iter(|| {
                let mut v = rhs.clone();
                DenseLu::default().solve(size, &trip, &mut v).unwrap();
                black_box(v[0])
            });
        });
        let mut mk = MarkowitzLu::default();
        g.bench_with_input(BenchmarkId::new("markowitz", size), &size, |b, _| {
            b.iter(|| {
                let mut v = rhs.clone();
                mk.solve(size, &trip, &mut v).unwrap();
                black_box(v[0])
            });
        });
        let mut sp = SparseLu::default();
        g.bench_with_input(BenchmarkId::new("sparse", size), &size, |b, _| {
            b.iter(|| {
                let mut v = rhs.clone();
                sp.solve(size, &trip, &mut v).unwrap();
                black_box(v[0])
            });
        });
        let mut band = BandLu::default();
        g.bench_with_input(BenchmarkId::new("band", size), &size, |b, _| {
            b.iter(|| {
                let mut v = rhs.clone();
                band.solve(size, &trip, &mut v).unwrap();
                black_box(v[0])
            });
        });
    }
    g.finish();
}

/// The LCP of a chain pressed together (M tridiagonal: 2 on the diagonal, −1 beside it),
/// two contacts in three pushed: Lemke's method takes n + 1 pivots, and the tableau's
/// B⁻¹ fills in.
fn chain_lcp(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut m = vec![0.0; n * n];
    for i in 0..n {
        m[i * n + i] = 2.0;
        if i > 0 {
            m[i * n + i - 1] = -1.0;
            m[(i - 1) * n + i] = -1.0;
        }
    }
    let q = (0..n)
        .map(|i| {
            if i % 3 == 0 {
                1.0
            } else {
                -1.0 - i as f64 * 1e-3
            }
        })
        .collect();
    (m, q)
}

fn lemke_pivoting(c: &mut Criterion) {
    let mut g = c.benchmark_group("lemke_pivoting");
    g.sample_size(10);
    for n in [200usize, 400, 800, 1600] {
        let (m, q) = chain_lcp(n);
        for (name, pivoting) in [
            ("tableau", Pivoting::Tableau),
            ("factored_basis", Pivoting::FactoredBasis),
        ] {
            g.bench_with_input(BenchmarkId::new(name, n), &n, |b, _| {
                b.iter(|| black_box(lemke_with(pivoting, &m, &q, 50 * n).unwrap().pivots));
            });
        }
    }
    g.finish();
}

criterion_group!(
    benches,
    one_step,
    ball_run,
    chain_scaling,
    linear_solve,
    lemke_pivoting
);
criterion_main!(benches);
