//! A committed step leaves no subnormal number in the state (`State::flush_subnormals`):
//! such numbers slow every later operation on them by two orders of magnitude.

use nsga::systems::oscillator::Oscillator;
use nsga::{Options, Stepper};

#[test]
fn a_committed_step_flushes_subnormal_numbers_to_zero() {
    let sys = Oscillator {
        mass: 1.0,
        stiffness: 1.0,
    };
    // A displacement in the subnormal range: one step moves it by a factor cos(Δt), so
    // without the flush it stays subnormal.
    let x0: f64 = 1e-310;
    assert!(x0.is_subnormal());
    let mut s = Stepper::new(sys, 0.0, &[x0], &[0.0], Options::default()).unwrap();
    s.step().unwrap();
    let st = s.state();
    for (name, v) in [("q", &st.q), ("u", &st.u), ("a", &st.a), ("x", &st.x)] {
        assert!(
            v.iter().all(|z| !z.is_subnormal()),
            "{name} = {v:?} after the step"
        );
    }
    assert_eq!(st.q[0], 0.0);
    // Normal numbers are left alone.
    let mut s = Stepper::new(sys, 0.0, &[1e-300], &[0.0], Options::default()).unwrap();
    s.step().unwrap();
    assert!(s.state().q[0] > 0.9e-300);
}
