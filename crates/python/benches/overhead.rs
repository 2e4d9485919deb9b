//! The Rust side of the Python overhead measurement (crates/python/tests/test_overhead.py
//! times the same call from Python): one `simulate` of the built-in Lire scene cut to
//! 10 steps (t_end = 0.1, Δt = 0.01), the trajectory kept in memory.
//!
//! `cargo bench -p rollstack-python --bench overhead`

use blockstack::scenes;
use blockstack::simulation::{simulate, RunOptions};
use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;

fn ten_steps(c: &mut Criterion) {
    let scene = scenes::find("lire")
        .and_then(blockstack::BuiltinScene::load)
        .expect("the built-in Lire scene")
        .scene;
    let options = RunOptions {
        t_end: Some(0.1),
        explore_branches: true,
        ..RunOptions::default()
    };
    c.bench_function("simulate lire, 10 steps", |b| {
        b.iter(|| {
            let mut records = Vec::new();
            let summary = simulate(black_box(&scene), &options, |r| records.push(r.clone()))
                .expect("a valid scene");
            black_box((summary, records))
        });
    });
}

criterion_group!(benches, ten_steps);
criterion_main!(benches);
