//! The transport of two touching cylinders (§3.6): 2000 steps of 2 ms at ϑ = 0.5, target
//! under 0.5 s. Two runs: the thesis's constant spin (steady from the first step) and a
//! smooth spin-up over 0.5 s (I pushes II through the mutual contact, I slips on the
//! floor, then the pair settles), which makes Newton work.
//!
//! `cargo bench -p cylinders --bench pair -- --quick`

use criterion::{criterion_group, criterion_main, Criterion};
use cylinders::studies::pair::{run_pair, PairSettings};
use cylinders::transport::SpinProfile;
use std::f64::consts::PI;
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("pair_transport");
    group.sample_size(10);
    let steady = PairSettings::thesis(0.5);
    group.bench_function("2000_steps_constant_spin", |b| {
        b.iter(|| run_pair(black_box(&steady), false).expect("runs"));
    });
    let ramp = PairSettings {
        spin: SpinProfile::ramp(-6.0 * PI, 0.5),
        ..PairSettings::thesis(0.5)
    };
    group.bench_function("2000_steps_spin_up", |b| {
        b.iter(|| run_pair(black_box(&ramp), false).expect("runs"));
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
