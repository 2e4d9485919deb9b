//! The inverse problem of App. C: every rectangle that produces a given rotation.
//!
//! # Method
//!
//! Write a quaternion of the target on {A1, A2, A3} as (q0, q1, q2, q3) and compare with
//! the corrected closed form (2.4.6)–(2.4.7) (ERRATA item 1). With u = sin²(ϑ/2) and
//! x = φ2/2, the equations (C.2.2)₁,₂ read
//!
//! k := (1 − q0)/2 = u sin²x,   q2 = 2 u sin x cos x,
//!
//! so that, for k > 0, **cot x = q2 / (2k)**: x = atan2(2k, q2) ∈ (0, π), up to
//! multiples of π. Then, using 1 − q0² = q1² + q2² + q3²,
//!
//! sin²(ϑ/2) = (4k² + q2²)/(4k),   cos²(ϑ/2) = (q1² + q3²)/(4k),
//!
//! which is always in [0, 1]: ϑ = 2 atan2(√(4k² + q2²), √(q1² + q3²)) or 2π minus it.
//! Finally (q1, q3) = ρ (sin β, −cos β) with ρ = sin ϑ sin x gives β = φ1 − φ2/2
//! ((2.4.7)). This replaces the root finding of (C.2.4) by a closed form: the equation
//! (C.2.4) reduces to the single condition above once the factor 2 of ERRATA item 1 is
//! restored. [`crate::appendix_c`] keeps the thesis's root-finding route as an
//! independent check.
//!
//! # The solution set
//!
//! Every rectangle (ϑ, φ1, φ2, direction) with φ2 ∈ (0, 3π] (a root that round-off puts
//! up to 1e-9 beyond 3π is kept unclamped, so that its error stays at round-off),
//! ϑ ∈ (0, 2π) and a start
//! on the side, 0 ≤ φ1 ≤ φ2, is found, for **both** quaternions ±q of the target and
//! **both** directions (clockwise travel produces the conjugate, (2.4.5)). The thesis's
//! (2.4.12) lists only the counter-clockwise solutions with q0 = cos(ψ/2) for the given
//! ψ = 3π/2; the sign −q and the clockwise direction add further rectangles. Since φ1 and
//! φ1 + 2π give the same holonomy on a side longer than 2π, φ1 is reported in
//! [φ2 − 2π, φ2] (which selects exactly the three rectangles printed in (2.4.12)).
//! Adding 2π to ϑ or 2π to both φ1 and φ2 repeats a rotation (ERRATA item 7); the first
//! is outside the reported range, the second is reported (φ2 ≤ 3π).
//!
//! When ϑ = π exactly (target axis along A2), ρ = 0 and every φ1 works ((2.4.9)₂): the
//! planner reports φ1 = φ2/2 and flags the rectangle with `phi1_free`.

use crate::rectangle::{rectangle_holonomy, Direction, Rectangle};
use crate::HolonomyError;
use nalgebra::{Rotation3, UnitQuaternion};
use rotations::{quaternion_from_matrix, rotation_distance};
use serde::{Deserialize, Serialize};
use std::f64::consts::{PI, TAU};

/// One solution of the planner.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PlannedRectangle {
    /// The rectangle, in the frame {A1, A2, A3} of the target's components.
    pub rectangle: Rectangle,
    /// Angle of R_targetᵀ S, with S the forward product (2.4.2): the verified error, rad.
    pub error: f64,
    /// True when any start φ1 ∈ [0, φ2] gives the same rotation ((2.4.9)₂, ϑ = π).
    pub phi1_free: bool,
}

/// Tolerance for merging duplicate solutions and for accepting φ1 slightly below 0.
const MERGE: f64 = 1e-9;

/// Every rectangle with φ2 ∈ (0, 3π] whose holonomy is `target` (components on
/// {A1, A2, A3}), sorted by direction (ccw first), then φ2, then ϑ. See the module
/// documentation for the method and the solution set.
///
/// # Errors
/// [`HolonomyError::Input`] for a target with NaN entries;
/// [`HolonomyError::IdentityTarget`] for the identity (infinitely many rectangles).
pub fn plan_rectangles(target: &Rotation3<f64>) -> Result<Vec<PlannedRectangle>, HolonomyError> {
    if !target.matrix().iter().all(|v| v.is_finite()) {
        return Err(HolonomyError::Input(input::InputError::NonFinite(
            "target rotation".into(),
        )));
    }
    let q = quaternion_from_matrix(target.matrix());
    if q.vector().norm() == 0.0 {
        return Err(HolonomyError::IdentityTarget);
    }
    let mut found: Vec<PlannedRectangle> = Vec::with_capacity(16);
    for direction in [Direction::Ccw, Direction::Cw] {
        // Clockwise travel produces the conjugate of the counter-clockwise closed form.
        let qd = match direction {
            Direction::Ccw => q,
            Direction::Cw => q.conjugate(),
        };
        for sign in [1.0, -1.0] {
            for rect in rectangles_for_quaternion(&qd, sign, direction) {
                let (rectangle, phi1_free) = rect;
                let planned = PlannedRectangle {
                    rectangle,
                    error: rotation_distance(target, &rectangle_holonomy(&rectangle)),
                    phi1_free,
                };
                if !found
                    .iter()
                    .any(|f| same_rectangle(&f.rectangle, &rectangle))
                {
                    found.push(planned);
                }
            }
        }
    }
    found.sort_by(|a, b| {
        let key = |p: &PlannedRectangle| {
            (
                p.rectangle.direction == Direction::Cw,
                p.rectangle.phi2,
                p.rectangle.theta,
            )
        };
        let (ka, kb) = (key(a), key(b));
        ka.0.cmp(&kb.0)
            .then(ka.1.total_cmp(&kb.1))
            .then(ka.2.total_cmp(&kb.2))
    });
    Ok(found)
}

/// The solution with the shortest path 2(ϑ + φ2)R, for a robot.
#[must_use]
pub fn shortest(solutions: &[PlannedRectangle]) -> Option<&PlannedRectangle> {
    solutions.iter().min_by(|a, b| {
        a.rectangle
            .path_length()
            .total_cmp(&b.rectangle.path_length())
    })
}

fn same_rectangle(a: &Rectangle, b: &Rectangle) -> bool {
    a.direction == b.direction
        && (a.theta - b.theta).abs() < MERGE
        && (a.phi1 - b.phi1).abs() < MERGE
        && (a.phi2 - b.phi2).abs() < MERGE
}

/// The counter-clockwise closed form (2.4.6) equated to `sign · q`: all (ϑ, φ1, φ2) with
/// φ2 ∈ (0, 3π], ϑ ∈ (0, 2π), φ1 ∈ [max(0, φ2 − 2π), φ2], each with its `phi1_free`
/// flag, given the direction to store.
fn rectangles_for_quaternion(
    q: &UnitQuaternion<f64>,
    sign: f64,
    direction: Direction,
) -> Vec<(Rectangle, bool)> {
    let (q0, q1, q2, q3) = (sign * q.w, sign * q.i, sign * q.j, sign * q.k);
    // k = (1 − q0)/2 without cancellation near q0 = 1: 1 − q0 = |q|²/(1 + q0).
    let vector_sq = q1 * q1 + q2 * q2 + q3 * q3;
    let k = if q0 > 0.0 {
        0.5 * vector_sq / (1.0 + q0)
    } else {
        0.5 * (1.0 - q0)
    };
    if k <= 0.0 {
        return Vec::new();
    }
    // cot(φ2/2) = q2/(2k), (C.2.2)₁,₂.
    let x0 = (2.0 * k).atan2(q2);
    // sin(ϑ/2) and cos(ϑ/2) up to the common factor 1/(2√k).
    let half_theta = (4.0 * k * k + q2 * q2)
        .sqrt()
        .atan2((q1 * q1 + q3 * q3).sqrt());
    let theta0 = 2.0 * half_theta;
    let mut out = Vec::with_capacity(4);
    for phi2 in [2.0 * x0, 2.0 * x0 + TAU] {
        if phi2 > 3.0 * PI + MERGE {
            continue;
        }
        for theta in [theta0, TAU - theta0] {
            let rho = theta.sin() * (0.5 * phi2).sin();
            let (phi1, free) = if rho.abs() < 1e-14 {
                (0.5 * phi2, true)
            } else {
                // (q1, q3) = ρ (sin β, −cos β), β = φ1 − φ2/2, (2.4.7).
                let beta = (q1 / rho).atan2(-q3 / rho);
                let raw = beta + 0.5 * phi2;
                // The representative in [φ2 − 2π, φ2).
                let low = phi2 - TAU;
                let phi1 = low + (raw - low).rem_euclid(TAU);
                (phi1, false)
            };
            let phi1 = if (-MERGE..0.0).contains(&phi1) {
                0.0
            } else {
                phi1
            };
            if let Ok(rect) = Rectangle::new(theta, phi1, phi2, direction) {
                out.push((rect, free));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Unit, Vector3};

    #[test]
    fn finds_its_own_rectangle() {
        let r = Rectangle::new(1.2, 0.4, 2.0, Direction::Ccw).unwrap();
        let sols = plan_rectangles(&rectangle_holonomy(&r)).unwrap();
        assert!(
            sols.iter().any(|s| same_rectangle(&s.rectangle, &r)),
            "{sols:#?}"
        );
        assert!(sols.iter().all(|s| s.error < 1e-13));
    }

    #[test]
    fn identity_is_rejected() {
        assert_eq!(
            plan_rectangles(&Rotation3::identity()),
            Err(HolonomyError::IdentityTarget)
        );
        let nan = Rotation3::from_axis_angle(&Unit::new_normalize(Vector3::x()), f64::NAN);
        assert!(plan_rectangles(&nan).is_err());
    }
}
