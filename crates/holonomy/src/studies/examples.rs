//! The worked examples of Ch. 2, with the values the thesis prints, so that a test, the
//! tour or a reader can set the computed numbers beside the printed ones.

use crate::rectangle::{Direction, Rectangle};
use crate::HolonomyError;
use nalgebra::{Rotation3, Vector3};
use rotations::rotation_from_axis_angle;
use std::f64::consts::{FRAC_PI_2, PI};

/// The rectangle of Figure 2.1 and (2.4.10): Ŝ(4π/3 − 0.5, π/2 − 0.4, 3π, ccw).
#[must_use]
pub fn rectangle_2_4_10() -> Rectangle {
    // Valid by construction (0 ≤ φ1 ≤ φ2), so the checked constructor is not needed.
    Rectangle {
        theta: 4.0 * PI / 3.0 - 0.5,
        phi1: FRAC_PI_2 - 0.4,
        phi2: 3.0 * PI,
        direction: Direction::Ccw,
    }
}

/// The angle ψ of the holonomy printed in (2.4.10), degrees.
pub const PRINTED_ANGLE_2_4_10_DEG: f64 = 62.7042;

/// The axis s of the holonomy printed in (2.4.10), components on A1, A2, A3.
pub const PRINTED_AXIS_2_4_10: [f64; 3] = [-0.389_418, 0.0, -0.921_061];

/// The holonomy as printed in (2.4.10), R(62.7042°, −0.389418 A1 − 0.921061 A3), built
/// from the printed digits (not computed from the rectangle).
///
/// # Errors
/// Never: the printed axis is not zero.
pub fn printed_holonomy_2_4_10() -> Result<Rotation3<f64>, HolonomyError> {
    let [x, y, z] = PRINTED_AXIS_2_4_10;
    Ok(rotation_from_axis_angle(
        PRINTED_ANGLE_2_4_10_DEG.to_radians(),
        &Vector3::new(x, y, z),
    )?)
}

/// The target of (2.4.12) and Figure 2.6: R(3π/2, 0.1 A1 + √0.98 A2 + 0.1 A3).
///
/// # Errors
/// Never: the axis is not zero.
pub fn target_2_4_12() -> Result<Rotation3<f64>, HolonomyError> {
    Ok(rotation_from_axis_angle(
        1.5 * PI,
        &Vector3::new(0.1, 0.98_f64.sqrt(), 0.1),
    )?)
}

/// The three counter-clockwise rectangles (ϑ, φ1, φ2) printed in (2.4.12)₁,₂,₃ for
/// [`target_2_4_12`], to the printed digits (ERRATA items 2, 7).
pub const PRINTED_RECTANGLES_2_4_12: [[f64; 3]; 3] = [
    [3.0333, 3.5379, 8.6465],
    [3.2499, 0.39626, 2.3633],
    [3.2499, 6.6794, 8.6465],
];

/// How close to the printed digits of (2.4.12) a computed rectangle must be.
pub const PRINTED_TOLERANCE_2_4_12: f64 = 1e-4;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::planner::plan_rectangles;
    use crate::rectangle::rectangle_holonomy;
    use rotations::rotation_distance;

    #[test]
    fn the_printed_holonomy_is_that_of_the_rectangle() {
        let s = rectangle_holonomy(&rectangle_2_4_10());
        let printed = printed_holonomy_2_4_10().unwrap();
        // Six printed digits of the axis: about 1e-6 rad.
        assert!(rotation_distance(&s, &printed) < 2e-6);
        let valid = Rectangle::new(
            rectangle_2_4_10().theta,
            rectangle_2_4_10().phi1,
            rectangle_2_4_10().phi2,
            Direction::Ccw,
        );
        assert_eq!(valid, Ok(rectangle_2_4_10()));
    }

    #[test]
    fn the_planner_finds_the_printed_rectangles() {
        let plans = plan_rectangles(&target_2_4_12().unwrap()).unwrap();
        for [t, p1, p2] in PRINTED_RECTANGLES_2_4_12 {
            assert!(plans.iter().any(|p| {
                let r = p.rectangle;
                r.direction == Direction::Ccw
                    && (r.theta - t).abs() < PRINTED_TOLERANCE_2_4_12
                    && (r.phi1 - p1).abs() < PRINTED_TOLERANCE_2_4_12
                    && (r.phi2 - p2).abs() < PRINTED_TOLERANCE_2_4_12
            }));
        }
    }
}
