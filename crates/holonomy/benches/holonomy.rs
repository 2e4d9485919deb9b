//! Criterion benchmarks: `sphere holonomy` (target < 1 µs) and `sphere plan` for all
//! solutions (target < 1 ms), plus the Euler plan and rolling with both integrators.
//!
//! `cargo bench -p holonomy --bench holonomy -- --quick`

use criterion::{criterion_group, criterion_main, Criterion};
use holonomy::roll::{roll, CentrePath, Integrator};
use holonomy::{
    euler_plan, plan_rectangles, rectangle_holonomy, rectangle_holonomy_closed_form, Direction,
    Rectangle,
};
use rotations::{AxisAngle, EulerSet, Vector3};
use std::f64::consts::PI;
use std::hint::black_box;

fn benches(c: &mut Criterion) {
    let r = Rectangle::new(
        4.0 * PI / 3.0 - 0.5,
        PI / 2.0 - 0.4,
        3.0 * PI,
        Direction::Ccw,
    )
    .unwrap();
    c.bench_function("holonomy_product_2_4_2", |b| {
        b.iter(|| rectangle_holonomy(black_box(&r)));
    });
    c.bench_function("holonomy_closed_form_2_4_6", |b| {
        b.iter(|| rectangle_holonomy_closed_form(black_box(&r)));
    });
    let target = AxisAngle::new(1.5 * PI, Vector3::new(0.1, 0.98_f64.sqrt(), 0.1))
        .unwrap()
        .to_rotation();
    c.bench_function("plan_all_solutions_2_4_12", |b| {
        b.iter(|| plan_rectangles(black_box(&target)).unwrap());
    });
    let set = EulerSet::from_name("3-2-3").unwrap();
    c.bench_function("euler_plan_323", |b| {
        b.iter(|| euler_plan(set, black_box([0.6, 1.1, 1.4])).unwrap());
    });
    let path = CentrePath::circle(2.0, Direction::Ccw).unwrap();
    for (name, integ) in [
        ("roll_circle_exact_256", Integrator::Exact),
        ("roll_circle_rk4_256", Integrator::Rk4),
    ] {
        c.bench_function(name, |b| {
            b.iter(|| roll(black_box(&path), 1.0, integ, 256).unwrap());
        });
    }
}

criterion_group!(group, benches);
criterion_main!(group);
