//! A step stopped by the caller's `Interrupt` (`nsga::interrupt`): it ends with
//! `StepError::Interrupted` before its next stage or Newton update, the stepper back at
//! the state, Δt and statistics the step started from, and stepping goes on once the
//! interrupt is lifted.

use nsga::system::{Evaluation, Layout, Scalar, System};
use nsga::systems::rocking::RockingBlock;
use nsga::{Interrupt, Options, StepError, Stepper};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;

/// The rocking block, with a tripwire: it counts its evaluations at real states (one
/// per Newton iterate) and sets `flag` at evaluation number `trip_at`.
#[derive(Debug, Clone)]
struct Tripwire {
    block: RockingBlock,
    evaluations: Arc<AtomicUsize>,
    trip_at: Arc<AtomicUsize>,
    flag: Arc<AtomicBool>,
}

impl Tripwire {
    fn new() -> Self {
        Self {
            block: RockingBlock::slender(),
            evaluations: Arc::default(),
            trip_at: Arc::new(AtomicUsize::new(usize::MAX)),
            flag: Arc::default(),
        }
    }

    fn evaluations(&self) -> usize {
        self.evaluations.load(Ordering::Relaxed)
    }
}

impl System for Tripwire {
    fn layout(&self) -> Layout {
        self.block.layout()
    }
    fn evaluate<T: Scalar>(&self, t: f64, q: &[T], u: &[T], out: &mut Evaluation<T>) {
        self.block.evaluate(t, q, u, out);
    }
    fn evaluate_real(&self, t: f64, q: &[f64], u: &[f64], out: &mut Evaluation<f64>) {
        let n = self.evaluations.fetch_add(1, Ordering::Relaxed) + 1;
        if n >= self.trip_at.load(Ordering::Relaxed) {
            self.flag.store(true, Ordering::Relaxed);
        }
        self.block.evaluate(t, q, u, out);
    }
}

/// A stepper of the block released from rest at half its slenderness angle, rocking
/// towards its first impact: every step takes Newton updates.
fn rocking() -> (Tripwire, Stepper<Tripwire>) {
    let sys = Tripwire::new();
    let (q0, u0) = sys.block.tilted(0.5 * sys.block.alpha());
    let options = Options {
        dt: 1e-2,
        ..Options::default()
    };
    let stepper = Stepper::new(sys.clone(), 0.0, &q0, &u0, options).unwrap();
    (sys, stepper)
}

#[test]
fn a_due_interrupt_stops_the_step_before_it_starts() {
    let (sys, mut s) = rocking();
    let mut free = rocking().1;
    for _ in 0..3 {
        s.step().unwrap();
        free.step().unwrap();
    }
    let (state, stats) = (s.state().clone(), s.run_stats().clone());
    let before = sys.evaluations();
    s.set_interrupt(Interrupt::new(None, Some(std::time::Instant::now())));
    let err = s.step().unwrap_err();
    let StepError::Interrupted { t, .. } = err else {
        panic!("not interrupted: {err}");
    };
    assert_eq!(t, state.t);
    assert_eq!(sys.evaluations(), before, "the step evaluated nothing");
    assert_eq!(s.state(), &state);
    assert_eq!(s.run_stats(), &stats);
    // Lifted, the interrupt leaves the run as if it had never been set.
    s.set_interrupt(Interrupt::default());
    s.step().unwrap();
    free.step().unwrap();
    assert_eq!(s.state(), free.state());
}

#[test]
fn an_interrupt_stops_the_step_at_its_next_newton_update() {
    let (sys, mut s) = rocking();
    s.set_interrupt(Interrupt::new(Some(sys.flag.clone()), None));
    s.step().unwrap();
    let state = s.state().clone();
    // Without the interrupt, the next step takes several evaluations.
    let mut free = s.branch_from(state.clone());
    free.set_interrupt(Interrupt::default());
    let before = sys.evaluations();
    free.step().unwrap();
    let needed = sys.evaluations() - before;
    assert!(needed >= 2, "the step took {needed} evaluations");
    // Tripped at its first evaluation, the step stops at the update after it.
    let before = sys.evaluations();
    sys.trip_at.store(before + 1, Ordering::Relaxed);
    let err = s.step().unwrap_err();
    assert!(matches!(err, StepError::Interrupted { .. }), "{err}");
    assert_eq!(sys.evaluations() - before, 1);
    assert_eq!(s.state(), &state);
    assert_eq!(s.options().dt, 1e-2);
}
