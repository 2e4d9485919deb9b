//! One rotation in every representation at once: the report `rollstack rotation --json`
//! prints, and the Euler round trip the tour tabulates.

use crate::axis_angle::AxisAngle;
use crate::euler::EulerSet;
use crate::quaternion::quaternion_from_matrix;
use crate::rotation_distance;
use nalgebra::Rotation3;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fmt;

/// The tolerance on the second Euler angle below which a set is reported singular
/// ([`EulerSet::is_singular`]).
pub const SINGULAR_TOLERANCE: f64 = 1e-12;

/// Every representation of one rotation R. The field names are the keys of the JSON of
/// `rollstack rotation` (docs/cli.md).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RotationReport {
    /// Rows of R: entry `[i][j]` = Eᵢ · R Eⱼ.
    pub matrix: [[f64; 3]; 3],
    /// Canonical unit quaternion [q0, q1, q2, q3], q0 ≥ 0, (2.2.1)₂–(2.2.2).
    pub quaternion: [f64; 4],
    /// Canonical unit axis (E3 for the identity), (2.2.1)₁.
    pub axis: [f64; 3],
    /// Canonical angle in [0, π], radians.
    pub angle: f64,
    /// The angles of all twelve Euler sets (A.1.2), keyed by set name (`3-1-3`, ...).
    pub euler: BTreeMap<String, [f64; 3]>,
    /// Sets for which the rotation is at a singular value of the second angle (the first
    /// angle was set to 0 there, App. A).
    pub euler_singular: Vec<String>,
}

impl fmt::Display for RotationReport {
    /// The readable summary `rollstack rotation` prints: the rows of R (9 decimals), the
    /// quaternion [q0, q1, q2, q3] (2.2.1)₂–(2.2.2), the angle in radians and degrees
    /// with the unit axis (2.2.1)₁, and the angles (rad) of all twelve Euler sets
    /// (A.1.2), those at a singular second angle marked. Lines are separated by `\n`,
    /// with none after the last.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "matrix (row i: Eᵢ · R Eⱼ):")?;
        for row in self.matrix {
            writeln!(f, "  [{:>12.9} {:>12.9} {:>12.9}]", row[0], row[1], row[2])?;
        }
        let [q0, q1, q2, q3] = self.quaternion;
        writeln!(
            f,
            "quaternion [q0, q1, q2, q3] = [{q0:.9}, {q1:.9}, {q2:.9}, {q3:.9}]"
        )?;
        writeln!(
            f,
            "angle = {:.9} rad ({:.6}°), axis = [{:.9}, {:.9}, {:.9}]",
            self.angle,
            self.angle.to_degrees(),
            self.axis[0],
            self.axis[1],
            self.axis[2]
        )?;
        write!(f, "Euler angles (rad):")?;
        for (set, a) in &self.euler {
            let flag = if self.euler_singular.contains(set) {
                "  (singular: a1 set to 0)"
            } else {
                ""
            };
            write!(
                f,
                "\n  {set}: [{:>12.9}, {:>12.9}, {:>12.9}]{flag}",
                a[0], a[1], a[2]
            )?;
        }
        Ok(())
    }
}

/// The rows of a rotation's matrix, entry `[i][j]` = Eᵢ · R Eⱼ, as the reports print them.
#[must_use]
pub fn matrix_rows(rotation: &Rotation3<f64>) -> [[f64; 3]; 3] {
    let m = rotation.matrix();
    [0, 1, 2].map(|i| [m[(i, 0)], m[(i, 1)], m[(i, 2)]])
}

/// Every representation of `rotation`: its matrix, its canonical quaternion (Shepperd's
/// method, q0 ≥ 0) and axis–angle pair (2.2.1)–(2.2.4), and its angles in all twelve
/// Euler sets (A.1.2), with the sets at a singular second angle flagged (App. A).
#[must_use]
pub fn rotation_report(rotation: &Rotation3<f64>) -> RotationReport {
    let aa = AxisAngle::from_rotation(rotation);
    let q = quaternion_from_matrix(rotation.matrix());
    let mut euler = BTreeMap::new();
    let mut euler_singular = Vec::new();
    for set in EulerSet::ALL {
        let angles = set.angles(rotation);
        if set.is_singular(angles, SINGULAR_TOLERANCE) {
            euler_singular.push(set.to_string());
        }
        euler.insert(set.to_string(), angles);
    }
    RotationReport {
        matrix: matrix_rows(rotation),
        quaternion: [q.scalar(), q.vector()[0], q.vector()[1], q.vector()[2]],
        axis: [aa.axis.x, aa.axis.y, aa.axis.z],
        angle: aa.angle,
        euler,
        euler_singular,
    }
}

/// The angles of one Euler set for a rotation, and how well they reproduce it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct EulerRoundTrip {
    /// The set.
    pub set: EulerSet,
    /// Its angles (a1, a2, a3) of the rotation, radians ([`EulerSet::angles`]).
    pub angles: [f64; 3],
    /// The angle of Rᵀ R(a1, a2, a3), radians: the round-trip error.
    pub error: f64,
}

/// The angles of `set` for `rotation` (A.1.2) and the angle between the rotation they
/// rebuild and `rotation`: round-off everywhere, including at the singular values of the
/// second angle where the first is set to 0.
#[must_use]
pub fn euler_round_trip(set: EulerSet, rotation: &Rotation3<f64>) -> EulerRoundTrip {
    let angles = set.angles(rotation);
    EulerRoundTrip {
        set,
        angles,
        error: rotation_distance(&set.rotation(angles), rotation),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    #[test]
    fn report_of_a_rotation_about_e3() {
        let r = AxisAngle::new(0.9, Vector3::z()).unwrap().to_rotation();
        let rep = rotation_report(&r);
        assert!((rep.angle - 0.9).abs() < 1e-15);
        assert_eq!(rep.axis, [0.0, 0.0, 1.0]);
        assert!(rep.quaternion[0] > 0.0);
        assert!((rep.quaternion[3] - (0.45_f64).sin()).abs() < 1e-15);
        assert_eq!(rep.matrix[2], [0.0, 0.0, 1.0]);
        assert_eq!(rep.euler.len(), 12);
        assert_eq!(rep.euler["3-1-3"], [0.0, 0.0, 0.9]);
        // At a2 = 0 of the symmetric sets about E3.
        assert_eq!(rep.euler_singular, ["3-1-3", "3-2-3"]);
    }

    #[test]
    fn matrix_rows_are_rows() {
        let r = AxisAngle::new(0.3, Vector3::x()).unwrap().to_rotation();
        let rows = matrix_rows(&r);
        assert_eq!(rows[1][2], r.matrix()[(1, 2)]);
        assert_eq!(rows[2][1], r.matrix()[(2, 1)]);
    }

    #[test]
    fn round_trips_are_exact_to_round_off() {
        let r = AxisAngle::new(1.1, Vector3::new(-0.4, 0.0, -0.9))
            .unwrap()
            .to_rotation();
        for set in EulerSet::ALL {
            let t = euler_round_trip(set, &r);
            assert_eq!(t.set, set);
            assert!(t.error < 1e-14, "{set}: {}", t.error);
        }
    }

    #[test]
    fn the_text_shows_every_representation() {
        let r = AxisAngle::new(0.9, Vector3::z()).unwrap().to_rotation();
        let text = rotation_report(&r).to_string();
        let lines: Vec<&str> = text.lines().collect();
        // A header and three rows, quaternion, angle, a header and twelve sets.
        assert_eq!(lines.len(), 1 + 3 + 1 + 1 + 1 + 12);
        assert_eq!(lines[3], "  [ 0.000000000  0.000000000  1.000000000]");
        assert!(
            lines[4].ends_with("0.000000000, 0.434965534]"),
            "{}",
            lines[4]
        );
        assert!(lines[5].starts_with("angle = 0.900000000 rad (51.566202°)"));
        assert_eq!(
            lines[16],
            "  3-1-3: [ 0.000000000,  0.000000000,  0.900000000]  (singular: a1 set to 0)"
        );
        assert!(!text.ends_with('\n'));
    }

    #[test]
    fn json_keys_are_those_of_the_cli() {
        let r = AxisAngle::new(0.4, Vector3::new(1.0, 2.0, 3.0))
            .unwrap()
            .to_rotation();
        let rep = rotation_report(&r);
        let text = serde_json::to_string(&rep).unwrap();
        assert!(text.starts_with("{\"matrix\":[["));
        for key in ["quaternion", "axis", "angle", "euler", "euler_singular"] {
            assert!(text.contains(&format!("\"{key}\":")), "{key}");
        }
        assert!(text.contains("\"euler\":{\"1-2-1\":["));
        assert!(text.ends_with("\"euler_singular\":[]}"));
        // Reads back (to the last bit only with serde_json's float_roundtrip feature).
        let back: RotationReport = serde_json::from_str(&text).unwrap();
        assert_eq!(
            back.euler.keys().collect::<Vec<_>>(),
            rep.euler.keys().collect::<Vec<_>>()
        );
        assert!((back.angle - rep.angle).abs() < 1e-15);
    }
}
