//! Rotation tools for constrained rigid bodies, following Honein (2024), §2.2 and App. A.
//!
//! A thin layer over nalgebra's [`Rotation3`] and [`UnitQuaternion`] that adds what the
//! thesis needs and nalgebra lacks:
//!
//! - the axis–angle form R(θ, r) (2.2.1)₁ and its inverse, robust at θ = 0 and near
//!   θ = π, with the 2-to-1 cover (2.2.4) resolved by a canonical form ([`AxisAngle`]);
//! - the quaternion form R̃(q0, q) (2.2.1)₂–(2.2.2) and the compound-rotation
//!   (Rodrigues) formula of footnote 3 of Ch. 2 ([`compound`]);
//! - all twelve Euler-angle sets ([`EulerSet`]), with their Euler basis gᵢ and dual basis
//!   gⁱ (A.1.4), (A.2.2), and the angular velocity from angle rates (A.2.1);
//! - the angular velocity of R(θ(t), r(t)) (2.2.5) and the [`skewt`] helper;
//! - a rotation from the values of any representation ([`Representation`]), and every
//!   representation of one rotation at once ([`report`]: [`rotation_report`], the JSON of
//!   `rollstack rotation`).
//!
//! Conventions (docs/architecture.md): angles are radians; `R2 * R1` means R1 first; a
//! matrix entry `[i][j]` is Eᵢ · R Eⱼ; a quaternion is (q0, q) with q0 the scalar part.
//!
//! ```
//! use rotations::{AxisAngle, EulerSet, Vector3};
//! use std::f64::consts::PI;
//!
//! // A quarter turn about E3 followed by a quarter turn about E1.
//! let r = AxisAngle::new(PI / 2.0, Vector3::z())?.to_rotation();
//! let s = AxisAngle::new(PI / 2.0, Vector3::x())?.to_rotation();
//! let total = s * r;
//! // Its 3-1-3 Euler angles reproduce it exactly.
//! let angles = EulerSet::from_name("3-1-3")?.angles(&total);
//! let back = EulerSet::from_name("3-1-3")?.rotation(angles);
//! assert!((back.matrix() - total.matrix()).norm() < 1e-15);
//!
//! // Every representation at once (the JSON of `rollstack rotation`).
//! let report = rotations::rotation_report(&total);
//! assert!((report.angle - 2.0 * PI / 3.0).abs() < 1e-15 && report.euler.len() == 12);
//! # Ok::<(), rotations::RotationError>(())
//! ```
#![warn(missing_docs)]

mod angular_velocity;
mod axis_angle;
mod error;
mod euler;
mod quaternion;
pub mod report;
mod representation;
mod skew;

pub use angular_velocity::axis_angle_angular_velocity;
pub use axis_angle::{rotation_from_axis_angle, AxisAngle};
pub use error::RotationError;
pub use euler::{EulerKind, EulerSet};
pub use quaternion::{
    canonical_quaternion, compound, quaternion_from_matrix, rotation_from_matrix,
    rotation_from_quaternion,
};
pub use report::{rotation_report, RotationReport};
pub use representation::{Representation, MATRIX_INPUT_TOLERANCE};
pub use skew::{axial, skewt};

pub use nalgebra::{Matrix3, Rotation3, Unit, UnitQuaternion, Vector3};

/// The angle of the relative rotation Aᵀ B, in [0, π]: a distance between rotations.
///
/// Used throughout rollstack to report how far an achieved rotation is from a target.
#[must_use]
pub fn rotation_distance(a: &Rotation3<f64>, b: &Rotation3<f64>) -> f64 {
    AxisAngle::from_rotation(&(a.transpose() * b)).angle
}
