//! Cost of evaluating every contact of a scene once (what a stepper does per Newton
//! iterate): the Lire tower, and resting columns of 10, 100 and 1000 blocks; and of the
//! block stack's derivative pass (what an exact Newton update asks of the system,
//! `StackSystem::derivatives`) on the Lire tower and a tilted, moving 10-block column.

use blockstack::scenarios::{lire_on_floor, Perturbation};
use blockstack::scene::{ContactParams, SolverParams};
use blockstack::{Base, BaseMotion, Block, Floor, Scene, StackContacts, StackSystem};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use nsga::{Derivatives, Probes, System};
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
    derivative_pass(
        c,
        "derivatives/lire4",
        lire_on_floor(4, Perturbation::Bottom).unwrap(),
    );
    derivative_pass(c, "derivatives/column10", column(10));
}

/// `StackSystem::derivatives` at a state with every block tilted and moving (so that no
/// row vanishes), every constraint used, as an exact Newton update asks for it.
fn derivative_pass(c: &mut Criterion, name: &str, scene: Scene) {
    let system = StackSystem::new(scene);
    let wave = |i: usize, s: f64| s * ((i as f64) * 1.7 + 0.3).sin();
    let mut q = system.scene().initial_coordinates();
    for (i, x) in q.iter_mut().enumerate() {
        *x += wave(i, 1e-3);
    }
    let nq = q.len();
    let layout = system.layout();
    let (np, nv) = (layout.n_position(), layout.n_velocity());
    let u: Vec<f64> = (0..nq).map(|i| wave(i + 5, 0.3)).collect();
    let a: Vec<f64> = (0..nq).map(|i| wave(i + 11, 0.7)).collect();
    let mp: Vec<f64> = (0..np).map(|i| wave(i + 23, 1.0)).collect();
    let mv: Vec<f64> = (0..nv).map(|i| wave(i + 29, 1.0)).collect();
    let probes = Probes {
        a: &a,
        u_old: &u,
        dynamics: [(&u, &mp, &mv), (&a, &mp, &mv), (&u, &mp, &mv)],
        unused_position: &[],
        unused_velocity: &[],
    };
    let mut out = Derivatives::default();
    c.bench_function(name, |b| {
        b.iter(|| {
            out.clear();
            system.derivatives(
                black_box(0.3),
                black_box(&q),
                black_box(&u),
                &probes,
                &mut out,
            );
            black_box(out.position_q.entries.len())
        });
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
