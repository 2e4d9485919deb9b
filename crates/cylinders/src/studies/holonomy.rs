//! The holonomy Δφ when the contact point P traces a rectangle or a circle (§3.4, values
//! in radians per ERRATA 8), each checked by rolling the cylinder along the path
//! ([`crate::rolling::roll`]): what `rollstack cylinder holonomy rectangle|circle` prints,
//! and the traces of Figures 3.10 and 3.12.

use crate::error::CylinderError;
use crate::holonomy::{initial_axis, CirclePath, RectanglePath};
use crate::kinematics::{check_point_contact, Cylinder, Pose};
use crate::rolling::{circle_motion, rectangle_segments, roll, RollingTrace, Sample};
use nalgebra::Vector3;
use rotations::{rotation_distance, AxisAngle};
use serde::{Deserialize, Serialize};
use std::fmt;

/// How finely the rolled check integrates and records.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RollSettings {
    /// Largest rotation per integration step, rad.
    pub max_step: f64,
    /// Record a sample every this many steps (and the last one).
    pub record_every: usize,
}

/// The holonomy of a rectangle traced by P. The field names are the keys of
/// `rollstack cylinder holonomy rectangle --json` (docs/cli.md), those of docs/cli.md
/// first.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RectangleReport {
    /// Δφ = ±(φ1 + φ2), rad, (3.4.6)–(3.4.8).
    pub delta_phi: f64,
    /// Angle between the nine-rotation product (3.4.3) and A(Δφ, ₀e3), rad.
    pub product_error: f64,
    /// ₀e3 of (3.4.4) on E1, E2, E3.
    pub axis: [f64; 3],
    /// Canonical angle of the product in [0, π], rad.
    pub product_angle: f64,
    /// Quaternion of the raw product (sign kept), compare (3.4.9).
    pub product_quaternion: [f64; 4],
    /// Δφ measured on the orientation integrated along the path (unwrapped), rad.
    pub rolling_delta_phi: f64,
    /// Angle between the integrated net rotation and A(Δφ, ₀e3), rad.
    pub rolling_error: f64,
    /// ‖x̄_end − x̄_0‖ of the integrated motion (units of the cylinder's lengths).
    pub rolling_closure_error: f64,
}

impl RectangleReport {
    /// This report with the path it was computed for, for its text
    /// ([`RectangleSummary`]).
    #[must_use]
    pub fn summary<'a>(&'a self, path: &'a RectanglePath) -> RectangleSummary<'a> {
        RectangleSummary { path, report: self }
    }
}

/// The readable text of `rollstack cylinder holonomy rectangle` (`Display`): the
/// holonomy of a rectangle with the path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RectangleSummary<'a> {
    /// The rectangle traced by P (its case and direction are shown).
    pub path: &'a RectanglePath,
    /// Its holonomy ([`rectangle_report`]).
    pub report: &'a RectangleReport,
}

impl fmt::Display for RectangleSummary<'_> {
    /// Δφ (rad) of (3.4.3) with the case and direction, the disagreement of the product
    /// with the closed form (3.4.5) (rad), and Δφ and the error (rad) of the rolled
    /// check. Lines are separated by `\n`, with none after the last.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let rep = self.report;
        writeln!(
            f,
            "Rectangle (3.4.3): Δφ = {:.9} rad (case {}, {})",
            rep.delta_phi,
            self.path.case.name(),
            self.path.direction.name()
        )?;
        writeln!(
            f,
            "  product vs closed form (3.4.5): {:.1e} rad",
            rep.product_error
        )?;
        write!(
            f,
            "  rolled along the path: Δφ = {:.9} rad, error {:.1e} rad",
            rep.rolling_delta_phi, rep.rolling_error
        )
    }
}

/// The holonomy of the rectangle `path` traced by P of `cylinder` at inclination
/// `theta`, starting at precession `psi0`: Δφ in closed form (3.4.5)–(3.4.8) (radians,
/// ERRATA 8), the nine-rotation product (3.4.3) with its quaternion (compare (3.4.9))
/// and its distance to the closed form, and the same holonomy measured by rolling the
/// cylinder along the path ([`roll`] with `settings`). Returns the rolled trace too:
/// the traces of P and of a rim point of Figure 3.10.
///
/// # Errors
/// ϑ outside (0, π/2) ([`CylinderError::NotPointContact`]), a `psi0` that is not finite
/// (every rotation would be NaN), a `settings.max_step` that is not positive, a ϑ so
/// close to 0 or π/2 that the trace overflows ([`CylinderError::NotFinite`]).
pub fn rectangle_report(
    cylinder: &Cylinder,
    theta: f64,
    path: &RectanglePath,
    psi0: f64,
    settings: RollSettings,
) -> Result<(RectangleReport, RollingTrace), CylinderError> {
    let theta = check_point_contact(theta)?;
    input::finite("psi0", psi0)?;
    let q = path.product_quaternion(theta, psi0);
    let product = q.to_rotation_matrix();
    let closed = path.closed_form(theta, psi0);
    let pose = Pose::on_plane(cylinder, 0.0, 0.0, [psi0, theta, 0.0]);
    let trace = roll(
        cylinder,
        &pose,
        &rectangle_segments(path),
        settings.max_step,
        settings.record_every,
    )?;
    if !trace.is_finite() {
        return Err(CylinderError::NotFinite(theta));
    }
    let axis = initial_axis(theta, psi0);
    let report = RectangleReport {
        delta_phi: path.delta_phi(),
        product_error: rotation_distance(&product, &closed),
        axis: [axis.x, axis.y, axis.z],
        product_angle: AxisAngle::from_rotation(&product).angle,
        product_quaternion: [q.w, q.i, q.j, q.k],
        rolling_delta_phi: trace.delta_phi(),
        rolling_error: rotation_distance(&trace.net_rotation, &closed),
        rolling_closure_error: trace.closure_error(),
    };
    Ok((report, trace))
}

/// The holonomy of a circle traced by P. The field names are the keys of
/// `rollstack cylinder holonomy circle --json` (docs/cli.md), those of docs/cli.md
/// first.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CircleReport {
    /// Δφ = ±2πℓ/r, rad, (3.4.16).
    pub delta_phi: f64,
    /// Radius of the circle of the centre of mass, (3.4.15) (ERRATA 15 for Case II).
    pub k: f64,
    /// φ̇0/ψ̇0 from (3.4.14).
    pub rate_ratio: f64,
    /// Δφ measured on the orientation integrated around the circle (unwrapped), rad.
    pub rolling_delta_phi: f64,
    /// ‖x̄_end − x̄_0‖ of the integrated motion.
    pub rolling_closure_error: f64,
}

impl CircleReport {
    /// This report with the path it was computed for, for its text
    /// ([`CircleSummary`]).
    #[must_use]
    pub fn summary<'a>(&'a self, path: &'a CirclePath) -> CircleSummary<'a> {
        CircleSummary { path, report: self }
    }
}

/// The readable text of `rollstack cylinder holonomy circle` (`Display`): the holonomy
/// of a circle with the path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CircleSummary<'a> {
    /// The circle traced by P (its case and direction are shown).
    pub path: &'a CirclePath,
    /// Its holonomy ([`circle_report`]).
    pub report: &'a CircleReport,
}

impl fmt::Display for CircleSummary<'_> {
    /// Δφ (rad) of (3.4.16) and the radius k of the centre's circle (3.4.15) with the case
    /// and direction, and Δφ (rad) of the rolled check. Lines are separated by `\n`, with
    /// none after the last.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let rep = self.report;
        writeln!(
            f,
            "Circle (3.4.16): Δφ = {:.9} rad, k = {:.9} (case {}, {})",
            rep.delta_phi,
            rep.k,
            self.path.case.name(),
            self.path.direction.name()
        )?;
        write!(
            f,
            "  rolled around the circle: Δφ = {:.9} rad",
            rep.rolling_delta_phi
        )
    }
}

/// The holonomy of the circle `path` traced by P of `cylinder` at inclination `theta`:
/// Δφ = ±2πℓ/r (3.4.16) (radians, ERRATA 8), the radius k of the centre's circle
/// (3.4.15) (ERRATA 15) and the rate ratio (3.4.14), and Δφ measured by rolling once
/// around the circle ([`circle_motion`], [`roll`] with `settings`). Returns the rolled
/// trace too: the traces of Figure 3.12.
///
/// # Errors
/// ϑ outside (0, π/2), k ≤ 0 ([`CylinderError::DegenerateCircle`]), a
/// `settings.max_step` that is not positive.
pub fn circle_report(
    cylinder: &Cylinder,
    theta: f64,
    path: &CirclePath,
    settings: RollSettings,
) -> Result<(CircleReport, RollingTrace), CylinderError> {
    let hol = path.holonomy(cylinder, theta)?;
    let (pose, segment) = circle_motion(cylinder, theta, path)?;
    let trace = roll(
        cylinder,
        &pose,
        &[segment],
        settings.max_step,
        settings.record_every,
    )?;
    let report = CircleReport {
        delta_phi: hol.delta_phi,
        k: hol.k,
        rate_ratio: hol.rate_ratio,
        rolling_delta_phi: trace.delta_phi(),
        rolling_closure_error: trace.closure_error(),
    };
    Ok((report, trace))
}

/// A rolled trace seen from above (E1, E2 components): the curves of Figures 3.10 and
/// 3.12.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlanView {
    /// The trace of the contact point P (curve i).
    pub contact: Vec<(f64, f64)>,
    /// The trace of the rim point X (curve ii).
    pub rim_point: Vec<(f64, f64)>,
    /// The trace of the centre of mass.
    pub center: Vec<(f64, f64)>,
    /// The start S of the centre of mass.
    pub start: (f64, f64),
    /// The rim point's start A.
    pub rim_start: (f64, f64),
    /// The rim point's end B.
    pub rim_end: (f64, f64),
}

/// The plan view of `trace`; `None` for a trace without samples.
#[must_use]
pub fn plan_view(trace: &RollingTrace) -> Option<PlanView> {
    let (first, last) = (trace.samples.first()?, trace.samples.last()?);
    let xy = |v: &Vector3<f64>| (v.x, v.y);
    let curve = |f: fn(&Sample) -> &Vector3<f64>| trace.samples.iter().map(|s| xy(f(s))).collect();
    Some(PlanView {
        contact: curve(|s| &s.contact),
        rim_point: curve(|s| &s.rim_point),
        center: curve(|s| &s.center),
        start: xy(&first.center),
        rim_start: xy(&first.rim_point),
        rim_end: xy(&last.rim_point),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::holonomy::{figure_3_12, Direction, Figure310, PathCase};
    use std::f64::consts::PI;

    const COARSE: RollSettings = RollSettings {
        max_step: 2e-3,
        record_every: 10,
    };

    #[test]
    fn an_inclination_a_few_ulps_from_zero_is_refused_not_returned_as_nan() {
        let cylinder = Cylinder::new(1.0, 1.0 / 0.12).unwrap();
        let path =
            RectanglePath::new(1.0, 2.0, 0.0, PathCase::I, Direction::CounterClockwise).unwrap();
        for theta in [5e-324, 1e-300] {
            let got = rectangle_report(&cylinder, theta, &path, 0.0, COARSE);
            assert!(
                matches!(got, Err(CylinderError::NotFinite(t)) if t == theta),
                "{theta}: {got:?}"
            );
            // Printed short, as typed, not as 324 digits.
            let message = got.unwrap_err().to_string();
            assert!(message.contains(&format!("ϑ = {theta:e} rad")), "{message}");
        }
    }

    #[test]
    fn figure_3_10_in_radians() {
        let fig = Figure310::new(PathCase::I);
        let (rep, trace) =
            rectangle_report(&fig.cylinder, fig.theta, &fig.path, 0.0, COARSE).unwrap();
        // ERRATA 8: Δφ = 139π/12 = 36.3901 rad.
        assert!((rep.delta_phi - 139.0 * PI / 12.0).abs() < 1e-13);
        assert!(rep.product_error < 1e-12);
        assert!((rep.rolling_delta_phi - rep.delta_phi).abs() < 1e-8);
        assert!(rep.rolling_error < 1e-8 && rep.rolling_closure_error < 1e-8);
        assert!((0.0..=PI).contains(&rep.product_angle));
        let text = rep.summary(&fig.path).to_string();
        assert!(text.starts_with("Rectangle (3.4.3): Δφ = 36.390114904 rad (case I, "));
        assert_eq!(text.lines().count(), 3);
        assert!(text.ends_with(&format!("error {:.1e} rad", rep.rolling_error)));
        let view = plan_view(&trace).unwrap();
        assert_eq!(view.contact.len(), trace.samples.len());
        assert_eq!(view.start, (0.0, 0.0));
        let bad = rectangle_report(&fig.cylinder, 0.0, &fig.path, 0.0, COARSE);
        assert!(matches!(bad, Err(CylinderError::NotPointContact(_))));
        // Python's holonomy_rectangle(psi0=inf) calls this: an error, not NaN arrays.
        for psi0 in [f64::INFINITY, f64::NAN] {
            let bad = rectangle_report(&fig.cylinder, fig.theta, &fig.path, psi0, COARSE);
            let err = bad.map(|_| ()).unwrap_err().to_string();
            assert_eq!(err, "psi0 is not finite");
        }
    }

    #[test]
    fn figure_3_12_both_cases() {
        let (cylinder, theta, ell) = figure_3_12();
        for (case, k) in [(PathCase::I, 25.0 / 3.0), (PathCase::II, 10.5515)] {
            let path = CirclePath::new(ell, case, Direction::CounterClockwise).unwrap();
            let (rep, _) = circle_report(&cylinder, theta, &path, COARSE).unwrap();
            assert!((rep.delta_phi.abs() - 59.3283).abs() < 5e-5, "{case:?}");
            assert!((rep.k - k).abs() < 1e-4, "{case:?}");
            assert!((rep.rolling_delta_phi - rep.delta_phi).abs() < 1e-8);
            let text = rep.summary(&path).to_string();
            let first = format!(
                "Δφ = {:.9} rad, k = {:.9} (case {}, counter-clockwise)",
                rep.delta_phi,
                rep.k,
                case.name()
            );
            assert!(text.lines().next().unwrap().ends_with(&first), "{text}");
            assert_eq!(text.lines().count(), 2);
        }
        let small = CirclePath::new(0.5, PathCase::I, Direction::CounterClockwise).unwrap();
        let bad = circle_report(&cylinder, theta, &small, COARSE);
        assert!(matches!(bad, Err(CylinderError::DegenerateCircle { .. })));
    }
}
