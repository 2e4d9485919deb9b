//! Kinematics of one inclined cylinder rolling on a horizontal plane (§3.2, App. A).
//!
//! The orientation is given by 3-1-3 Euler angles (ψ, ϑ, φ), Q = R(ψ,E3) R(ϑ,E1) R(φ,E3)
//! ([`rotations::EulerSet`] "3-1-3"). The functions here are generic over the scalar
//! (`f64`, or a dual number of `num-dual` for exact derivatives in [`crate::frobenius`]);
//! their `f64` values are tested against the `rotations` crate.

use crate::error::CylinderError;
use input::{finite, positive};
use nalgebra::{Matrix3, RealField, SMatrix, Vector3};
use rotations::EulerSet;
use serde::{Deserialize, Serialize};
use std::f64::consts::FRAC_PI_2;

/// The rolling-constraint matrix of one cylinder: 3 rows (E1, E2, E3 components of v_P),
/// 6 columns (ẋ1, ẋ2, ẋ3, ψ̇, ϑ̇, φ̇), (D.1.4).
pub type RollingMatrix<T> = SMatrix<T, 3, 6>;

/// A homogeneous circular cylinder of radius r and height h (§3.2).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Cylinder {
    radius: f64,
    height: f64,
}

impl Cylinder {
    /// A cylinder of radius `radius` and height `height` (same length unit).
    ///
    /// # Errors
    /// When either is not finite or not positive.
    pub fn new(radius: f64, height: f64) -> Result<Self, CylinderError> {
        Ok(Self {
            radius: positive("radius r", radius)?,
            height: positive("height h", height)?,
        })
    }

    /// The cylinder with r/h = `r_over_h` and height 1.
    ///
    /// # Errors
    /// When `r_over_h` is not finite or not positive.
    pub fn from_ratio(r_over_h: f64) -> Result<Self, CylinderError> {
        Self::new(positive("r/h", r_over_h)?, 1.0)
    }

    /// The cylinders of §3.6 and ERRATA 14: h = 1.2954 m, r = 0.1143 m (a 220 ft³ gas
    /// cylinder).
    #[must_use]
    pub fn gas_cylinder() -> Self {
        Self {
            radius: 0.1143,
            height: 1.2954,
        }
    }

    /// Radius r.
    #[must_use]
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// Height h.
    #[must_use]
    pub fn height(&self) -> f64 {
        self.height
    }

    /// f1 = r cos ϑ − (h/2) sin ϑ, (3.2.6): minus the horizontal offset π_P · e′2.
    #[must_use]
    pub fn f1(&self, theta: f64) -> f64 {
        self.radius * theta.cos() - 0.5 * self.height * theta.sin()
    }

    /// f2 = r sin ϑ + (h/2) cos ϑ, (3.2.6): the height of the centre of mass above the
    /// plane (minus π_P · E3).
    #[must_use]
    pub fn f2(&self, theta: f64) -> f64 {
        self.radius * theta.sin() + 0.5 * self.height * theta.cos()
    }
}

/// Checks the point-contact assumption of §3.2: the cylinder touches the plane at one
/// rim point only when ϑ ∈ (0, π/2).
///
/// # Errors
/// [`CylinderError::NotPointContact`] otherwise (also for NaN).
pub fn check_point_contact(theta: f64) -> Result<f64, CylinderError> {
    finite("inclination ϑ", theta)?;
    if theta > 0.0 && theta < FRAC_PI_2 {
        Ok(theta)
    } else {
        Err(CylinderError::NotPointContact(theta))
    }
}

/// The vectors of the 3-1-3 Euler construction (A.1.1)–(A.1.3) that the rolling
/// constraints need, components on E1, E2, E3.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EulerFrame<T: RealField + Copy> {
    /// e′1 = cos ψ E1 + sin ψ E2 = g2, (A.1.1).
    pub e1p: Vector3<T>,
    /// e′2 = −sin ψ E1 + cos ψ E2, (A.1.1).
    pub e2p: Vector3<T>,
    /// e″2 = cos ϑ e′2 + sin ϑ E3, (A.1.2).
    pub e2pp: Vector3<T>,
    /// e3 = e″3 = −sin ϑ e′2 + cos ϑ E3 = g3, the axis of the cylinder, (A.1.2)–(A.1.3).
    pub e3: Vector3<T>,
}

impl<T: RealField + Copy> EulerFrame<T> {
    /// The frame for precession ψ and nutation (inclination) ϑ; the spin φ does not enter.
    #[must_use]
    pub fn new(psi: T, theta: T) -> Self {
        let (sp, cp) = psi.sin_cos();
        let (st, ct) = theta.sin_cos();
        let z = T::zero();
        let e1p = Vector3::new(cp, sp, z);
        let e2p = Vector3::new(-sp, cp, z);
        let e3_fixed = Vector3::new(z, z, T::one());
        Self {
            e1p,
            e2p,
            e2pp: e2p * ct + e3_fixed * st,
            e3: e3_fixed * ct - e2p * st,
        }
    }

    /// The Euler basis {g1, g2, g3} = {E3, e′1, e3}, (A.1.4).
    #[must_use]
    pub fn euler_basis(&self) -> [Vector3<T>; 3] {
        [
            Vector3::new(T::zero(), T::zero(), T::one()),
            self.e1p,
            self.e3,
        ]
    }
}

/// π_P = −(h/2) e3 − r e″2, the contact point P relative to the centre of mass, (3.2.4),
/// for the frame of angles (ψ, ϑ).
#[must_use]
pub fn contact_offset<T: RealField + Copy>(
    cylinder: &Cylinder,
    frame: &EulerFrame<T>,
) -> Vector3<T> {
    let r: T = nalgebra::convert(cylinder.radius);
    let half_h: T = nalgebra::convert(0.5 * cylinder.height);
    -(frame.e3 * half_h) - frame.e2pp * r
}

/// π_P from the axis e3 alone: the lowest point of the bottom rim, −(h/2) e3 − r e″2 with
/// e″2 the unit vector along the part of E3 normal to e3. Equal to (3.2.4) for
/// ϑ ∈ (0, π); used where the orientation is not held as Euler angles.
#[must_use]
pub fn contact_offset_from_axis<T: RealField + Copy>(
    cylinder: &Cylinder,
    e3: &Vector3<T>,
) -> Vector3<T> {
    let r: T = nalgebra::convert(cylinder.radius);
    let half_h: T = nalgebra::convert(0.5 * cylinder.height);
    let up = Vector3::new(T::zero(), T::zero(), T::one());
    let uphill = up - *e3 * e3.z;
    -(*e3 * half_h) - uphill * (r / uphill.norm())
}

/// The columns gₖ × π of a constraint v = x̄̇ + ω × π with ω = ψ̇ g1 + ϑ̇ g2 + φ̇ g3
/// (A.2.1): the 3×3 block that multiplies (ψ̇, ϑ̇, φ̇). With π = π_P this is the matrix
/// A of (F.2.4), corrected per ERRATA 12 (third column e3 × π_P1, printed with the wrong
/// sign).
#[must_use]
pub fn rotation_columns<T: RealField + Copy>(frame: &EulerFrame<T>, pi: &Vector3<T>) -> Matrix3<T> {
    let [g1, g2, g3] = frame.euler_basis();
    Matrix3::from_columns(&[g1.cross(pi), g2.cross(pi), g3.cross(pi)])
}

/// The rolling constraints v_P = 0 as Π = W q̇ with q = (x1, x2, x3, ψ, ϑ, φ): the
/// matrix W of (D.1.4), built as [I | g1 × π_P, g2 × π_P, g3 × π_P] from (3.2.3).
/// Its rows are (3.2.5) with f1, f2 of (3.2.6).
#[must_use]
pub fn rolling_matrix<T: RealField + Copy>(
    cylinder: &Cylinder,
    psi: T,
    theta: T,
) -> RollingMatrix<T> {
    let frame = EulerFrame::new(psi, theta);
    let pi = contact_offset(cylinder, &frame);
    let mut w = RollingMatrix::zeros();
    w.fixed_view_mut::<3, 3>(0, 0)
        .copy_from(&Matrix3::identity());
    w.fixed_view_mut::<3, 3>(0, 3)
        .copy_from(&rotation_columns(&frame, &pi));
    w
}

/// The same matrix written out as printed in (D.1.4), for checking.
#[must_use]
pub fn rolling_matrix_printed(cylinder: &Cylinder, psi: f64, theta: f64) -> RollingMatrix<f64> {
    let (f1, f2, r) = (cylinder.f1(theta), cylinder.f2(theta), cylinder.radius);
    let (s, c) = psi.sin_cos();
    RollingMatrix::from_row_slice(&[
        1.0,
        0.0,
        0.0,
        c * f1,
        -s * f2,
        r * c, //
        0.0,
        1.0,
        0.0,
        s * f1,
        c * f2,
        r * s, //
        0.0,
        0.0,
        1.0,
        0.0,
        -f1,
        0.0,
    ])
}

/// The pose of one cylinder: centre of mass and 3-1-3 Euler angles.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Pose {
    /// x̄ = x1 E1 + x2 E2 + x3 E3, (3.2.1).
    pub position: Vector3<f64>,
    /// (ψ, ϑ, φ), radians.
    pub angles: [f64; 3],
}

impl Pose {
    /// A pose standing on the plane z = 0: x3 = f2(ϑ) so that P is on the plane (the
    /// integral of Π3 = 0, §3.2).
    #[must_use]
    pub fn on_plane(cylinder: &Cylinder, x1: f64, x2: f64, angles: [f64; 3]) -> Self {
        Self {
            position: Vector3::new(x1, x2, cylinder.f2(angles[1])),
            angles,
        }
    }

    /// The 12 generalized coordinates ordering of Appendix F for one body:
    /// (x1, x2, x3, ψ, ϑ, φ), (D.1.2).
    #[must_use]
    pub fn coordinates(&self) -> [f64; 6] {
        let [a, b, c] = self.angles;
        [self.position.x, self.position.y, self.position.z, a, b, c]
    }

    /// The rotation Q of the cylinder, through [`rotations::EulerSet`] 3-1-3.
    #[must_use]
    pub fn rotation(&self) -> rotations::Rotation3<f64> {
        three_one_three().rotation(self.angles)
    }

    /// The axis e3 = Q E3.
    #[must_use]
    pub fn axis(&self) -> Vector3<f64> {
        self.rotation() * Vector3::z()
    }
}

/// The 3-1-3 Euler set of the `rotations` crate.
#[must_use]
pub fn three_one_three() -> EulerSet {
    // "3-1-3" is one of the twelve valid names; `EulerSet::new` only fails on others.
    EulerSet::new(3, 1, 3).unwrap_or(EulerSet::ALL[0])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_matches_rotations_crate() {
        let set = three_one_three();
        for &(psi, theta, phi) in &[(0.3, 0.4, 1.0), (-2.0, 1.2, 0.1), (3.0, 0.05, -2.5)] {
            let frame = EulerFrame::new(psi, theta);
            let [g1, g2, g3] = set.basis([psi, theta, phi]);
            let [h1, h2, h3] = frame.euler_basis();
            assert!(
                (g1 - h1).norm() < 1e-15 && (g2 - h2).norm() < 1e-15 && (g3 - h3).norm() < 1e-15
            );
            // e″2 is the image of E2 after the first two rotations.
            let q12 = set.rotation([psi, theta, 0.0]);
            assert!((q12 * Vector3::y() - frame.e2pp).norm() < 1e-15);
        }
    }

    #[test]
    fn contact_offset_components() {
        // π_P · e′2 = −f1, π_P · E3 = −f2, π_P · e′1 = 0 (used in (3.4.15)).
        let cyl = Cylinder::new(0.3, 2.0).unwrap();
        let (psi, theta) = (0.9, 0.6);
        let frame = EulerFrame::new(psi, theta);
        let pi = contact_offset(&cyl, &frame);
        assert!((pi.dot(&frame.e2p) + cyl.f1(theta)).abs() < 1e-15);
        assert!((pi.z + cyl.f2(theta)).abs() < 1e-15);
        assert!(pi.dot(&frame.e1p).abs() < 1e-15);
        let from_axis = contact_offset_from_axis(&cyl, &frame.e3);
        assert!((from_axis - pi).norm() < 1e-15);
    }

    #[test]
    fn matrix_is_printed_d14() {
        let cyl = Cylinder::new(0.25, 1.7).unwrap();
        for &(psi, theta) in &[(0.1, 0.2), (2.5, 1.3), (-1.0, 0.7)] {
            let w = rolling_matrix(&cyl, psi, theta);
            assert!((w - rolling_matrix_printed(&cyl, psi, theta)).norm() < 1e-15);
        }
    }

    #[test]
    fn errata_12_third_column() {
        // A = [E3 × π_P1, e′1 × π_P1, e3 × π_P1]: the third column is +r (cos ψ, sin ψ, 0),
        // not the printed −r (cos ψ, sin ψ, 0).
        let cyl = Cylinder::new(0.4, 1.0).unwrap();
        let (psi, theta): (f64, f64) = (0.8, 0.5);
        let w = rolling_matrix(&cyl, psi, theta);
        assert!((w[(0, 5)] - 0.4 * psi.cos()).abs() < 1e-15);
        assert!((w[(1, 5)] - 0.4 * psi.sin()).abs() < 1e-15);
    }

    #[test]
    fn bad_inputs() {
        assert!(Cylinder::new(-1.0, 1.0).is_err());
        assert!(Cylinder::new(1.0, f64::NAN).is_err());
        assert!(check_point_contact(0.0).is_err());
        assert!(check_point_contact(FRAC_PI_2).is_err());
        assert!(check_point_contact(f64::NAN).is_err());
        assert!(check_point_contact(0.3).is_ok());
    }
}
