//! The rectangles of the two planners with the paths a robot would follow: every
//! rectangle producing a target rotation (App. C), what `rollstack sphere plan` prints
//! and writes to plan.csv, and the three rectangles of an Euler plan (§2.5), what
//! `rollstack sphere euler-plan` prints and writes to euler_plan.csv.

use crate::euler::EulerPlan;
use crate::placed::PlacedRectangle;
use crate::planner::{plan_rectangles, shortest};
use crate::rectangle::{Direction, Rectangle};
use crate::HolonomyError;
use nalgebra::Rotation3;
use rotations::report::matrix_rows;
use serde::{Deserialize, Serialize};
use std::fmt;

/// One rectangle of a plan, placed on the ground, with the corners of the centre's path.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RectangleReport {
    /// ϑ, rad.
    pub theta: f64,
    /// φ1, rad.
    pub phi1: f64,
    /// φ2, rad.
    pub phi2: f64,
    /// Direction of travel (`ccw` or `cw`).
    pub direction: Direction,
    /// Angle of R_targetᵀ S (plan), or between the rectangle's holonomy and its Euler
    /// factor R(νᵢ, gᵢ) (euler-plan), rad.
    pub error: f64,
    /// Corners of the centre's path, ground coordinates in units of R, in order of travel.
    pub waypoints: Vec<[f64; 2]>,
    /// Path length 2(ϑ + φ2), units of R.
    pub path_length: f64,
    /// Heading of A1 from E1, rad (0 for `plan`).
    pub heading: f64,
    /// True when any φ1 in [0, φ2] works ((2.4.9)₂).
    pub phi1_free: bool,
}

impl RectangleReport {
    /// The report of a placed rectangle (Figure 2.3, turned by its heading for §2.5),
    /// with the `error` of its holonomy against what it stands for and whether φ1 is
    /// free ((2.4.9)₂).
    #[must_use]
    pub fn new(placed: &PlacedRectangle, error: f64, phi1_free: bool) -> Self {
        let r = placed.rectangle;
        Self {
            theta: r.theta,
            phi1: r.phi1,
            phi2: r.phi2,
            direction: r.direction,
            error,
            waypoints: placed.waypoints(),
            path_length: r.path_length(),
            heading: placed.heading,
            phi1_free,
        }
    }

    /// The rectangle Ŝ(ϑ, φ1, φ2, A1, A2, direction) in its own frame (2.4.3).
    #[must_use]
    pub fn rectangle(&self) -> Rectangle {
        Rectangle {
            theta: self.theta,
            phi1: self.phi1,
            phi2: self.phi2,
            direction: self.direction,
        }
    }

    /// The columns of plan.csv: ϑ, φ1, φ2 (rad), `ccw` (1 or 0), the error (rad), the
    /// path length 2(ϑ + φ2) (units of R), then the six corners of the centre's path in
    /// order of travel, from S back to S ([`Rectangle::waypoints`]): `x1`, `y1` … `x6`,
    /// `y6` (ground coordinates, units of R), as the JSON's `waypoints`.
    pub const PLAN_CSV_HEADER: [&'static str; 18] = [
        "theta",
        "phi1",
        "phi2",
        "ccw",
        "error",
        "path_length",
        "x1",
        "y1",
        "x2",
        "y2",
        "x3",
        "y3",
        "x4",
        "y4",
        "x5",
        "y5",
        "x6",
        "y6",
    ];

    /// The cells of this rectangle's row under [`Self::PLAN_CSV_HEADER`], numbers in
    /// shortest round-trip form; waypoint cells beyond the path's corners (never for a
    /// rectangle's six) are empty.
    #[must_use]
    pub fn plan_csv_cells(&self) -> Vec<String> {
        let mut cells = vec![
            self.theta.to_string(),
            self.phi1.to_string(),
            self.phi2.to_string(),
            super::ccw_cell(self.direction),
            self.error.to_string(),
            self.path_length.to_string(),
        ];
        let corners = (Self::PLAN_CSV_HEADER.len() - cells.len()) / 2;
        for k in 0..corners {
            match self.waypoints.get(k) {
                Some([x, y]) => cells.extend([x.to_string(), y.to_string()]),
                None => cells.extend([String::new(), String::new()]),
            }
        }
        cells
    }
}

/// Every rectangle (φ2 in [0, 3π]) that produces a target rotation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlanReport {
    /// Every solution with φ2 in [0, 3π], at the origin with heading 0.
    pub rectangles: Vec<RectangleReport>,
    /// Index into `rectangles` of the shortest path.
    pub shortest: Option<usize>,
    /// Largest verified error, rad.
    pub max_error: f64,
}

impl PlanReport {
    /// The first rectangle within `tol` (radians, in each of ϑ, φ1, φ2) of the given
    /// one: to look up a rectangle printed in the thesis, e.g. in (2.4.12).
    #[must_use]
    pub fn find(&self, rect: &Rectangle, tol: f64) -> Option<&RectangleReport> {
        self.rectangles.iter().find(|r| {
            r.direction == rect.direction
                && (r.theta - rect.theta).abs() < tol
                && (r.phi1 - rect.phi1).abs() < tol
                && (r.phi2 - rect.phi2).abs() < tol
        })
    }
}

impl fmt::Display for PlanReport {
    /// How many rectangles there are, then one line each: ϑ, φ1, φ2 (rad), the direction,
    /// the path length 2(ϑ + φ2) (units of R) and the error (rad), the shortest marked.
    /// Lines are separated by `\n`, with none after the last.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} rectangle(s) with φ2 in [0, 3π]:",
            self.rectangles.len()
        )?;
        for (i, r) in self.rectangles.iter().enumerate() {
            let mark = if self.shortest == Some(i) {
                "  <- shortest"
            } else {
                ""
            };
            write!(
                f,
                "\n  ϑ = {:.6}, φ1 = {:.6}, φ2 = {:.6}, {:>3}, length {:.4} R, error {:.1e}{mark}",
                r.theta,
                r.phi1,
                r.phi2,
                r.direction.as_str(),
                r.path_length,
                r.error
            )?;
        }
        Ok(())
    }
}

/// Every rectangle whose holonomy is `target` (components on {A1, A2, A3}) by the
/// closed-form inverse of (2.4.6) that replaces the root finding of App. C
/// ([`plan_rectangles`]), each verified against the forward product (2.4.2), with the
/// shortest path 2(ϑ + φ2)R marked.
///
/// # Errors
/// A non-finite target, or the identity ([`HolonomyError::IdentityTarget`]).
pub fn plan_report(target: &Rotation3<f64>) -> Result<PlanReport, HolonomyError> {
    let plans = plan_rectangles(target)?;
    let best = shortest(&plans).and_then(|b| plans.iter().position(|p| p == b));
    let rectangles = plans
        .iter()
        .map(|p| {
            RectangleReport::new(
                &PlacedRectangle::at_origin(p.rectangle),
                p.error,
                p.phi1_free,
            )
        })
        .collect();
    let max_error = plans.iter().map(|p| p.error).fold(0.0, f64::max);
    Ok(PlanReport {
        rectangles,
        shortest: best,
        max_error,
    })
}

/// The three rectangles of an Euler plan and how well they compose to the target.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EulerPlanReport {
    /// The three rectangles in order of travel (ground frame).
    pub rectangles: Vec<RectangleReport>,
    /// Angle of R_targetᵀ R_achieved, rad.
    pub error: f64,
    /// The set.
    pub set: String,
    /// The angles used (ν1, ν3 reduced to [0, 2π)).
    pub angles: [f64; 3],
    /// Rows of the target (components on E).
    pub target_matrix: [[f64; 3]; 3],
}

impl EulerPlanReport {
    /// The columns of euler_plan.csv: the rectangle's number in order of travel (1–3),
    /// ϑ, φ1, φ2 (rad), `ccw` (1 or 0) and the heading of A1 from E1 (rad).
    pub const CSV_HEADER: [&'static str; 6] =
        ["rectangle", "theta", "phi1", "phi2", "ccw", "heading"];

    /// One row of cells per rectangle under [`Self::CSV_HEADER`], numbers in shortest
    /// round-trip form.
    #[must_use]
    pub fn csv_rows(&self) -> Vec<Vec<String>> {
        self.rectangles
            .iter()
            .zip(1u8..)
            .map(|(r, number)| {
                vec![
                    number.to_string(),
                    r.theta.to_string(),
                    r.phi1.to_string(),
                    r.phi2.to_string(),
                    super::ccw_cell(r.direction),
                    r.heading.to_string(),
                ]
            })
            .collect()
    }
}

impl fmt::Display for EulerPlanReport {
    /// The set, the angles (ν1, ν2, ν3) (rad) and the error of the composition (rad), then
    /// one line per rectangle: ϑ, φ1, φ2 (rad), the direction and the heading (rad).
    /// Lines are separated by `\n`, with none after the last.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} angles (ν1, ν2, ν3) = ({:.6}, {:.6}, {:.6}); composed error {:.1e} rad",
            self.set, self.angles[0], self.angles[1], self.angles[2], self.error
        )?;
        for (i, r) in self.rectangles.iter().enumerate() {
            write!(
                f,
                "\n  {}: ϑ = {:.6}, φ1 = {:.6}, φ2 = {:.6}, {:>3}, heading {:.6}",
                i + 1,
                r.theta,
                r.phi1,
                r.phi2,
                r.direction.as_str(),
                r.heading
            )?;
        }
        Ok(())
    }
}

/// The report of an Euler plan of §2.5 ((2.5.7)–(2.5.20), ERRATA items 5, 6). Each
/// rectangle's `error` is the angle between its holonomy and the elementary rotation
/// R(νᵢ, gᵢ) (A.1.4) it stands for; `error` is that of the composition S3 S2 S1.
#[must_use]
pub fn euler_plan_report(plan: &EulerPlan) -> EulerPlanReport {
    EulerPlanReport {
        rectangles: plan
            .rectangles
            .iter()
            .zip(plan.rectangle_errors)
            .map(|(p, e)| RectangleReport::new(p, e, false))
            .collect(),
        error: plan.error,
        set: plan.set.clone(),
        angles: plan.angles,
        target_matrix: matrix_rows(&plan.target),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::euler::euler_plan;
    use crate::studies::examples::{
        target_2_4_12, PRINTED_RECTANGLES_2_4_12, PRINTED_TOLERANCE_2_4_12,
    };
    use rotations::EulerSet;

    #[test]
    fn plan_of_2_4_12() {
        let rep = plan_report(&target_2_4_12().unwrap()).unwrap();
        assert!(rep.max_error < 1e-12);
        let best = &rep.rectangles[rep.shortest.unwrap()];
        assert!(rep
            .rectangles
            .iter()
            .all(|r| r.path_length >= best.path_length));
        for [theta, phi1, phi2] in PRINTED_RECTANGLES_2_4_12 {
            let printed = Rectangle::new(theta, phi1, phi2, Direction::Ccw).unwrap();
            let found = rep.find(&printed, PRINTED_TOLERANCE_2_4_12).unwrap();
            assert_eq!(found.waypoints, found.rectangle().waypoints());
            assert_eq!(found.heading, 0.0);
            assert!((found.path_length - 2.0 * (found.theta + found.phi2)).abs() < 1e-14);
        }
        assert!(plan_report(&Rotation3::identity()).is_err());
    }

    #[test]
    fn plan_text_and_csv() {
        let rep = plan_report(&target_2_4_12().unwrap()).unwrap();
        let text = rep.to_string();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), rep.rectangles.len() + 1);
        assert_eq!(
            lines[0],
            format!("{} rectangle(s) with φ2 in [0, 3π]:", rep.rectangles.len())
        );
        let best = rep.shortest.unwrap();
        assert!(lines[best + 1].ends_with("  <- shortest"));
        assert_eq!(text.matches("<- shortest").count(), 1);
        let r = &rep.rectangles[best];
        assert!(lines[best + 1].contains(&format!("ϑ = {:.6}, φ1 = {:.6}", r.theta, r.phi1)));
        let cells = r.plan_csv_cells();
        assert_eq!(cells.len(), RectangleReport::PLAN_CSV_HEADER.len());
        assert_eq!(cells[0], r.theta.to_string());
        assert_eq!(cells[3], "1");
        assert_eq!(cells[5], r.path_length.to_string());
        // The corners, as the JSON's waypoints: x1, y1 … x6, y6, S to S.
        assert_eq!(r.waypoints.len(), 6);
        assert_eq!(RectangleReport::PLAN_CSV_HEADER[6], "x1");
        assert_eq!(RectangleReport::PLAN_CSV_HEADER[17], "y6");
        for (k, [x, y]) in r.waypoints.iter().enumerate() {
            assert_eq!(cells[6 + 2 * k], x.to_string());
            assert_eq!(cells[7 + 2 * k], y.to_string());
        }
        assert_eq!(cells[6], "0");
        assert_eq!(cells[16..], ["0", "0"]);
    }

    #[test]
    fn euler_plan_report_of_3_2_1() {
        let set = EulerSet::from_name("3-2-1").unwrap();
        let plan = euler_plan(set, [0.3, -0.5, 2.0]).unwrap();
        let rep = euler_plan_report(&plan);
        assert_eq!(rep.set, "3-2-1");
        assert!(rep.error < 1e-12);
        assert_eq!(rep.rectangles.len(), 3);
        for (r, p) in rep.rectangles.iter().zip(&plan.rectangles) {
            assert!(r.error < 1e-12 && !r.phi1_free);
            assert_eq!(r.waypoints.len(), 6);
            assert_eq!(r.rectangle(), p.rectangle);
            assert_eq!(r.heading, p.heading);
        }
        // ν2 < 0: the second rectangle is travelled clockwise (ERRATA item 6).
        assert_eq!(rep.rectangles[1].direction, Direction::Cw);
        assert_eq!(rep.target_matrix[1][2], plan.target.matrix()[(1, 2)]);
        let text = rep.to_string();
        assert!(text.starts_with("3-2-1 angles (ν1, ν2, ν3) = (0.300000, -0.500000, 2.000000)"));
        assert_eq!(text.lines().count(), 4);
        assert!(text.lines().nth(2).unwrap().contains(" cw, heading "));
        let rows = rep.csv_rows();
        assert_eq!(rows.len(), 3);
        for (k, row) in rows.iter().enumerate() {
            assert_eq!(row.len(), EulerPlanReport::CSV_HEADER.len());
            assert_eq!(row[0], (k + 1).to_string());
        }
        assert_eq!(rows[1][4], "0");
        assert_eq!(rows[2][5], rep.rectangles[2].heading.to_string());
    }
}
