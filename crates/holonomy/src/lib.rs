//! Holonomy of a sphere rolling without slipping on a plane (Honein 2024, Ch. 2, App. B, C).
//!
//! When the centre of a rolling sphere traces a closed path, the sphere comes back
//! rotated: the holonomy. This crate computes it and plans paths that produce a
//! wanted rotation, for spherical robots and for teaching:
//!
//! - [`rectangle`]: the holonomy of a rectangle as the five-rotation product (2.4.2) and
//!   its transpose (2.4.5), the closed-form quaternion (2.4.6)–(2.4.7) (with the factor 2
//!   of ERRATA item 1), the components (B.1.2) (ERRATA item 3), the no-holonomy families
//!   (2.4.8) and the special paths (2.4.9) (ERRATA item 4);
//! - [`planner`]: every rectangle that produces a given rotation (App. C), in closed form,
//!   each verified by the forward product; [`appendix_c`] the thesis's root-finding route;
//! - [`euler`]: three rectangles for any rotation through the 3-2-3, 3-1-3, 3-2-1 and
//!   3-1-2 Euler angles (§2.5, ERRATA items 5, 6);
//! - [`mod@roll`]: kinematic rolling along any closed polygon or circle, (2.3.4)–(2.3.5),
//!   with an exact (Lie-group exponential) and an RK4 integrator;
//! - [`studies`]: what `rollstack sphere` and the tour report, as typed, serializable
//!   results: the holonomy report of a rectangle, the plans with their waypoints, rolling
//!   against the closed form and the integrators' speed-vs-error study, the level sets of
//!   Figure 2.5, and the worked examples (2.4.10), (2.4.12) with their printed values.
//!
//! Conventions: lengths of rectangles are angles (units of the sphere's radius R), all
//! angles are radians, components are on {A1, A2, A3 = E3}, and `R2 * R1` means R1 first.
//!
//! ```
//! use holonomy::{plan_rectangles, Direction, Rectangle};
//! use std::f64::consts::{FRAC_PI_2, PI};
//!
//! // The rectangle of Figure 2.1 and (2.4.10): ψ = 62.7042°, s = −0.389418 A1 − 0.921061 A3.
//! let rect = Rectangle::new(4.0 * PI / 3.0 - 0.5, FRAC_PI_2 - 0.4, 3.0 * PI, Direction::Ccw)?;
//! let aa = rotations::AxisAngle::from_rotation(&rect.holonomy());
//! assert!((aa.angle.to_degrees() - 62.7042).abs() < 5e-5);
//! assert!((aa.axis.x + 0.389418).abs() < 1e-6 && (aa.axis.z + 0.921061).abs() < 1e-6);
//!
//! // Back again: every rectangle that produces this rotation, each verified.
//! let plans = plan_rectangles(&rect.holonomy())?;
//! assert!(plans.iter().all(|p| p.error < 1e-12));
//! assert!(plans.iter().any(|p| (p.rectangle.theta - rect.theta).abs() < 1e-9
//!     && (p.rectangle.phi2 - rect.phi2).abs() < 1e-9));
//!
//! // The same as `rollstack sphere holonomy --json` prints it.
//! let report = holonomy::studies::report::holonomy_report(&rect);
//! assert!((report.e3_final[2] - 0.917896).abs() < 1e-6);
//! # Ok::<(), holonomy::HolonomyError>(())
//! ```
#![warn(missing_docs)]

pub mod appendix_c;
mod error;
pub mod euler;
pub mod placed;
pub mod planner;
pub mod rectangle;
pub mod roll;
pub mod studies;

pub use error::HolonomyError;
pub use euler::{euler_plan, euler_plan_for_rotation, EulerPlan};
pub use placed::PlacedRectangle;
pub use planner::{plan_rectangles, shortest, PlannedRectangle};
pub use rectangle::{
    holonomy_components, rectangle_holonomy, rectangle_holonomy_closed_form, Direction, Rectangle,
};
pub use roll::{circle_holonomy, polygon_holonomy, roll, CentrePath, Integrator, Trajectory};
