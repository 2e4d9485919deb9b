//! Cost of evaluating every contact of a scene once (what a stepper does per Newton
//! iterate): the Lire tower, and resting columns of 10, 100 and 1000 blocks.

use blockstack::scenarios::{lire_on_floor, Perturbation};
use blockstack::scene::{ContactParams, SolverParams};
use blockstack::{Base, BaseMotion, Block, Floor, Scene, StackContacts};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use std::hint::black_box;

fn column(n: usize) -> Scene {
    let base = Base::new(1.0, 0.1, BaseMotion::Fixed).unwrap();
    let block = Block::new(0.2, 0.4, 1.0).unwrap();
    let blocks = blockstack::scene::stack_on(&base, &vec![(block, 0.0, 0.0); n]).unwrap();
    let floor = Some(Floor::new(base.bottom()));
    Scene::new(
        base,
        blocks,
        floor,
        ContactParams {
            mu: 0.2,
            e_n: 0.0,
            e_f: 0.0,
        },
        SolverParams::default(),
    )
    .unwrap()
}

fn bench(c: &mut Criterion) {
    // With the floor: the interface and the floor rows.
    let scene = lire_on_floor(4, Perturbation::Bottom).unwrap();
    let q = scene.initial_coordinates();
    let u = vec![0.01; q.len()];
    let mut out = StackContacts::default();
    c.bench_function("contacts/lire4", |b| {
        b.iter(|| {
            scene.contacts_into(black_box(0.3), black_box(&q), black_box(&u), &mut out);
            black_box(out.normals.len())
        });
    });
    let mut group = c.benchmark_group("contacts/column");
    for n in [10, 100, 1000] {
        let scene = column(n);
        let q = scene.initial_coordinates();
        let u = vec![0.0; q.len()];
        group.bench_with_input(BenchmarkId::from_parameter(n), &n, |b, _| {
            b.iter(|| {
                scene.contacts_into(0.0, black_box(&q), black_box(&u), &mut out);
                black_box(out.slips.len())
            });
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
