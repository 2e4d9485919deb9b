//! Errors of the cylinder models.

use input::InputError;

/// Why an input does not describe a valid cylinder problem.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CylinderError {
    /// The run-time watchdog stopped a run projected past its bound
    /// ([`crate::studies::pair::PairSettings::time_bound`]).
    #[error("{}", .0.message())]
    Stopped(input::watchdog::Overrun),
    /// A value that is not finite, positive, non-negative or within its range (the
    /// checks every rollstack crate shares, [`input`]).
    #[error(transparent)]
    Input(#[from] InputError),
    /// The inclination is outside the range where the cylinder touches the plane at
    /// one rim point (§3.2: ϑ ∈ (0, π/2)).
    #[error("the inclination ϑ = {} rad is outside (0, π/2): the point-contact assumption of §3.2 fails (at ϑ = 0 the base lies flat, at π/2 the side does)", input::Short(*.0))]
    NotPointContact(f64),
    /// A construction for two identical cylinders was given two different ones.
    #[error("cylinder II (r, h) = {second:?} must be identical to cylinder I (r, h) = {first:?} for this construction")]
    DifferentCylinders {
        /// Radius and height of cylinder I.
        first: [f64; 2],
        /// Radius and height of cylinder II.
        second: [f64; 2],
    },
    /// No applied force can sustain the steady motion at this inclination (the static
    /// friction criterion and F3 ≥ 0, N ≥ 0 cannot all hold), §3.3.
    #[error("no steady support exists at ϑ = {theta} rad for r/h = {r_over_h}, μ = {mu}")]
    NoSupport {
        /// Inclination.
        theta: f64,
        /// Aspect ratio r/h.
        r_over_h: f64,
        /// Friction coefficient.
        mu: f64,
    },
    /// The circle traced by the centre of mass would have a non-positive radius.
    #[error("the centre of mass would trace a circle of radius k = {k} ≤ 0 for ℓ = {ell}: choose a larger ℓ")]
    DegenerateCircle {
        /// Radius of the path of P.
        ell: f64,
        /// Resulting radius of the path of the centre of mass, (3.4.15).
        k: f64,
    },
    /// The two axes are parallel, so the closest points are not unique and their rates
    /// (E.2.5) do not exist (line contact, H singular).
    #[error("the cylinder axes are parallel (|e3_I · e3_II| = {0}): H in (E.2.4) is singular")]
    ParallelAxes(f64),
    /// A rolled trace that is not finite: an inclination within a few ulps of 0 or π/2
    /// passes the open interval of [`CylinderError::NotPointContact`] but overflows.
    #[error("the rolled trace is not finite at ϑ = {} rad: the inclination is too close to 0 or π/2 for double precision", input::Short(*.0))]
    NotFinite(f64),
    /// The time stepper (nsga) failed on a step or at the start.
    #[error("the time stepper failed: {0}")]
    Solver(String),
    /// A contact position between two cylinders given for the single cylinder, whose
    /// test has no such contact (the front ends name their own flag or argument).
    #[error("a contact position between two cylinders applies to the pair systems (pair7, pair9), not to the single cylinder")]
    ContactOfSingle,
    /// A dimension mismatch between a system and the coordinates given to it.
    #[error("expected {expected} coordinates, got {got}")]
    Dimension {
        /// Number of coordinates of the system.
        expected: usize,
        /// Number given.
        got: usize,
    },
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::holonomy::{Direction, PathCase, RectanglePath};
    use crate::kinematics::Cylinder;
    use crate::statics::SupportProblem;

    #[test]
    fn generic_checks_read_as_input_errors() {
        let e = Cylinder::new(1.0, f64::NAN).unwrap_err();
        assert_eq!(
            e,
            CylinderError::Input(InputError::NonFinite("height h".into()))
        );
        assert_eq!(e.to_string(), "height h is not finite");
        assert_eq!(
            SupportProblem::new(0.1, -0.2).unwrap_err().to_string(),
            "μ must not be negative, got -0.2"
        );
        assert_eq!(
            Cylinder::new(-1.0, 1.0).unwrap_err().to_string(),
            "radius r must be positive, got -1"
        );
        let s = RectanglePath::new(1.0, 2.0, 1.5, PathCase::I, Direction::Clockwise);
        assert_eq!(s.unwrap_err().to_string(), "s must lie in [0, 1], got 1.5");
    }

    #[test]
    fn cylinder_specific_checks_keep_their_words() {
        let e = crate::kinematics::check_point_contact(0.0).unwrap_err();
        assert!(e.to_string().contains("outside (0, π/2)"), "{e}");
        // A huge ϑ is printed short, not as three hundred digits.
        let huge = crate::kinematics::check_point_contact(1e300).unwrap_err();
        assert!(huge.to_string().contains("ϑ = 1e300 rad"), "{huge}");
        let pair = crate::pair::CylinderPair {
            first: Cylinder::new(1.0, 2.0).unwrap(),
            second: Cylinder::new(0.5, 2.0).unwrap(),
        };
        let e = pair.touching_configuration(0.4, 0.1, 0.5).unwrap_err();
        assert_eq!(
            e,
            CylinderError::DifferentCylinders {
                first: [1.0, 2.0],
                second: [0.5, 2.0]
            }
        );
        assert_eq!(
            e.to_string(),
            "cylinder II (r, h) = [0.5, 2.0] must be identical to cylinder I (r, h) = [1.0, 2.0] for this construction"
        );
    }
}
