//! The holonomy of a sphere whose centre traces a rectangle (§2.4, App. B).
//!
//! Geometry (Figure 2.3, lengths in units of the sphere's radius R): in the frame
//! {A1, A2, A3 = E3} the centre starts at S, moves φ1 along +A1, ϑ along +A2, φ2 along
//! −A1, ϑ along −A2 and φ2 − φ1 along +A1 back to S. Viewed from +A3 this is the
//! counter-clockwise traversal; clockwise is the same rectangle travelled backwards.
//!
//! Rolling a distance L in the horizontal direction d rotates the sphere by L/R about
//! E3 × d ((2.3.5)): moving along +A1 is a rotation about +A2, moving along +A2 a
//! rotation about −A1. Hence the product (2.4.2).

use crate::HolonomyError;
use nalgebra::{Matrix3, Quaternion, Rotation3, Unit, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};
use std::f64::consts::{PI, TAU};

/// Direction of travel around a rectangle, viewed from above (from +A3).
///
/// ERRATA item 2: the product (2.4.2) read right to left follows the motion sequence
/// (2.4.1), which is the counter-clockwise traversal; the ↺/↻ glyphs of the extracted
/// thesis text are unreliable and are not used.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Direction {
    /// Counter-clockwise: the product (2.4.2).
    Ccw,
    /// Clockwise: the transpose of (2.4.2), (2.4.5).
    Cw,
}

impl Direction {
    /// The other direction.
    #[must_use]
    pub fn reversed(self) -> Self {
        match self {
            Self::Ccw => Self::Cw,
            Self::Cw => Self::Ccw,
        }
    }

    /// `"ccw"` or `"cw"`, as in the CLI's JSON.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Ccw => "ccw",
            Self::Cw => "cw",
        }
    }
}

/// A rectangular path of the centre, Ŝ(ϑ, φ1, φ2, A1, A2, direction) in the local frame
/// {A1, A2, A3 = E3} (Figure 2.3, (2.4.3)).
///
/// Sides: φ2 R along A1 and ϑ R along A2; the start S is φ1 R from the corner.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Rectangle {
    /// ϑ = W/R: the side along A2, radians (equivalently in units of R).
    pub theta: f64,
    /// φ1 = H1/R: the distance of the start S from the corner, radians, in [0, φ2].
    pub phi1: f64,
    /// φ2 = H2/R: the side along A1, radians.
    pub phi2: f64,
    /// Direction of travel.
    pub direction: Direction,
}

impl Rectangle {
    /// A rectangle, checked: all values finite, ϑ ≥ 0, φ2 ≥ 0, 0 ≤ φ1 ≤ φ2.
    ///
    /// # Errors
    /// [`HolonomyError::Input`] for a non-finite value or a negative ϑ or φ2;
    /// [`HolonomyError::StartOffSide`].
    pub fn new(
        theta: f64,
        phi1: f64,
        phi2: f64,
        direction: Direction,
    ) -> Result<Self, HolonomyError> {
        for (name, v) in [("theta", theta), ("phi1", phi1), ("phi2", phi2)] {
            input::finite(name, v)?;
        }
        input::non_negative("theta", theta)?;
        input::non_negative("phi2", phi2)?;
        if !(0.0..=phi2).contains(&phi1) {
            return Err(HolonomyError::StartOffSide { phi1, phi2 });
        }
        Ok(Self {
            theta,
            phi1,
            phi2,
            direction,
        })
    }

    /// The length of the path in units of R: 2(ϑ + φ2).
    #[must_use]
    pub fn path_length(&self) -> f64 {
        2.0 * (self.theta + self.phi2)
    }

    /// The corners of the centre's path in the local frame, (x along A1, y along A2) in
    /// units of R, from S back to S in the order of travel (six points).
    #[must_use]
    pub fn waypoints(&self) -> Vec<[f64; 2]> {
        let (p1, p2, t) = (self.phi1, self.phi2, self.theta);
        let ccw = vec![
            [0.0, 0.0],
            [p1, 0.0],
            [p1, t],
            [p1 - p2, t],
            [p1 - p2, 0.0],
            [0.0, 0.0],
        ];
        match self.direction {
            Direction::Ccw => ccw,
            Direction::Cw => ccw.into_iter().rev().collect(),
        }
    }

    /// The holonomy S as the product of five rotations (2.4.2) (counter-clockwise), or
    /// its transpose (2.4.5) (clockwise). Components on {A1, A2, A3}.
    #[must_use]
    pub fn holonomy(&self) -> Rotation3<f64> {
        rectangle_holonomy(self)
    }

    /// The holonomy as the closed-form unit quaternion (2.4.6)–(2.4.7), corrected.
    #[must_use]
    pub fn quaternion(&self) -> UnitQuaternion<f64> {
        rectangle_holonomy_closed_form(self)
    }
}

/// R(α, A1).
fn about_a1(angle: f64) -> Rotation3<f64> {
    Rotation3::from_axis_angle(&Vector3::x_axis(), angle)
}

/// R(α, A2).
fn about_a2(angle: f64) -> Rotation3<f64> {
    Rotation3::from_axis_angle(&Vector3::y_axis(), angle)
}

/// Rectangle holonomy as the product of five rotations, (2.4.2):
/// S = R(φ2 − φ1, A2) R(ϑ, A1) R(−φ2, A2) R(−ϑ, A1) R(φ1, A2) for counter-clockwise
/// travel (ERRATA item 2), and Sᵀ for clockwise travel (2.4.5).
///
/// Components on {A1, A2, A3 = E3}: entry (i, k) is Aᵢ · S Aₖ.
#[must_use]
pub fn rectangle_holonomy(rect: &Rectangle) -> Rotation3<f64> {
    let s = about_a2(rect.phi2 - rect.phi1)
        * about_a1(rect.theta)
        * about_a2(-rect.phi2)
        * about_a1(-rect.theta)
        * about_a2(rect.phi1);
    match rect.direction {
        Direction::Ccw => s,
        Direction::Cw => s.transpose(),
    }
}

/// Rectangle holonomy in closed form, (2.4.6)–(2.4.7) **corrected by ERRATA item 1**:
///
/// q0 = cos(ψ/2) = 1 − 2 sin²(ϑ/2) sin²(φ2/2),
/// q = sin(ψ/2) s = sin ϑ sin(φ2/2) A_r + sin φ2 sin²(ϑ/2) A2,
/// A_r = −cos(φ1 − φ2/2) A3 + sin(φ1 − φ2/2) A1,
///
/// for counter-clockwise travel; the conjugate (q0, −q) for clockwise travel (2.4.5).
/// The printed (2.4.6)₁ lacks the factor 2. This is one of the two quaternions ±(q0, q)
/// of S, with this sign (its q0 may be negative).
#[must_use]
pub fn rectangle_holonomy_closed_form(rect: &Rectangle) -> UnitQuaternion<f64> {
    let half_theta_sin = (0.5 * rect.theta).sin();
    let (half_phi2_sin, _) = (0.5 * rect.phi2).sin_cos();
    let sin2_half_theta = half_theta_sin * half_theta_sin;
    let q0 = 1.0 - 2.0 * sin2_half_theta * half_phi2_sin * half_phi2_sin;
    let a_r = axis_a_r(rect.phi1, rect.phi2);
    let q =
        rect.theta.sin() * half_phi2_sin * a_r + rect.phi2.sin() * sin2_half_theta * Vector3::y();
    let q = match rect.direction {
        Direction::Ccw => q,
        Direction::Cw => -q,
    };
    UnitQuaternion::new_unchecked(Quaternion::from_parts(q0, q))
}

/// The unit vector A_r = −cos(φ1 − φ2/2) A3 + sin(φ1 − φ2/2) A1 of (2.4.7).
#[must_use]
pub fn axis_a_r(phi1: f64, phi2: f64) -> Vector3<f64> {
    let (s, c) = (phi1 - 0.5 * phi2).sin_cos();
    Vector3::new(s, 0.0, -c)
}

/// Rectangle holonomy from the components (B.1.2)–(B.1.3), **corrected by ERRATA
/// item 3** (`sx` read as `sy`, so M22 = cos²ϑ + cos φ2 sin²ϑ):
///
/// `[S] = Y(φ2 − φ1) [M] Y(φ1)`, `Y(α) = [[cos α, 0, sin α], [0, 1, 0], [−sin α, 0, cos α]]`,
///
/// with M exactly as printed in (B.1.3) (not its transpose, although the middle factor
/// of (B.1.2) is typeset with the indices M_ji; checked against (2.4.2) to round-off).
/// Clockwise travel gives the transpose (end of App. B).
#[must_use]
pub fn holonomy_components(rect: &Rectangle) -> Matrix3<f64> {
    let (sy, cy) = rect.theta.sin_cos();
    let (sz, cz) = rect.phi2.sin_cos();
    #[rustfmt::skip]
    let m = Matrix3::new(
        cz,       sy * sz,                  -cy * sz,
        -sy * sz, cy * cy + cz * sy * sy,   (1.0 - cz) * cy * sy,
        cy * sz,  (1.0 - cz) * cy * sy,     cy * cy * cz + sy * sy,
    );
    let y = |a: f64| {
        let (s, c) = a.sin_cos();
        Matrix3::new(c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c)
    };
    let s = y(rect.phi2 - rect.phi1) * m * y(rect.phi1);
    match rect.direction {
        Direction::Ccw => s,
        Direction::Cw => s.transpose(),
    }
}

/// The angle of rotation ψ ∈ [0, 2π] of the counter-clockwise holonomy as a function
/// of ϑ and φ2 alone, (2.4.11) corrected by ERRATA item 1:
/// cos(ψ/2) = 1 − 2 sin²(ϑ/2) sin²(φ2/2). (This is the ψ of Figure 2.5.)
#[must_use]
pub fn holonomy_angle(theta: f64, phi2: f64) -> f64 {
    let q0 = 1.0 - 2.0 * (0.5 * theta).sin().powi(2) * (0.5 * phi2).sin().powi(2);
    2.0 * q0.clamp(-1.0, 1.0).acos()
}

/// Which of the no-holonomy families (2.4.8) a rectangle belongs to, if any. Serializes
/// as its [`NoHolonomy::name`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum NoHolonomy {
    /// (2.4.8)₁: ϑ and φ2 both odd multiples of π (S = R(2(2n − 1)π, s) = I).
    OddMultiplesOfPi,
    /// (2.4.8)₂: ϑ a multiple of 2π.
    ThetaMultipleOfTwoPi,
    /// (2.4.8)₃: φ2 a multiple of 2π.
    Phi2MultipleOfTwoPi,
}

impl NoHolonomy {
    /// The family's name in JSON: `odd_multiples_of_pi`, `theta_multiple_of_two_pi` or
    /// `phi2_multiple_of_two_pi`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::OddMultiplesOfPi => "odd_multiples_of_pi",
            Self::ThetaMultipleOfTwoPi => "theta_multiple_of_two_pi",
            Self::Phi2MultipleOfTwoPi => "phi2_multiple_of_two_pi",
        }
    }

    /// The family as text: its equation and condition, `(2.4.8)₂: ϑ a multiple of 2π`.
    #[must_use]
    pub fn description(self) -> &'static str {
        match self {
            Self::OddMultiplesOfPi => "(2.4.8)₁: ϑ and φ2 odd multiples of π",
            Self::ThetaMultipleOfTwoPi => "(2.4.8)₂: ϑ a multiple of 2π",
            Self::Phi2MultipleOfTwoPi => "(2.4.8)₃: φ2 a multiple of 2π",
        }
    }
}

/// The no-holonomy family (2.4.8) of a rectangle, with `tol` the tolerance on the
/// angles (radians); `None` when the rectangle is not in any of them.
#[must_use]
pub fn no_holonomy_family(rect: &Rectangle, tol: f64) -> Option<NoHolonomy> {
    let near_multiple = |x: f64, period: f64| {
        let r = x.rem_euclid(period);
        r.min(period - r) <= tol
    };
    let odd_pi = |x: f64| near_multiple(x - PI, TAU);
    if near_multiple(rect.theta, TAU) {
        Some(NoHolonomy::ThetaMultipleOfTwoPi)
    } else if near_multiple(rect.phi2, TAU) {
        Some(NoHolonomy::Phi2MultipleOfTwoPi)
    } else if odd_pi(rect.theta) && odd_pi(rect.phi2) {
        Some(NoHolonomy::OddMultiplesOfPi)
    } else {
        None
    }
}

/// The special paths (2.4.9) in axis–angle form, or `None` if the rectangle is not one.
///
/// - φ2 = (2m − 1)π: S = R(2ϑ, ±A_r), with **+A_r for φ2 = π, 3π... alternating**:
///   the axis flips with each further π, so φ2 = π gives +A_r and φ2 = 3π gives −A_r
///   (ERRATA item 4);
/// - ϑ = (2l − 1)π: S = R(2φ2, A2) for every l (sin²(ϑ/2) = 1 and sin ϑ = 0 in (2.4.6)).
///
/// Both for counter-clockwise travel; clockwise reverses the axis (2.4.5). `tol` is the
/// tolerance on the angles, radians.
#[must_use]
pub fn special_path_rotation(rect: &Rectangle, tol: f64) -> Option<(f64, Unit<Vector3<f64>>)> {
    let odd = |x: f64| -> Option<f64> {
        // Returns +1 for π, 5π, ..., −1 for 3π, 7π, ...
        let n = ((x / PI - 1.0) / 2.0).round();
        let nearest = (2.0 * n + 1.0) * PI;
        ((x - nearest).abs() <= tol && n >= 0.0).then(|| {
            if n.rem_euclid(2.0) == 0.0 {
                1.0
            } else {
                -1.0
            }
        })
    };
    let reverse = match rect.direction {
        Direction::Ccw => 1.0,
        Direction::Cw => -1.0,
    };
    if let Some(sign) = odd(rect.phi2) {
        let axis = sign * reverse * axis_a_r(rect.phi1, rect.phi2);
        return Some((2.0 * rect.theta, Unit::new_normalize(axis)));
    }
    odd(rect.theta).map(|_| (2.0 * rect.phi2, Unit::new_normalize(reverse * Vector3::y())))
}

#[cfg(test)]
mod tests {
    use super::*;
    use rotations::{rotation_distance, rotation_from_quaternion};

    fn close_quaternion(q: &UnitQuaternion<f64>, r: &Rotation3<f64>) -> f64 {
        let (_, m) = rotation_from_quaternion([q.w, q.i, q.j, q.k]).unwrap();
        rotation_distance(&m, r)
    }

    #[test]
    fn three_forms_agree() {
        for &(t, p1, p2) in &[
            (0.3, 0.1, 0.7),
            (2.0, 1.0, 4.0),
            (5.5, 2.5, 9.0),
            (PI, 0.5, 1.0),
        ] {
            for d in [Direction::Ccw, Direction::Cw] {
                let r = Rectangle::new(t, p1, p2, d).unwrap();
                let s = rectangle_holonomy(&r);
                assert!((holonomy_components(&r) - s.matrix()).norm() < 1e-14);
                assert!(close_quaternion(&rectangle_holonomy_closed_form(&r), &s) < 1e-14);
            }
        }
    }

    #[test]
    fn waypoints_close_and_turn_left_for_ccw() {
        let r = Rectangle::new(1.0, 0.5, 2.0, Direction::Ccw).unwrap();
        let w = r.waypoints();
        assert_eq!(w.first(), w.last());
        // Shoelace area: positive for counter-clockwise.
        let area: f64 = w
            .windows(2)
            .map(|p| p[0][0] * p[1][1] - p[1][0] * p[0][1])
            .sum::<f64>()
            / 2.0;
        assert!((area - 2.0).abs() < 1e-15);
    }

    #[test]
    fn rejects_bad_rectangles() {
        assert!(Rectangle::new(f64::NAN, 0.0, 1.0, Direction::Ccw).is_err());
        assert!(Rectangle::new(-1.0, 0.0, 1.0, Direction::Ccw).is_err());
        assert!(Rectangle::new(1.0, 2.0, 1.0, Direction::Ccw).is_err());
        assert!(Rectangle::new(1.0, -0.1, 1.0, Direction::Ccw).is_err());
    }
}
