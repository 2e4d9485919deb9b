//! The Frobenius test of the nine rolling constraints of a touching pair (12 coordinates,
//! 9 constraints): target under 1 ms. Also the pieces: W alone, and the skew matrices.
//!
//! `cargo bench -p cylinders --bench frobenius -- --quick`

use criterion::{criterion_group, criterion_main, Criterion};
use cylinders::frobenius::{frobenius_test, skew_matrices, PfaffianSystem};
use cylinders::kinematics::Cylinder;
use cylinders::pair::{CylinderPair, PairConstraints, PairSystem, SingleCylinder};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let pair = CylinderPair::identical(Cylinder::gas_cylinder());
    let q = pair
        .generic_configuration(0.4, 0.3, 0.5)
        .expect("valid configuration");
    let nine = PairSystem {
        pair,
        constraints: PairConstraints::Nine,
    };
    c.bench_function("frobenius_pair9_12x9", |b| {
        b.iter(|| frobenius_test(black_box(&nine), black_box(&q)));
    });
    c.bench_function("skew_matrices_pair9", |b| {
        b.iter(|| skew_matrices(black_box(&nine), black_box(&q)));
    });
    c.bench_function("constraint_matrix_pair9", |b| {
        b.iter(|| nine.constraint_matrix(black_box(&q[..])));
    });
    let single = SingleCylinder {
        cylinder: Cylinder::gas_cylinder(),
    };
    let q6 = [0.1, 0.2, 0.7, 0.4, 0.5, 0.3];
    c.bench_function("frobenius_single_6x3", |b| {
        b.iter(|| frobenius_test(black_box(&single), black_box(&q6)));
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
