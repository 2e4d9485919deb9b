//! A step whose Newton matrix is singular on every attempt reports the singular matrix
//! (`StepError::Linear`), not a non-converged step "with residual inf and 0 index sets
//! visited" (regression: the shaken block column at t = 9.53, where a contact with W = 0
//! was taken as closed).

use nsga::system::{Evaluation, Layout, Scalar, System};
use nsga::{Options, PolicyOptions, StepError, Stepper};

/// A point mass with one normal contact whose gap g = ½ − t does not depend on q
/// (W = 0, χ = −1): open at the start, closed from t = ½ on, with zero rows in the
/// Newton matrix.
#[derive(Debug, Clone, Copy)]
struct StuckContact;

impl System for StuckContact {
    fn layout(&self) -> Layout {
        Layout {
            nq: 1,
            nu: 1,
            e_n: vec![0.0],
            ..Layout::default()
        }
    }
    fn evaluate<T: Scalar>(&self, t: f64, _q: &[T], _u: &[T], out: &mut Evaluation<T>) {
        out.mass.push(0, 0, T::from(1.0));
        out.forces[0] = T::from(-1.0);
        out.position[0] = T::from(0.5 - t);
        out.position_chi[0] = T::from(-1.0);
    }
}

#[test]
fn a_singular_newton_matrix_is_reported_as_such() {
    let options = Options {
        policy: PolicyOptions {
            last_resort: false,
            ..PolicyOptions::default()
        },
        ..Options::default()
    };
    let mut s = Stepper::new(StuckContact, 0.0, &[0.0], &[0.0], options).unwrap();
    let steps = (1.0 / s.options().dt).ceil() as usize;
    let err = (0..steps)
        .find_map(|_| s.step().err())
        .expect("no step can keep a contact with W = 0 closed");
    assert!(matches!(err, StepError::Linear { .. }), "{err:?}");
    assert!(err.to_string().contains("singular"), "{err}");
    // The stepper stays at the last good state, just before the contact closes.
    assert!(s.state().t <= 0.5 + s.options().dt);
}

#[test]
fn the_last_resort_finds_that_no_step_can_keep_the_contact_closed() {
    // W = 0: no percussion changes the closing rate χ = −1, so the step's contact
    // problem has no solution, and Lemke's method ends on a ray.
    let mut s = Stepper::new(StuckContact, 0.0, &[0.0], &[0.0], Options::default()).unwrap();
    let steps = (1.0 / s.options().dt).ceil() as usize;
    let err = (0..steps)
        .find_map(|_| s.step().err())
        .expect("no step can keep a contact with W = 0 closed");
    assert!(matches!(err, StepError::NoSolution { .. }), "{err:?}");
    assert!(err.to_string().contains("has no solution"), "{err}");
    assert!(s.state().t <= 0.5 + s.options().dt);
}
