//! Holonomy of a rolling cylinder whose contact point P traces a rectangle or a circle
//! (§3.4), with the values of Figures 3.10 and 3.12 in radians (ERRATA 8).
//!
//! Both paths change only the spin φ: the holonomy is a rotation A(Δφ, ₀e3) about the
//! initial axis ₀e3 of the cylinder.

use crate::error::CylinderError;
use crate::kinematics::{check_point_contact, Cylinder, EulerFrame};
use input::{in_range, positive};
use nalgebra::{Quaternion, Rotation3, Unit, UnitQuaternion, Vector3};
use rotations::{compound, AxisAngle};
use serde::{Deserialize, Serialize};
use std::f64::consts::{FRAC_PI_2, PI};

/// Whether e′2 points out of the path (Case I, φ̇ > 0 when travelled counter-clockwise)
/// or into it (Case II, φ̇ < 0), §3.4.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum PathCase {
    /// e′2 points outward.
    I,
    /// e′2 points inward.
    II,
}

impl PathCase {
    /// The case's name in text, file names and JSON: `I` or `II`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::I => "I",
            Self::II => "II",
        }
    }

    /// +1 for Case I, −1 for Case II.
    #[must_use]
    pub fn sign(self) -> f64 {
        match self {
            Self::I => 1.0,
            Self::II => -1.0,
        }
    }
}

/// The sense in which the path is travelled (seen from above, E3 up).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Direction {
    /// Counter-clockwise (↺).
    CounterClockwise,
    /// Clockwise (↻).
    Clockwise,
}

impl Direction {
    /// The direction in text: `counter-clockwise` or `clockwise`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::CounterClockwise => "counter-clockwise",
            Self::Clockwise => "clockwise",
        }
    }

    /// +1 counter-clockwise, −1 clockwise.
    #[must_use]
    pub fn sign(self) -> f64 {
        match self {
            Self::CounterClockwise => 1.0,
            Self::Clockwise => -1.0,
        }
    }
}

/// One elementary motion of a path made of straight rolls and pivots.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Motion {
    /// Roll about the cylinder's axis e3 by this angle (ω = φ̇ e3, (3.4.1)): P moves
    /// a distance r |angle| along a straight line.
    Roll(f64),
    /// Pivot about the vertical through P by this angle (ω = ψ̇ E3, (3.4.2)): P stays.
    Pivot(f64),
}

/// The ₀e3 of (3.4.4): sin ψ0 sin ϑ E1 − cos ψ0 sin ϑ E2 + cos ϑ E3.
#[must_use]
pub fn initial_axis(theta: f64, psi0: f64) -> Vector3<f64> {
    EulerFrame::new(psi0, theta).e3
}

/// A rectangle of sides rφ1/2 and rφ2/2 traced by the contact point P, starting at the
/// point S given by s ∈ [0, 1] on a side of length rφ1/2 (Figure 3.9).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RectanglePath {
    /// φ1 > 0: a side of length rφ1/2 is rolled through an angle φ1/2.
    pub phi1: f64,
    /// φ2 > 0: the other side.
    pub phi2: f64,
    /// Start parameter s ∈ [0, 1]: ℓ1 = r(1 − s)φ1/2 before the first corner.
    pub s: f64,
    /// Case I or II.
    pub case: PathCase,
    /// Sense of travel.
    pub direction: Direction,
}

impl RectanglePath {
    /// A validated rectangle.
    ///
    /// # Errors
    /// When φ1 or φ2 is not positive or s is outside [0, 1].
    pub fn new(
        phi1: f64,
        phi2: f64,
        s: f64,
        case: PathCase,
        direction: Direction,
    ) -> Result<Self, CylinderError> {
        positive("φ1", phi1)?;
        positive("φ2", phi2)?;
        in_range("s", s, 0.0..=1.0, "[0, 1]")?;
        Ok(Self {
            phi1,
            phi2,
            s,
            case,
            direction,
        })
    }

    /// The nine motions in the order they happen. Counter-clockwise this is (3.4.3) read
    /// right to left: roll (1−s)φ1/2, pivot π/2, roll φ2/2, pivot, roll φ1/2, pivot,
    /// roll φ2/2, pivot, roll sφ1/2, the rolls negated for Case II. Clockwise is the same
    /// path travelled backwards: the reversed sequence with every angle negated.
    #[must_use]
    pub fn motions(&self) -> Vec<Motion> {
        let k = self.case.sign();
        let (a, b, s) = (0.5 * self.phi1, 0.5 * self.phi2, self.s);
        let ccw = vec![
            Motion::Roll(k * (1.0 - s) * a),
            Motion::Pivot(FRAC_PI_2),
            Motion::Roll(k * b),
            Motion::Pivot(FRAC_PI_2),
            Motion::Roll(k * a),
            Motion::Pivot(FRAC_PI_2),
            Motion::Roll(k * b),
            Motion::Pivot(FRAC_PI_2),
            Motion::Roll(k * s * a),
        ];
        match self.direction {
            Direction::CounterClockwise => ccw,
            Direction::Clockwise => ccw
                .into_iter()
                .rev()
                .map(|m| match m {
                    Motion::Roll(x) => Motion::Roll(-x),
                    Motion::Pivot(x) => Motion::Pivot(-x),
                })
                .collect(),
        }
    }

    /// The holonomy as the product of the nine rotations, (3.4.3): each roll is a
    /// rotation about the current axis ᵢe3 = A(iπ/2, E3) ₀e3 (3.4.4), each pivot about E3;
    /// later motions multiply on the left. Returned as the unit quaternion of the
    /// compound rotation (Rodrigues' formula, footnote 2 of Ch. 3), without changing its
    /// sign, so it can be compared with (3.4.9).
    #[must_use]
    pub fn product_quaternion(&self, theta: f64, psi0: f64) -> UnitQuaternion<f64> {
        let mut psi = psi0;
        let mut total = UnitQuaternion::identity();
        for m in self.motions() {
            let (angle, axis) = match m {
                Motion::Roll(x) => (x, initial_axis(theta, psi)),
                Motion::Pivot(x) => {
                    psi += x;
                    (x, Vector3::z())
                }
            };
            let step = AxisAngle {
                angle,
                axis: Unit::new_normalize(axis),
            }
            .to_quaternion();
            total = compound(&total, &step);
        }
        total
    }

    /// The product (3.4.3) as a rotation.
    #[must_use]
    pub fn product(&self, theta: f64, psi0: f64) -> Rotation3<f64> {
        self.product_quaternion(theta, psi0).to_rotation_matrix()
    }

    /// Δφ = ±(φ1 + φ2): (3.4.6) for Case I counter-clockwise, (3.4.7) clockwise,
    /// (3.4.8) for Case II.
    #[must_use]
    pub fn delta_phi(&self) -> f64 {
        self.case.sign() * self.direction.sign() * (self.phi1 + self.phi2)
    }

    /// The closed form A(Δφ, ₀e3), (3.4.5), (3.4.7), (3.4.8).
    #[must_use]
    pub fn closed_form(&self, theta: f64, psi0: f64) -> Rotation3<f64> {
        Rotation3::from_axis_angle(
            &Unit::new_normalize(initial_axis(theta, psi0)),
            self.delta_phi(),
        )
    }

    /// The quaternion (3.4.9) of the raw product (Case I counter-clockwise; the general
    /// form uses Δφ): q0 = cos(π + Δφ/2), q = sin(π + Δφ/2) ₀e3. The π comes from the
    /// four quarter turns about E3, whose quaternions multiply to −1.
    #[must_use]
    pub fn quaternion_3_4_9(&self, theta: f64, psi0: f64) -> UnitQuaternion<f64> {
        let half = PI + 0.5 * self.delta_phi();
        UnitQuaternion::new_unchecked(Quaternion::from_parts(
            half.cos(),
            initial_axis(theta, psi0) * half.sin(),
        ))
    }
}

/// A circle of radius ℓ traced by P while the centre of mass traces a concentric circle
/// of radius k (§3.4, Figure 3.11).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CirclePath {
    /// Radius ℓ of the path of P.
    pub ell: f64,
    /// Case I (e′2 outward) or II (inward).
    pub case: PathCase,
    /// Sense of travel.
    pub direction: Direction,
}

/// The numbers of one circular holonomy.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CircleHolonomy {
    /// Δφ = ±2πℓ/r, (3.4.16) (sign flipped for clockwise travel).
    pub delta_phi: f64,
    /// Radius k of the path of the centre of mass, (3.4.15).
    pub k: f64,
    /// φ̇0/ψ̇0 from (3.4.14).
    pub rate_ratio: f64,
    /// Δφ computed as (φ̇0/ψ̇0) Δψ with Δψ = ±2π, a check of (3.4.16).
    pub delta_phi_from_rates: f64,
}

impl CirclePath {
    /// A validated circle.
    ///
    /// # Errors
    /// When ℓ is not positive.
    pub fn new(ell: f64, case: PathCase, direction: Direction) -> Result<Self, CylinderError> {
        Ok(Self {
            ell: positive("ℓ", ell)?,
            case,
            direction,
        })
    }

    /// k, φ̇0/ψ̇0 and Δφ for a cylinder at inclination ϑ ∈ (0, π/2).
    ///
    /// k from (3.4.15): ℓ − k = (h/2) sin ϑ − r cos ϑ = −f1 (Case I), ℓ − k = f1 (Case II);
    /// then (3.4.14) gives φ̇0/ψ̇0 = (k − f1)/r (I) or −(k + f1)/r (II), and (3.4.16)
    /// Δφ = ±2πℓ/r.
    ///
    /// # Errors
    /// When ϑ is outside (0, π/2) or k ≤ 0.
    pub fn holonomy(
        &self,
        cylinder: &Cylinder,
        theta: f64,
    ) -> Result<CircleHolonomy, CylinderError> {
        check_point_contact(theta)?;
        let (r, f1) = (cylinder.radius(), cylinder.f1(theta));
        let (k, rate_ratio) = match self.case {
            PathCase::I => (self.ell + f1, (self.ell + f1 - f1) / r),
            PathCase::II => (self.ell - f1, -(self.ell - f1 + f1) / r),
        };
        if k <= 0.0 {
            return Err(CylinderError::DegenerateCircle { ell: self.ell, k });
        }
        let turn = self.direction.sign() * 2.0 * PI;
        Ok(CircleHolonomy {
            delta_phi: self.case.sign() * self.direction.sign() * 2.0 * PI * self.ell / r,
            k,
            rate_ratio,
            delta_phi_from_rates: rate_ratio * turn,
        })
    }
}

/// The inclination, sizes and start of a holonomy example of Figure 3.10.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Figure310 {
    /// r = 1.
    pub cylinder: Cylinder,
    /// ϑ = π/10.
    pub theta: f64,
    /// The rectangle (φ1 = 13π/3, φ2 = 29π/4, s = 0).
    pub path: RectanglePath,
}

impl Figure310 {
    /// The data of Figure 3.10: h = 8.3333 r, φ1 = 13π/3, φ2 = 29π/4, ϑ = π/10, s = 0;
    /// Δφ = ±139π/12 = ±36.3901 rad (ERRATA 8).
    #[must_use]
    pub fn new(case: PathCase) -> Self {
        Self {
            cylinder: Cylinder::new(1.0, 25.0 / 3.0).unwrap_or(Cylinder::gas_cylinder()),
            theta: PI / 10.0,
            path: RectanglePath {
                phi1: 13.0 * PI / 3.0,
                phi2: 29.0 * PI / 4.0,
                s: 0.0,
                case,
                direction: Direction::CounterClockwise,
            },
        }
    }
}

/// The data of Figure 3.12: r = 1, h = 13.3333 r (40/3), ϑ = π/10, k = 25/3 for Case I,
/// so ℓ = 9.44239 r (ERRATA 8; the printed 9.44233 is a rounding slip) and
/// Δφ = ±59.3283 rad. Returns (cylinder, ϑ, ℓ).
#[must_use]
pub fn figure_3_12() -> (Cylinder, f64, f64) {
    let cylinder = Cylinder::new(1.0, 40.0 / 3.0).unwrap_or(Cylinder::gas_cylinder());
    let theta = PI / 10.0;
    let ell = 25.0 / 3.0 - cylinder.f1(theta);
    (cylinder, theta, ell)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rotations::rotation_distance;

    #[test]
    fn figure_3_10_radians() {
        for case in [PathCase::I, PathCase::II] {
            let fig = Figure310::new(case);
            let d = fig.path.delta_phi();
            assert!((d.abs() - 139.0 * PI / 12.0).abs() < 1e-13);
            assert!((d.abs() - 36.3901).abs() < 5e-5);
            let err = rotation_distance(
                &fig.path.product(fig.theta, 0.0),
                &fig.path.closed_form(fig.theta, 0.0),
            );
            assert!(err < 1e-12, "{err}");
        }
    }

    #[test]
    fn quaternion_3_4_9_exact() {
        let path =
            RectanglePath::new(1.3, 2.9, 0.37, PathCase::I, Direction::CounterClockwise).unwrap();
        let q = path.product_quaternion(0.4, 0.8);
        let expect = path.quaternion_3_4_9(0.4, 0.8);
        assert!(
            (q.coords - expect.coords).norm() < 1e-14,
            "{q:?} vs {expect:?}"
        );
    }

    #[test]
    fn figure_3_12_radians() {
        let (cyl, theta, ell) = figure_3_12();
        assert!((ell - 9.44239).abs() < 5e-6);
        let one = CirclePath::new(ell, PathCase::I, Direction::CounterClockwise)
            .unwrap()
            .holonomy(&cyl, theta)
            .unwrap();
        assert!((one.delta_phi - 59.3283).abs() < 5e-5);
        assert!((one.k - 25.0 / 3.0).abs() < 1e-13);
        let two = CirclePath::new(ell, PathCase::II, Direction::CounterClockwise)
            .unwrap()
            .holonomy(&cyl, theta)
            .unwrap();
        assert!((two.delta_phi + 59.3283).abs() < 5e-5);
        // ERRATA 15: Case II's k = 10.5515 r is consistent: the exact value is
        // 10.551447 r, within one unit of the last printed digit.
        assert!((two.k - 10.5515).abs() < 1e-4);
        assert!((two.k - 10.551_447).abs() < 1e-6);
        // ℓ = 9.44233 as printed gives 59.3279 (ERRATA 8).
        let printed = CirclePath::new(9.44233, PathCase::I, Direction::CounterClockwise)
            .unwrap()
            .holonomy(&cyl, theta)
            .unwrap();
        assert!((printed.delta_phi - 59.3279).abs() < 5e-5);
    }
}
