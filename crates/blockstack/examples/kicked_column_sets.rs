//! How many contacts of a kicked column change their index sets from one step to the
//! next, against the Newton updates its steps take (docs/method.md §8.2, "Where a tall
//! column's updates go").
//!
//! The column of n blocks stands on a base that moves as x = 0.001 sin 2t (μ = 0.2,
//! Δt = 2π/628), whose velocity at t = 0 kicks it: the scene of `rollstack blocks shake
//! --blocks N --omega 2 --amplitude 0.001 --mu 0.2 --steps-per-period 314`, stepped as a
//! run steps it. For steps 2 to STEPS the example prints the means per step of the
//! Newton updates, of the contacts whose sets differ from the step before's (A, B, C per
//! normal contact; D, E per friction law: eqs. 128–142), and of the interfaces with a
//! corner open on position level; then the run's linear solves. With `trace`, one line
//! per step.
//!
//! `cargo run --release -p blockstack --example kicked_column_sets [BLOCKS] [STEPS] [trace]`
//! (defaults 100 blocks, 100 steps).

use blockstack::scenarios::{shaking_column, Shaking};
use blockstack::simulation::stepper_options;
use blockstack::stepping::CornerStepping;
use blockstack::RunOptions;
use nsga::IndexSets;

/// The number of entries in which `a` and `b` differ.
fn changed(a: &[bool], b: &[bool]) -> usize {
    a.iter().zip(b).filter(|(x, y)| x != y).count()
}

/// The changes of A, B, C, D and E from `before` to `after`; None where the contacts
/// differ (a corner contact came or went).
fn set_changes(before: &IndexSets, after: &IndexSets) -> Option<[usize; 5]> {
    let same = before.a.len() == after.a.len() && before.d.len() == after.d.len();
    same.then(|| {
        [
            changed(&before.a, &after.a),
            changed(&before.b, &after.b),
            changed(&before.c, &after.c),
            changed(&before.d, &after.d),
            changed(&before.e, &after.e),
        ]
    })
}

fn argument(k: usize, default: usize) -> Result<usize, String> {
    std::env::args().nth(k).map_or(Ok(default), |a| {
        a.parse().map_err(|e| format!("'{a}': {e}"))
    })
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let n = argument(1, 100)?;
    let steps = argument(2, 100)?.max(2);
    let trace = std::env::args().nth(3).as_deref() == Some("trace");
    let scene = shaking_column(&Shaking::tall_column(n, false))?;
    let options = stepper_options(&scene, &RunOptions::default())?;
    let (mut corners, mut stepper) = CornerStepping::start_scene(&scene, options)?;
    // The two gaps of interface k are normal contacts 2k and 2k + 1 (blockstack::stack).
    let lifted = |sets: &IndexSets| {
        (0..n)
            .filter(|&k| !(sets.a[2 * k] && sets.a[2 * k + 1]))
            .count()
    };
    let (mut updates, mut changes, mut open, mut counted) = (0, [0; 5], 0, 0);
    let mut before: Option<IndexSets> = None;
    for step in 1..=steps {
        corners.step(&scene, &mut stepper, 1e-8)?;
        let stats = stepper.last_step().ok_or("a step was taken")?;
        let sets = &stats.sets;
        if let Some(c) = before.as_ref().and_then(|b| set_changes(b, sets)) {
            counted += 1;
            updates += stats.iterations;
            open += lifted(sets);
            for (total, c) in changes.iter_mut().zip(c) {
                *total += c;
            }
            if trace {
                println!(
                    "step {step:4}: {:3} updates, changed A {:3} B {:3} C {:3} D {:3} E {:3}, \
                     {:3} interfaces lifted",
                    stats.iterations,
                    c[0],
                    c[1],
                    c[2],
                    c[3],
                    c[4],
                    lifted(sets)
                );
            }
        }
        before = Some(sets.clone());
    }
    let mean = |x: usize| x as f64 / counted.max(1) as f64;
    println!(
        "{n} blocks, steps 2 to {steps} ({counted} with the same contacts): per step \
         {:.2} updates; contacts changed in A {:.2}, B {:.2}, C {:.2}, D {:.2}, E {:.2}; \
         {:.2} interfaces with a corner open in A; {} linear solves",
        mean(updates),
        mean(changes[0]),
        mean(changes[1]),
        mean(changes[2]),
        mean(changes[3]),
        mean(changes[4]),
        mean(open),
        stepper.linear_solves()
    );
    Ok(())
}
