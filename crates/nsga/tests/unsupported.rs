//! A normal contact that the system reports without W at an iterate (an "open contact
//! that cannot close", such as a corner slid past the end of its face) is open, whatever
//! its multipliers: closed, its rows would hold nothing but the regularization and the
//! Newton matrix would be singular at every Δt (docs/method.md §8.2). (A gap at or below
//! zero without W is another matter: no force can keep it closed; `singular.rs`.)

use nsga::system::{Evaluation, Layout, Scalar, System};
use nsga::{Options, Stepper};

/// A point mass on a table that ends at x = 1: gap y while over it, and past the end the
/// value 1 with no W.
#[derive(Debug, Clone, Copy)]
struct ShortTable;

impl System for ShortTable {
    fn layout(&self) -> Layout {
        Layout {
            nq: 2,
            nu: 2,
            e_n: vec![0.0],
            ..Layout::default()
        }
    }
    fn evaluate<T: Scalar>(&self, _t: f64, q: &[T], _u: &[T], out: &mut Evaluation<T>) {
        out.mass.push(0, 0, T::from(1.0));
        out.mass.push(1, 1, T::from(1.0));
        out.forces[1] = T::from(-1.0);
        if q[0].re() <= 1.0 {
            out.position[0] = q[1];
            out.position_w.push(1, 0, T::from(1.0));
        } else {
            out.position[0] = T::from(1.0);
        }
    }
}

/// The sets at the stepper's own unknowns with κ_N = 10, for the mass at x.
fn closed_with_a_large_multiplier(x: f64) -> bool {
    let options = Options {
        dt: 1e-3,
        ..Options::default()
    };
    let mut s = Stepper::new(ShortTable, 0.0, &[x, 0.0], &[0.0, 0.0], options).unwrap();
    let mut unknowns = s.state().x.clone();
    // x = (a, U, Q, κ_N, Λ_N, λ_N) for two velocities and one contact.
    unknowns[6] = 10.0;
    s.sets_of(&unknowns, 0.5).a[0]
}

#[test]
fn a_contact_without_w_is_open_whatever_its_multipliers() {
    // Over the table the large κ̂_N closes the contact (r g − κ̂ < 0) ...
    assert!(closed_with_a_large_multiplier(0.5));
    // ... past its end r·1 − κ̂ < 0 too, but the contact has no W: open.
    assert!(!closed_with_a_large_multiplier(1.5));
}
