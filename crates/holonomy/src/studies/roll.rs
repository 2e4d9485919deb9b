//! Rolling along a closed path by integrating the rolling constraint (2.3.4)–(2.3.5),
//! checked against the holonomy in closed form: what `rollstack sphere roll` prints, and
//! the speed-vs-error study of the two integrators (`--study`, roll_study.csv).
//!
//! The sphere has radius R = 1: lengths are in units of R.

use crate::rectangle::{rectangle_holonomy, Direction, Rectangle};
use crate::roll::{
    axis_angle, circle_holonomy, polygon_holonomy, roll, CentrePath, Integrator, Trajectory,
};
use crate::studies::examples::rectangle_2_4_10;
use crate::HolonomyError;
use nalgebra::Rotation3;
use rotations::rotation_distance;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::time::Instant;

/// The shape of a closed path of the centre, in units of R.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum PathShape {
    /// A rectangle of §2.4 starting at the origin (Figure 2.3).
    Rectangle(Rectangle),
    /// A circle through the origin, starting along +E1 ([`CentrePath::circle`]).
    Circle {
        /// Its radius ρ, units of R.
        radius: f64,
        /// Turning left (ccw) or right (cw).
        direction: Direction,
    },
    /// The closed polygon through these vertices (E1, E2 components, units of R).
    Polygon(Vec<[f64; 2]>),
}

/// A closed path of the centre and its holonomy in closed form.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ClosedPath {
    /// The path, in units of R.
    pub path: CentrePath,
    /// The holonomy of rolling once along it, in closed form: (2.4.2) for a rectangle,
    /// [`circle_holonomy`] for a circle, [`polygon_holonomy`] for a polygon.
    pub holonomy: Rotation3<f64>,
    /// What the path is, for reports: `rectangle`, `circle of radius 2 R`,
    /// `polygon of 4 sides`.
    pub label: String,
}

impl ClosedPath {
    /// The path of a shape and its closed-form holonomy, for a sphere of radius 1: the
    /// product (2.4.2) (transposed (2.4.5) clockwise) for a rectangle, one rotation by
    /// 2π√(1 + ρ²) for a circle ([`circle_holonomy`]), the product of the sides'
    /// rotations (2.3.5) for a polygon ([`polygon_holonomy`]).
    ///
    /// # Errors
    /// A circle radius that is not finite and positive, a polygon with non-finite
    /// vertices or fewer than two distinct ones, a rectangle with fewer than two sides.
    pub fn new(shape: &PathShape) -> Result<Self, HolonomyError> {
        Ok(match shape {
            PathShape::Circle { radius, direction } => Self {
                path: CentrePath::circle(*radius, *direction)?,
                holonomy: circle_holonomy(*radius, 1.0, *direction)?,
                label: format!("circle of radius {radius} R"),
            },
            PathShape::Polygon(vertices) => {
                let path = CentrePath::polygon(vertices)?;
                Self {
                    holonomy: polygon_holonomy(&path, 1.0)?,
                    // Zero-length edges were dropped: count the sides rolled along.
                    label: format!("polygon of {} sides", path.segments().len()),
                    path,
                }
            }
            PathShape::Rectangle(rect) => Self {
                path: CentrePath::rectangle(rect, 1.0)?,
                holonomy: rectangle_holonomy(rect),
                label: "rectangle".into(),
            },
        })
    }
}

/// One roll along a closed path, against the closed form.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RollReport {
    /// Canonical angle of the final orientation, rad.
    pub angle: f64,
    /// Canonical axis of the final orientation on A1, A2, A3.
    pub axis: [f64; 3],
    /// Angle between the integrated and the closed-form holonomy, rad.
    pub error_vs_closed_form: f64,
    /// `exact` or `rk4`.
    pub integrator: Integrator,
    /// Steps taken.
    pub steps: usize,
    /// Path length, units of R.
    pub path_length: f64,
    /// Wall time of the integration, s.
    pub wall_time_s: f64,
}

/// Rolls once along `closed` with about `steps` steps of `integrator`, integrating
/// Q′ = skewt(ω) Q with ω = E3 × d (2.3.4)–(2.3.5) ([`roll`]), and reports the final
/// orientation, its angle to the closed-form holonomy and the wall time. Returns the
/// trajectory too (centre, marked point X and orientation: the traces of Figure 2.1).
///
/// # Errors
/// `steps` smaller than the number of sides.
pub fn roll_report(
    closed: &ClosedPath,
    integrator: Integrator,
    steps: usize,
) -> Result<(RollReport, Trajectory), HolonomyError> {
    let start = Instant::now();
    let trajectory = roll(&closed.path, 1.0, integrator, steps)?;
    let seconds = start.elapsed().as_secs_f64();
    let q = trajectory.final_orientation();
    let (angle, axis) = axis_angle(&q);
    let report = RollReport {
        angle,
        axis: [axis.x, axis.y, axis.z],
        error_vs_closed_form: rotation_distance(&q.to_rotation_matrix(), &closed.holonomy),
        integrator,
        steps,
        path_length: closed.path.length(),
        wall_time_s: seconds,
    };
    Ok((report, trajectory))
}

impl RollReport {
    /// This report with what it does not hold for its text: the path's label
    /// ([`ClosedPath::label`]) and the rows of the integrator study, if one was run
    /// ([`RollSummary`]).
    #[must_use]
    pub fn summary<'a>(&'a self, label: &'a str, study: Option<&'a [StudyRow]>) -> RollSummary<'a> {
        RollSummary {
            label,
            report: self,
            study,
        }
    }
}

/// The readable text of `rollstack sphere roll` (`Display`): one roll along a labelled
/// path and, optionally, the integrator study.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RollSummary<'a> {
    /// What the path is ([`ClosedPath::label`]).
    pub label: &'a str,
    /// The roll ([`roll_report`]).
    pub report: &'a RollReport,
    /// The rows of [`integrator_study`], when it was run.
    pub study: Option<&'a [StudyRow]>,
}

impl fmt::Display for RollSummary<'_> {
    /// The path, steps and integrator with the final ψ (rad) and axis s, the angle to
    /// the closed-form holonomy (rad) and the wall time (s); then, with a study, one line
    /// per row: path, integrator, steps, error (rad), wall time (s). Lines are separated
    /// by `\n`, with none after the last.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let rep = self.report;
        writeln!(
            f,
            "{}, {} steps, {}: ψ = {:.9} rad, s = [{:.6}, {:.6}, {:.6}]",
            self.label,
            rep.steps,
            rep.integrator.as_str(),
            rep.angle,
            rep.axis[0],
            rep.axis[1],
            rep.axis[2]
        )?;
        write!(
            f,
            "  error vs closed form: {:.2e} rad; wall time {:.2e} s",
            rep.error_vs_closed_form, rep.wall_time_s
        )?;
        if let Some(rows) = self.study {
            write!(
                f,
                "\n  study (path, integrator, steps, error rad, wall time s):"
            )?;
            for r in rows {
                write!(
                    f,
                    "\n    {:<9} {:<5} {:>5} {:>9.2e} {:>9.2e}",
                    r.path.as_str(),
                    r.integrator.as_str(),
                    r.steps,
                    r.error,
                    r.wall_time_s
                )?;
            }
        }
        Ok(())
    }
}

/// The two paths of the integrator study.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum StudyPath {
    /// The rectangle of (2.4.10).
    Rectangle,
    /// A circle of radius 2R, counter-clockwise.
    Circle,
}

impl StudyPath {
    /// `"rectangle"` or `"circle"`, as in roll_study.csv.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Rectangle => "rectangle",
            Self::Circle => "circle",
        }
    }
}

/// One row of the integrator study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StudyRow {
    /// Which path.
    pub path: StudyPath,
    /// Which integrator.
    pub integrator: Integrator,
    /// Steps requested.
    pub steps: usize,
    /// Error of the final orientation vs the closed form, rad.
    pub error: f64,
    /// Median wall time of one run, s.
    pub wall_time_s: f64,
}

impl StudyRow {
    /// The columns of roll_study.csv: the path (`rectangle` or `circle`), the integrator
    /// (`exact` or `rk4`), the steps, the error (rad) and the median wall time (s).
    pub const CSV_HEADER: [&'static str; 5] =
        ["path", "integrator", "steps", "error_rad", "wall_time_s"];

    /// The cells of this row under [`Self::CSV_HEADER`], numbers in shortest round-trip
    /// form.
    #[must_use]
    pub fn csv_cells(&self) -> Vec<String> {
        vec![
            self.path.as_str().to_owned(),
            self.integrator.as_str().to_owned(),
            self.steps.to_string(),
            self.error.to_string(),
            self.wall_time_s.to_string(),
        ]
    }
}

/// The speed-vs-error study of the two integrators: the rectangle of (2.4.10) against
/// (2.4.2), and a circle of radius 2R against [`circle_holonomy`], both integrators,
/// 8, 16, …, 4096 steps. The wall time is the median of repeated runs (build with
/// `--release` for meaningful times); rows are ordered by path, integrator (exact first),
/// then steps.
///
/// # Errors
/// Never for these built-in paths.
pub fn integrator_study() -> Result<Vec<StudyRow>, HolonomyError> {
    let cases = [
        (
            StudyPath::Rectangle,
            ClosedPath::new(&PathShape::Rectangle(rectangle_2_4_10()))?,
        ),
        (
            StudyPath::Circle,
            ClosedPath::new(&PathShape::Circle {
                radius: 2.0,
                direction: Direction::Ccw,
            })?,
        ),
    ];
    let mut out = Vec::new();
    for (path, closed) in &cases {
        for integrator in [Integrator::Exact, Integrator::Rk4] {
            for k in 3..=12 {
                let steps = 1usize << k;
                let mut times = Vec::new();
                let mut error = 0.0;
                // Enough repetitions for a stable median, fewer for the long runs.
                let reps = (50_000 / steps).clamp(3, 100);
                for _ in 0..reps {
                    let (report, _) = roll_report(closed, integrator, steps)?;
                    times.push(report.wall_time_s);
                    error = report.error_vs_closed_form;
                }
                times.sort_by(f64::total_cmp);
                out.push(StudyRow {
                    path: *path,
                    integrator,
                    steps,
                    error,
                    wall_time_s: times[times.len() / 2],
                });
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Unit, Vector3};

    #[test]
    fn rolling_matches_the_closed_forms() {
        let shapes = [
            PathShape::Rectangle(Rectangle::new(1.2, 0.3, 2.0, Direction::Cw).unwrap()),
            PathShape::Circle {
                radius: 2.0,
                direction: Direction::Cw,
            },
            PathShape::Polygon(vec![[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.5]]),
        ];
        for shape in &shapes {
            let closed = ClosedPath::new(shape).unwrap();
            let (rep, traj) = roll_report(&closed, Integrator::Exact, 200).unwrap();
            assert!(rep.error_vs_closed_form < 1e-12, "{}", closed.label);
            assert_eq!(rep.integrator, Integrator::Exact);
            assert_eq!(
                traj.final_orientation().to_rotation_matrix().matrix().len(),
                9
            );
            assert!((rep.path_length - closed.path.length()).abs() < 1e-15);
            assert!(rep.wall_time_s >= 0.0);
        }
        let closed = ClosedPath::new(&shapes[1]).unwrap();
        assert_eq!(closed.label, "circle of radius 2 R");
        let (rk4, _) = roll_report(&closed, Integrator::Rk4, 400).unwrap();
        assert!(rk4.error_vs_closed_form < 1e-8);
    }

    #[test]
    fn text_of_a_roll_with_and_without_a_study() {
        let closed = ClosedPath::new(&PathShape::Circle {
            radius: 2.0,
            direction: Direction::Ccw,
        })
        .unwrap();
        let (rep, _) = roll_report(&closed, Integrator::Rk4, 100).unwrap();
        let text = rep.summary(&closed.label, None).to_string();
        assert!(text.starts_with(&format!(
            "circle of radius 2 R, 100 steps, rk4: ψ = {:.9} rad",
            rep.angle
        )));
        assert!(text.contains(&format!(
            "error vs closed form: {:.2e} rad",
            rep.error_vs_closed_form
        )));
        assert_eq!(text.lines().count(), 2);
        let rows = [StudyRow {
            path: StudyPath::Circle,
            integrator: Integrator::Exact,
            steps: 8,
            error: 2.5e-16,
            wall_time_s: 1.5e-6,
        }];
        let text = rep.summary(&closed.label, Some(&rows)).to_string();
        assert_eq!(
            text.lines().last().unwrap(),
            "    circle    exact     8  2.50e-16   1.50e-6"
        );
        let cells = rows[0].csv_cells();
        assert_eq!(cells.len(), StudyRow::CSV_HEADER.len());
        assert_eq!(
            cells,
            ["circle", "exact", "8", "0.00000000000000025", "0.0000015"]
        );
    }

    #[test]
    fn polygon_labels_count_the_sides_rolled() {
        // A repeated vertex adds no side.
        let shape = PathShape::Polygon(vec![[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [0.0, 1.0]]);
        assert_eq!(ClosedPath::new(&shape).unwrap().label, "polygon of 3 sides");
        assert!(ClosedPath::new(&PathShape::Polygon(vec![[0.0, 0.0]; 3])).is_err());
    }

    #[test]
    fn polygon_holonomy_of_a_segment_and_back() {
        // Rolling 1 along +E1 turns the sphere by 1 about E2, rolling back undoes it.
        let there_and_back = CentrePath::polygon(&[[0.0, 0.0], [1.0, 0.0]]).unwrap();
        let s = polygon_holonomy(&there_and_back, 1.0).unwrap();
        assert!(rotation_distance(&s, &Rotation3::identity()) < 1e-15);
        let triangle = CentrePath::polygon(&[[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]]).unwrap();
        let about = |axis: Vector3<f64>, angle: f64| {
            Rotation3::from_axis_angle(&Unit::new_normalize(axis), angle)
        };
        // Sides along E1, (−E1 + E2)/√2, −E2: axes E3 × d = E2, −(E1 + E2)/√2, E1.
        let expected = about(Vector3::x(), 2.0)
            * about(Vector3::new(-1.0, -1.0, 0.0), 8.0_f64.sqrt())
            * about(Vector3::y(), 2.0);
        let s = polygon_holonomy(&triangle, 1.0).unwrap();
        assert!(rotation_distance(&s, &expected) < 1e-14);
        // Twice the radius: half the angles.
        let half = polygon_holonomy(&triangle, 2.0).unwrap();
        let expected = about(Vector3::x(), 1.0)
            * about(Vector3::new(-1.0, -1.0, 0.0), 2.0_f64.sqrt())
            * about(Vector3::y(), 1.0);
        assert!(rotation_distance(&half, &expected) < 1e-14);
        let circle = CentrePath::circle(1.0, Direction::Ccw).unwrap();
        assert!(polygon_holonomy(&circle, 1.0).is_err());
    }

    #[test]
    fn the_study_covers_both_paths_and_integrators() {
        let rows = integrator_study().unwrap();
        assert_eq!(rows.len(), 2 * 2 * 10);
        assert_eq!(
            (rows[0].path, rows[0].integrator, rows[0].steps),
            (StudyPath::Rectangle, Integrator::Exact, 8)
        );
        // The exact flow is exact at any resolution; RK4 converges.
        for r in &rows {
            match r.integrator {
                Integrator::Exact => assert!(r.error < 1e-12),
                Integrator::Rk4 => assert!(r.error < 1.0),
            }
        }
        let rk4_circle: Vec<_> = rows
            .iter()
            .filter(|r| r.path == StudyPath::Circle && r.integrator == Integrator::Rk4)
            .collect();
        assert!(rk4_circle.last().unwrap().error < rk4_circle[0].error * 1e-6);
        assert_eq!(StudyPath::Circle.as_str(), "circle");
        assert_eq!(Integrator::Rk4.as_str(), "rk4");
    }
}
