//! The holonomy of one rectangle in every form: what `rollstack sphere holonomy` prints.

use crate::rectangle::{
    holonomy_components, no_holonomy_family, rectangle_holonomy, rectangle_holonomy_closed_form,
    NoHolonomy, Rectangle,
};
use nalgebra::Vector3;
use rotations::report::matrix_rows;
use rotations::{quaternion_from_matrix, rotation_distance, AxisAngle};
use serde::{Deserialize, Serialize};

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
    }
}
