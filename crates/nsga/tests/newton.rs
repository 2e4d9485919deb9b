//! Newton variants of the stepper reach the converged steps of the paper's exact,
//! full-step Newton (eq. 143): simplified updates from kept factors
//! (`LinearOptions::reuse_factorization`) and damped updates (`NewtonOptions::line_search`); and
//! the sparse Markowitz LU takes the steps of dense LU.

use nsga::systems::chain::Chain;
use nsga::systems::rocking::RockingBlock;
use nsga::{
    LinearOptions, NewtonOptions, Options, PolicyOptions, SolverChoice, State, Stepper, System,
};

/// The states of `steps` steps and the number of factorizations they took.
fn run<S: System>(
    sys: S,
    q0: &[f64],
    u0: &[f64],
    opts: Options,
    steps: usize,
) -> (Vec<State>, u64) {
    let mut s = Stepper::new(sys, 0.0, q0, u0, opts).unwrap();
    let mut states = Vec::new();
    for _ in 0..steps {
        s.step().unwrap();
        states.push(s.state().clone());
    }
    (states, s.linear_solves())
}

fn largest_difference(a: &[State], b: &[State]) -> f64 {
    a.iter()
        .zip(b)
        .flat_map(|(x, y)| {
            x.q.iter()
                .zip(&y.q)
                .chain(x.u.iter().zip(&y.u))
                .map(|(p, q)| (p - q).abs())
        })
        .fold(0.0, f64::max)
}

/// The three Newton variants on one system for `steps` steps: exact full steps, kept
/// factors, kept factors with a line search, all with a tight tolerance so that states
/// converged within it agree closely.
struct Variants {
    /// The exact run's states.
    exact: Vec<State>,
    /// Largest state difference of the kept-factor and of the damped run to the exact one.
    difference: [f64; 2],
    /// Factorizations of the exact and of the kept-factor run.
    factorizations: [u64; 2],
}

fn variants<S: System + Copy>(sys: S, q0: &[f64], u0: &[f64], steps: usize) -> Variants {
    let exact = Options {
        dt: 1e-3,
        tol: 1e-13,
        ..Options::default()
    };
    let reuse = Options {
        linear: LinearOptions {
            reuse_factorization: true,
            ..exact.linear.clone()
        },
        ..exact.clone()
    };
    let damped = Options {
        newton: NewtonOptions {
            line_search: 3,
            ..reuse.newton.clone()
        },
        ..reuse.clone()
    };
    let (a, exact_solves) = run(sys, q0, u0, exact, steps);
    let (b, reuse_solves) = run(sys, q0, u0, reuse, steps);
    let (c, _) = run(sys, q0, u0, damped, steps);
    Variants {
        difference: [largest_difference(&a, &b), largest_difference(&a, &c)],
        factorizations: [exact_solves, reuse_solves],
        exact: a,
    }
}

#[test]
fn kept_factors_carry_a_sliding_block_to_rest_with_fewer_factorizations() {
    // The top block of a resting chain slides at 1 m/s and stops after
    // v/(μg) = 0.34 s: a long phase with unchanged index sets, then a stick transition.
    let chain = Chain::benchmark(5);
    let (q0, u0) = chain.resting(1.0);
    let v = variants(chain, &q0, &u0, 500);
    assert!(v.difference.iter().all(|&d| d < 1e-9), "{:?}", v.difference);
    let top = 2 * (chain.n - 1);
    assert!(
        v.exact.last().unwrap().u[top].abs() < 1e-9,
        "the top block has stopped"
    );
    let [exact, reuse] = v.factorizations;
    assert!(
        2 * reuse < exact,
        "{reuse} factorizations with kept factors, {exact} without"
    );
}

#[test]
fn kept_factors_follow_a_rocking_block_through_its_impacts() {
    // Nonlinear in θ, with corner impacts that change the index sets.
    let block = RockingBlock::slender();
    let (q0, u0) = block.tilted(0.08);
    let v = variants(block, &q0, &u0, 1500);
    assert!(v.difference.iter().all(|&d| d < 1e-8), "{:?}", v.difference);
    let [exact, reuse] = v.factorizations;
    assert!(reuse < exact, "{reuse} vs {exact}");
}

/// The largest state difference between runs with dense LU and with Markowitz LU.
fn markowitz_difference<S: System + Copy>(sys: S, q0: &[f64], u0: &[f64], steps: usize) -> f64 {
    let dense = Options {
        dt: 1e-3,
        tol: 1e-13,
        linear: LinearOptions {
            solver: SolverChoice::Dense,
            ..LinearOptions::default()
        },
        ..Options::default()
    };
    let markowitz = Options {
        linear: LinearOptions {
            solver: SolverChoice::Markowitz(usize::MAX),
            ..dense.linear.clone()
        },
        ..dense.clone()
    };
    let (a, _) = run(sys, q0, u0, dense, steps);
    let (b, _) = run(sys, q0, u0, markowitz, steps);
    largest_difference(&a, &b)
}

#[test]
fn markowitz_lu_takes_the_steps_of_dense_lu() {
    // Sliding to rest on a chain (stick–slip transition) and rocking with corner impacts.
    let chain = Chain::benchmark(5);
    let (q0, u0) = chain.resting(1.0);
    let d = markowitz_difference(chain, &q0, &u0, 500);
    assert!(d < 1e-9, "chain: {d}");
    let block = RockingBlock::slender();
    let (q0, u0) = block.tilted(0.08);
    let d = markowitz_difference(block, &q0, &u0, 1500);
    assert!(d < 1e-8, "rocking block: {d}");
}

/// A unit mass on a saturating spring, force −K atan(q/ε): stiff near q = 0, flat
/// beyond. With K/ε far above 1/Δt², full Newton updates on it behave like Newton's
/// method on atan, which overshoots and diverges from far enough out.
struct SaturatingSpring {
    stiffness: f64,
    width: f64,
}

impl System for SaturatingSpring {
    fn layout(&self) -> nsga::Layout {
        nsga::Layout {
            nq: 1,
            nu: 1,
            ..nsga::Layout::default()
        }
    }
    fn evaluate<T: nsga::Scalar>(&self, _t: f64, q: &[T], _u: &[T], out: &mut nsga::Evaluation<T>) {
        out.mass.push(0, 0, T::from(1.0));
        out.forces[0] = -(q[0] / T::from(self.width)).atan() * T::from(self.stiffness);
    }
}

#[test]
fn the_line_search_carries_newton_where_full_updates_diverge() {
    let spring = || SaturatingSpring {
        stiffness: 100.0,
        width: 1e-3,
    };
    // Without the last resort, which would take the failing steps.
    let full = Options {
        dt: 0.1,
        newton: NewtonOptions {
            max_iter: 60,
            ..NewtonOptions::default()
        },
        policy: PolicyOptions {
            rho_inf_retries: Vec::new(),
            last_resort: false,
            ..PolicyOptions::default()
        },
        ..Options::default()
    };
    let damped = Options {
        newton: NewtonOptions {
            line_search: 8,
            ..full.newton.clone()
        },
        ..full.clone()
    };
    let mut s = Stepper::new(spring(), 0.0, &[0.3], &[0.0], full).unwrap();
    let full_ok = (0..20).all(|_| s.step().is_ok());
    assert!(!full_ok, "full Newton updates fail at this step size");
    let mut s = Stepper::new(spring(), 0.0, &[0.3], &[0.0], damped).unwrap();
    for _ in 0..20 {
        let stats = s.step().unwrap();
        assert!(stats.converged && stats.retries == 0);
        // The scheme dissipates: the mass never swings beyond where it started.
        assert!(s.state().q[0].abs() <= 0.3);
    }
}

/// A chain of 12 blocks with gaps of H/2 between them, whose upper half moves down and
/// sideways: it falls onto itself and the ground, and slides. Options with more contacts
/// (12) than `max_iter` (8) allows updates, so that the held-sets attempt, when asked
/// for, is taken at every step.
fn falling_chain(dt: f64) -> (Chain, Vec<f64>, Vec<f64>, Options) {
    let n = 12;
    let chain = Chain::benchmark(n);
    let h = chain.height;
    let mut q0 = Vec::new();
    let mut u0 = Vec::new();
    for k in 0..n {
        q0.extend([0.0, h / 2.0 + 1.5 * h * k as f64]);
        let moving = if k >= n / 2 { 1.0 } else { 0.0 };
        u0.extend([0.5 * moving, -moving]);
    }
    let options = Options {
        dt,
        tol: 1e-11,
        newton: NewtonOptions {
            max_iter: 8,
            max_iter_per_contact: 3,
            ..NewtonOptions::default()
        },
        ..Options::default()
    };
    (chain, q0, u0, options)
}

/// The held-sets attempt (`NewtonOptions::max_openings_per_update`) holds the previous step's
/// index sets, then opens contacts one per update, but judges convergence on the contact
/// laws' own sets: on the falling chain its steps are those of free Newton.
#[test]
fn the_held_sets_attempt_takes_the_steps_of_free_newton() {
    let (chain, q0, u0, free) = falling_chain(1e-3);
    let held = Options {
        newton: NewtonOptions {
            max_openings_per_update: 1,
            ..free.newton.clone()
        },
        ..free.clone()
    };
    let (a, _) = run(chain, &q0, &u0, free, 300);
    let (b, _) = run(chain, &q0, &u0, held, 300);
    let landed = |s: &State| s.lambda_n.iter().filter(|&&l| l > 0.0).count();
    assert!(
        landed(&a[299]) >= 6,
        "the blocks land: {} contacts carry force",
        landed(&a[299])
    );
    let d = largest_difference(&a, &b);
    assert!(d < 1e-8, "held sets and free Newton differ by {d}");
}

/// The held-sets attempt takes its updates whole, whatever `NewtonOptions::line_search` says:
/// after the release each update changes the sets of a contact or a few, and halving
/// those updates only delayed the next change (docs/method.md §8.2, `Stage::HeldSets` and `Stage::Free`). On the
/// falling chain at Δt = 2·10⁻³, the first 150 steps converge within that attempt, so a
/// line search of three halvings changes nothing, to the last bit, and makes no damped
/// trial (when the attempt still took the line search, it made 5, from step 95).
#[test]
fn the_held_sets_attempt_takes_its_updates_whole() {
    let (chain, q0, u0, options) = falling_chain(2e-3);
    let whole = Options {
        newton: NewtonOptions {
            max_openings_per_update: 1,
            ..options.newton
        },
        ..options
    };
    let damped = Options {
        newton: NewtonOptions {
            line_search: 3,
            ..whole.newton.clone()
        },
        ..whole.clone()
    };
    let steps = 150;
    let (a, _) = run(chain, &q0, &u0, whole, steps);
    let mut s = Stepper::new(chain, 0.0, &q0, &u0, damped).unwrap();
    let mut b = Vec::new();
    for _ in 0..steps {
        s.step().unwrap();
        b.push(s.state().clone());
    }
    assert_eq!(s.newton_work().line_search_trials, 0);
    assert_eq!(largest_difference(&a, &b), 0.0);
}
