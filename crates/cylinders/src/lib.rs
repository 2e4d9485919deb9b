//! Inclined cylinders rolling on one rim point (Honein 2024, Ch. 3, App. D, E, F).
//!
//! - [`kinematics`]: 3-1-3 Euler angles (through [`rotations::EulerSet`]), the contact
//!   point π_P (3.2.4), the rolling constraints (3.2.5)–(3.2.6) and their matrix W (D.1.4).
//! - [`statics`]: steady support (§3.3) corrected per ERRATA 9–11: limiting normal forces
//!   (3.3.8), (3.3.10), feasible inclinations (3.3.9), the common point (3.3.11), the
//!   minimum applied force in its four cases (3.3.15)–(3.3.19), the circle (3.3.20) and
//!   point D; plus a numerical solution of the balance laws (3.3.3) as a check.
//! - [`holonomy`]: rectangle (nine-rotation product (3.4.3) and closed forms
//!   (3.4.5)–(3.4.9)) and circle ((3.4.10)–(3.4.16)); values in radians (ERRATA 8).
//! - [`rolling`]: kinematic rolling along those paths, traces of P and of a rim point.
//! - [`frobenius`]: a generic numerical Frobenius test with exact derivatives (App. D).
//! - [`pair`]: the single cylinder and the touching pair as constraint systems (App. F;
//!   the rank of the nine constraints is 9, ERRATA 13).
//! - [`contact`]: contact between two cylinders (App. E).
//! - [`studies`]: what the command line and the tour report, as typed, serializable
//!   results: the support at one inclination, the curves of Figures 3.3–3.8, the
//!   holonomy reports and traces of Figures 3.10 and 3.12, the Frobenius reports.
//!
//! Lengths are in any consistent unit, angles in radians, forces divided by mg.
//!
//! ```
//! use cylinders::statics::{FrictionLimit, SupportProblem};
//! use cylinders::holonomy::{Direction, PathCase, RectanglePath};
//! use cylinders::frobenius::frobenius_test;
//! use cylinders::pair::{CylinderPair, PairConstraints, PairSystem};
//! use cylinders::kinematics::Cylinder;
//!
//! // Support forces for r/h = 0.1, μ = 0.2 at the common point (3.3.11).
//! let problem = SupportProblem::new(0.1, 0.2)?;
//! let (theta, n) = problem.common_point().unwrap();
//! let n_plus = problem.normal_force(theta, FrictionLimit::Plus)?.unwrap();
//! assert!((n_plus - n).abs() < 1e-15);
//!
//! // Figure 3.10: Δφ = 139π/12 rad, and the nine-rotation product agrees.
//! let path = RectanglePath::new(13.0 * std::f64::consts::PI / 3.0, 29.0 * std::f64::consts::PI / 4.0,
//!                               0.0, PathCase::I, Direction::CounterClockwise)?;
//! let err = rotations::rotation_distance(&path.product(0.3, 0.0), &path.closed_form(0.3, 0.0));
//! assert!(err < 1e-12 && (path.delta_phi() - 36.3901).abs() < 1e-4);
//!
//! // The nine rolling constraints of a touching pair have rank 9 (ERRATA 13).
//! let pair = CylinderPair::identical(Cylinder::gas_cylinder());
//! let q = pair.touching_configuration(0.4, 0.3, 0.5)?;
//! let report = frobenius_test(&PairSystem { pair, constraints: PairConstraints::Nine }, &q)?;
//! assert_eq!(report.rank, 9);
//! # Ok::<(), cylinders::CylinderError>(())
//! ```
#![warn(missing_docs)]

pub mod contact;
mod error;
pub mod frobenius;
pub mod holonomy;
pub mod kinematics;
pub mod pair;
pub mod rolling;
pub mod statics;
pub mod studies;
pub mod transport;

pub use error::CylinderError;
