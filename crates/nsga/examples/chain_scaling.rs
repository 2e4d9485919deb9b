//! Step cost against the size of a chain of blocks, and the dense/sparse choice.
//!
//! `cargo run -p nsga --release --example chain_scaling`

use nsga::systems::chain::Chain;
use nsga::{LinearOptions, NewtonOptions, Options, SolverChoice, Stepper};
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    for n in [10usize, 30, 100, 300, 1000] {
        for solver in [SolverChoice::Dense, SolverChoice::Sparse] {
            let profiling = std::env::var("PROFILE_N").is_ok();
            if (solver == SolverChoice::Dense && n > 30)
                || (profiling && (n != 10 || solver == SolverChoice::Dense))
            {
                continue;
            }
            let chain = Chain::benchmark(n);
            let (q0, u0) = chain.resting(1.0);
            let mut s = Stepper::new(
                chain,
                0.0,
                &q0,
                &u0,
                Options {
                    linear: LinearOptions {
                        solver,
                        ..LinearOptions::default()
                    },
                    ..Options::default()
                },
            )?;
            s.run(2, |_, _| {})?;
            let mut saved = s.state().clone();
            saved.x.iter_mut().for_each(|v| *v = 0.0);
            let reps = if std::env::var("PROFILE_N").is_ok() {
                2000
            } else {
                20
            };
            let mut iters = 0;
            let start = Instant::now();
            for _ in 0..reps {
                s.set_state(saved.clone());
                iters += s.step()?.iterations;
            }
            let per_step = start.elapsed().as_secs_f64() / f64::from(reps);
            println!(
                "n = {n:5} ({:6} unknowns, {solver:?}): {:8.1} µs/step, {:.1} Newton iterations, {:7.2} µs/iteration",
                s.n_unknowns(),
                per_step * 1e6,
                iters as f64 / f64::from(reps),
                per_step * 1e6 * f64::from(reps) / iters as f64
            );
        }
    }
    // Open contacts left out of the linear solve: a spread stack falling together.
    for n in [100usize, 1000] {
        for prune in [false, true] {
            let chain = Chain::benchmark(n);
            let (q0, u0) = chain.spread(0.05, 1.0);
            let opts = Options {
                newton: NewtonOptions {
                    prune_open_contacts: prune,
                    ..NewtonOptions::default()
                },
                ..Options::default()
            };
            let mut s = Stepper::new(chain, 0.0, &q0, &u0, opts)?;
            s.run(2, |_, _| {})?;
            let mut saved = s.state().clone();
            saved.x.iter_mut().for_each(|v| *v = 0.0);
            let reps = 20;
            let start = Instant::now();
            for _ in 0..reps {
                s.set_state(saved.clone());
                s.step()?;
            }
            println!(
                "spread chain n = {n:5}, prune_open_contacts = {prune:5}: {:8.1} µs/step",
                start.elapsed().as_secs_f64() / f64::from(reps) * 1e6
            );
        }
    }
    Ok(())
}
