//! Cost of the conversions the planners call in their inner loops.

use criterion::{criterion_group, criterion_main, Criterion};
use rotations::{compound, AxisAngle, EulerSet, Vector3};
use std::hint::black_box;

fn conversions(c: &mut Criterion) {
    let r = AxisAngle::new(1.1, Vector3::new(0.3, -0.5, 0.8))
        .unwrap()
        .to_rotation();
    let set = EulerSet::from_name("3-2-1").unwrap();
    c.bench_function("euler_angles_3-2-1", |b| {
        b.iter(|| set.angles(black_box(&r)));
    });
    c.bench_function("euler_rotation_3-2-1", |b| {
        b.iter(|| set.rotation(black_box([0.2, -0.4, 1.0])));
    });
    c.bench_function("axis_angle_from_rotation", |b| {
        b.iter(|| AxisAngle::from_rotation(black_box(&r)));
    });
    let q = AxisAngle::from_rotation(&r).to_quaternion();
    c.bench_function("compound_quaternion", |b| {
        b.iter(|| compound(black_box(&q), black_box(&q)));
    });
}

criterion_group!(benches, conversions);
criterion_main!(benches);
