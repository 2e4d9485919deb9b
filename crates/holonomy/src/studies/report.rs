//! The holonomy of one rectangle in every form: what `rollstack sphere holonomy` prints
//! and writes to holonomy.csv.

use crate::rectangle::{
    holonomy_components, no_holonomy_family, rectangle_holonomy, rectangle_holonomy_closed_form,
    NoHolonomy, Rectangle,
};
use nalgebra::Vector3;
use rotations::report::matrix_rows;
use rotations::{quaternion_from_matrix, rotation_distance, AxisAngle};
use serde::{Deserialize, Serialize};
use std::fmt;

/// Tolerance on the angles (radians) for placing a rectangle in a no-holonomy family
/// (2.4.8).
pub const NO_HOLONOMY_TOLERANCE: f64 = 1e-12;

/// The holonomy S of one rectangle. Components on {A1, A2, A3 = E3}.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HolonomyReport {
    /// Canonical angle ψ in [0, π], rad.
    pub angle: f64,
    /// Canonical unit axis s on A1, A2, A3.
    pub axis: [f64; 3],
    /// Canonical quaternion [q0, q1, q2, q3], q0 ≥ 0.
    pub quaternion: [f64; 4],
    /// Rows of S: entry `[i][k]` = Aᵢ · S Aₖ.
    pub matrix: [[f64; 3]; 3],
    /// e3(t1) = S E3 on A1, A2, A3.
    pub e3_final: [f64; 3],
    /// The closed form (2.4.6) as computed (its sign, q0 may be negative).
    pub quaternion_closed_form: [f64; 4],
    /// Angle between the product (2.4.2) and the closed form (2.4.6), rad.
    pub closed_form_error: f64,
    /// Largest entry difference between the product and the components (B.1.2).
    pub components_error: f64,
    /// Path length 2(ϑ + φ2), units of R.
    pub path_length: f64,
    /// The no-holonomy family (2.4.8), if any.
    pub no_holonomy: Option<NoHolonomy>,
}

/// The holonomy of `rect` as the five-rotation product (2.4.2) (its transpose (2.4.5)
/// clockwise), in axis–angle, quaternion and matrix form, with e3(t1) = S E3, the
/// disagreement of the corrected closed form (2.4.6)–(2.4.7) (ERRATA item 1) and of the
/// components (B.1.2) (ERRATA item 3) with the product, and the family (2.4.8) if the
/// rectangle has no holonomy.
#[must_use]
pub fn holonomy_report(rect: &Rectangle) -> HolonomyReport {
    let s = rectangle_holonomy(rect);
    let aa = AxisAngle::from_rotation(&s);
    let q = quaternion_from_matrix(s.matrix());
    let qc = rectangle_holonomy_closed_form(rect);
    let e3 = s * Vector3::z();
    HolonomyReport {
        angle: aa.angle,
        axis: [aa.axis.x, aa.axis.y, aa.axis.z],
        quaternion: [q.w, q.i, q.j, q.k],
        matrix: matrix_rows(&s),
        e3_final: [e3.x, e3.y, e3.z],
        quaternion_closed_form: [qc.w, qc.i, qc.j, qc.k],
        closed_form_error: rotation_distance(&qc.to_rotation_matrix(), &s),
        components_error: (holonomy_components(rect) - s.matrix()).amax(),
        path_length: rect.path_length(),
        no_holonomy: no_holonomy_family(rect, NO_HOLONOMY_TOLERANCE),
    }
}

impl HolonomyReport {
    /// This report beside the rectangle it was computed for: its text and its CSV row
    /// ([`HolonomySummary`]).
    #[must_use]
    pub fn summary<'a>(&'a self, rectangle: &'a Rectangle) -> HolonomySummary<'a> {
        HolonomySummary {
            rectangle,
            report: self,
        }
    }
}

/// The holonomy of one rectangle with the rectangle itself: the readable text of
/// `rollstack sphere holonomy` (`Display`) and the row of its holonomy.csv
/// ([`HolonomySummary::CSV_HEADER`], [`HolonomySummary::csv_cells`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HolonomySummary<'a> {
    /// The rectangle Ŝ(ϑ, φ1, φ2, A1, A2, direction) (2.4.3).
    pub rectangle: &'a Rectangle,
    /// Its holonomy ([`holonomy_report`]).
    pub report: &'a HolonomyReport,
}

impl HolonomySummary<'_> {
    /// The columns of holonomy.csv: the rectangle (ϑ, φ1, φ2 in rad; `ccw` 1 or 0), the
    /// canonical angle ψ (rad) and axis s of S, and the rows of S (`s{i}{k}` = Aᵢ · S Aₖ).
    pub const CSV_HEADER: [&'static str; 17] = [
        "theta", "phi1", "phi2", "ccw", "angle", "axis1", "axis2", "axis3", "s11", "s12", "s13",
        "s21", "s22", "s23", "s31", "s32", "s33",
    ];

    /// The cells of the row under [`Self::CSV_HEADER`], numbers in shortest round-trip
    /// form.
    #[must_use]
    pub fn csv_cells(&self) -> Vec<String> {
        let (r, rep) = (self.rectangle, self.report);
        let mut cells: Vec<String> = [r.theta, r.phi1, r.phi2]
            .iter()
            .map(f64::to_string)
            .collect();
        cells.push(super::ccw_cell(r.direction));
        let numbers = std::iter::once(&rep.angle)
            .chain(&rep.axis)
            .chain(rep.matrix.iter().flatten());
        cells.extend(numbers.map(f64::to_string));
        cells
    }
}

impl fmt::Display for HolonomySummary<'_> {
    /// The rectangle, then ψ (rad and degrees) and s, e3(t1) = S E3, the disagreement of
    /// the product (2.4.2) with the closed form (2.4.6) and with the components (B.1.2),
    /// and the no-holonomy family (2.4.8) if any. Lines are separated by `\n`, with none
    /// after the last.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (r, rep) = (self.rectangle, self.report);
        writeln!(
            f,
            "S = Ŝ(ϑ = {}, φ1 = {}, φ2 = {}, {})",
            r.theta,
            r.phi1,
            r.phi2,
            r.direction.as_str()
        )?;
        writeln!(
            f,
            "  ψ = {:.9} rad ({:.6}°), s = [{:.6}, {:.6}, {:.6}]",
            rep.angle,
            rep.angle.to_degrees(),
            rep.axis[0],
            rep.axis[1],
            rep.axis[2]
        )?;
        writeln!(
            f,
            "  e3(t1) = [{:.6}, {:.6}, {:.6}]",
            rep.e3_final[0], rep.e3_final[1], rep.e3_final[2]
        )?;
        write!(
            f,
            "  product vs closed form (2.4.6): {:.1e} rad; vs components (B.1.2): {:.1e}",
            rep.closed_form_error, rep.components_error
        )?;
        if let Some(family) = &rep.no_holonomy {
            write!(f, "\n  no holonomy: {}", family.description())?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rectangle::Direction;
    use crate::studies::examples::{
        rectangle_2_4_10, PRINTED_ANGLE_2_4_10_DEG, PRINTED_AXIS_2_4_10,
    };
    use std::f64::consts::PI;

    #[test]
    fn reproduces_2_4_10() {
        let rep = holonomy_report(&rectangle_2_4_10());
        assert!((rep.angle.to_degrees() - PRINTED_ANGLE_2_4_10_DEG).abs() < 5e-5);
        for (a, b) in rep.axis.iter().zip(PRINTED_AXIS_2_4_10) {
            assert!((a - b).abs() < 1e-6);
        }
        // e3(t1) printed after (2.4.10).
        for (a, b) in rep.e3_final.iter().zip([0.194_194, 0.346_057, 0.917_896]) {
            assert!((a - b).abs() < 1e-6);
        }
        assert!(rep.closed_form_error < 1e-14 && rep.components_error < 1e-14);
        assert!(rep.quaternion[0] >= 0.0);
        assert_eq!(rep.no_holonomy, None);
        assert!((rep.path_length - 2.0 * (4.0 * PI / 3.0 - 0.5 + 3.0 * PI)).abs() < 1e-14);
    }

    #[test]
    fn flags_the_no_holonomy_families() {
        let r = Rectangle::new(2.0 * PI, 0.5, 2.0, Direction::Cw).unwrap();
        let rep = holonomy_report(&r);
        assert_eq!(rep.no_holonomy, Some(NoHolonomy::ThetaMultipleOfTwoPi));
        assert!(rep.angle < 1e-12);
        let text = rep.summary(&r).to_string();
        assert!(text.starts_with("S = Ŝ(ϑ = 6.283185307179586, φ1 = 0.5, φ2 = 2, cw)\n"));
        assert!(text.ends_with("\n  no holonomy: (2.4.8)₂: ϑ a multiple of 2π"));
        assert_eq!(
            serde_json::to_value(&rep).unwrap()["no_holonomy"],
            "theta_multiple_of_two_pi"
        );
        for family in [
            NoHolonomy::OddMultiplesOfPi,
            NoHolonomy::ThetaMultipleOfTwoPi,
            NoHolonomy::Phi2MultipleOfTwoPi,
        ] {
            assert_eq!(serde_json::to_value(family).unwrap(), family.name());
        }
    }

    #[test]
    fn text_and_csv_row_of_2_4_10() {
        let rect = rectangle_2_4_10();
        let rep = holonomy_report(&rect);
        let summary = rep.summary(&rect);
        let text = summary.to_string();
        assert_eq!(text.lines().count(), 4);
        // ψ in degrees as printed after (2.4.10), and e3(t1).
        assert!(text.contains(&format!("({:.6}°)", rep.angle.to_degrees())));
        assert!(text.contains("e3(t1) = [0.194194, 0.346057, 0.917896]"));
        let cells = summary.csv_cells();
        assert_eq!(cells.len(), HolonomySummary::CSV_HEADER.len());
        assert_eq!(cells[3], "1");
        assert_eq!(cells[4], rep.angle.to_string());
        assert_eq!(cells[16], rep.matrix[2][2].to_string());
    }
}
