//! The Euler three-rectangle planner of §2.5: any rotation T = T̄(ν1, ν2, ν3) from three
//! rectangles, for the 3-2-3, 3-1-3, 3-2-1 and 3-1-2 sets (Figures 2.7–2.9).
//!
//! All three rectangles start and end at the same point S (the origin). With e′1, e′2 the
//! basis after the first rotation (2.5.1), the constructions are, following ERRATA
//! item 6 for the directions (rectangle 1 clockwise, rectangle 2 counter-clockwise for
//! ν2 > 0 and clockwise for ν2 < 0, rectangle 3 clockwise):
//!
//! 1. Ŝ(ν1/2, π/2, π, E1, E2, cw) = R(ν1, E3), (2.5.7);
//! 2. Ŝ(π, |ν2|/4, |ν2|/2, A1, A2, ·) = R(ν2, A2), (2.5.8)/(2.5.13), with
//!    (A1, A2) = (e′1, e′2) for 3-2-x and (−e′2, e′1) for 3-1-x;
//! 3. Ŝ(ν3/2, φ1, 3π, A1, A2, cw) = R(ν3, third Euler axis), with
//!    3-2-3: φ1 = 5π/2 − ν2, A1 = e′1 (2.5.10)–(2.5.11);
//!    3-1-3: φ1 = 5π/2 − ν2, A1 = −e′2 (2.5.15), **φ1 not φ2 (ERRATA item 5)**;
//!    3-2-1: φ1 = π + ν2, A1 = −e′1 (2.5.18); 3-1-2: φ1 = 2π + ν2, A1 = e′2 (2.5.20).
//!
//! ν1 and ν3 are taken modulo 2π into [0, 2π) so that the widths ν/2 are not negative.
//! The construction holds at the singular values of ν2 (ERRATA item 6), where rectangle 2
//! degenerates (ν2 = 0: a segment travelled back and forth).

use crate::placed::PlacedRectangle;
use crate::rectangle::{Direction, Rectangle};
use crate::HolonomyError;
use nalgebra::{Rotation3, Unit};
use rotations::{rotation_distance, EulerKind, EulerSet};
use serde::{Deserialize, Serialize};
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// The result of [`euler_plan`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EulerPlan {
    /// The Euler set, e.g. `3-2-3`.
    pub set: String,
    /// The angles (ν1, ν2, ν3) used (ν1, ν3 in [0, 2π); ν2 in the set's range).
    pub angles: [f64; 3],
    /// The three rectangles in order of travel, on the ground frame {E1, E2, E3}.
    pub rectangles: [PlacedRectangle; 3],
    /// The target T̄(ν1, ν2, ν3) (components on E).
    pub target: Rotation3<f64>,
    /// The composed holonomy S3 S2 S1 of the three forward products (2.4.2).
    pub achieved: Rotation3<f64>,
    /// Angle of targetᵀ achieved, radians.
    pub error: f64,
    /// For each rectangle, the angle between its holonomy and the elementary rotation
    /// R(νᵢ, gᵢ) about the Euler basis vector gᵢ (A.1.4) it is built to produce, radians.
    pub rectangle_errors: [f64; 3],
}

/// Which construction of §2.5 a set uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Construction {
    S323,
    S313,
    S321,
    S312,
}

fn construction(set: EulerSet) -> Result<Construction, HolonomyError> {
    match set.axes() {
        [3, 2, 3] => Ok(Construction::S323),
        [3, 1, 3] => Ok(Construction::S313),
        [3, 2, 1] => Ok(Construction::S321),
        [3, 1, 2] => Ok(Construction::S312),
        _ => Err(HolonomyError::UnsupportedEulerSet(set.to_string())),
    }
}

/// Plans three rectangles whose composed holonomy is `set.rotation(angles)`.
///
/// Angles outside the set's canonical range of ν2 are first replaced by the canonical
/// angles of the same rotation ([`EulerSet::angles`]).
///
/// # Errors
/// Non-finite angles, or a set other than 3-2-3, 3-1-3, 3-2-1, 3-1-2.
pub fn euler_plan(set: EulerSet, angles: [f64; 3]) -> Result<EulerPlan, HolonomyError> {
    let kind = construction(set)?;
    if angles.iter().any(|a| !a.is_finite()) {
        return Err(HolonomyError::Input(input::InputError::NonFinite(
            "Euler angles".into(),
        )));
    }
    let target = set.rotation(angles);
    let (lo, hi) = set.second_angle_range();
    let angles = if (lo..=hi).contains(&angles[1]) {
        angles
    } else {
        set.angles(&target)
    };
    let [nu1, nu2, nu3] = [
        angles[0].rem_euclid(TAU),
        angles[1],
        angles[2].rem_euclid(TAU),
    ];

    let first = PlacedRectangle {
        rectangle: Rectangle {
            theta: 0.5 * nu1,
            phi1: FRAC_PI_2,
            phi2: PI,
            direction: Direction::Cw,
        },
        heading: 0.0,
        start: [0.0, 0.0],
    };
    // Frame of rectangle 2: A1 = e′1 (heading ν1) or A1 = −e′2 (heading ν1 − π/2).
    let heading2 = match kind {
        Construction::S323 | Construction::S321 => nu1,
        Construction::S313 | Construction::S312 => nu1 - FRAC_PI_2,
    };
    let second = PlacedRectangle {
        rectangle: Rectangle {
            theta: PI,
            phi1: 0.25 * nu2.abs(),
            phi2: 0.5 * nu2.abs(),
            direction: if nu2 >= 0.0 {
                Direction::Ccw
            } else {
                Direction::Cw
            },
        },
        heading: heading2,
        start: [0.0, 0.0],
    };
    let (phi1_3, heading3) = match kind {
        Construction::S323 => (2.5 * PI - nu2, nu1),
        Construction::S313 => (2.5 * PI - nu2, nu1 - FRAC_PI_2),
        Construction::S321 => (PI + nu2, nu1 + PI),
        Construction::S312 => (TAU + nu2, nu1 + FRAC_PI_2),
    };
    let third = PlacedRectangle {
        rectangle: Rectangle {
            theta: 0.5 * nu3,
            phi1: phi1_3,
            phi2: 3.0 * PI,
            direction: Direction::Cw,
        },
        heading: heading3,
        start: [0.0, 0.0],
    };
    let achieved = third.holonomy() * second.holonomy() * first.holonomy();
    // T = R(ν3, g3) R(ν2, g2) R(ν1, g1) with the Euler basis g of (A.1.4).
    let g = set.basis([nu1, nu2, nu3]);
    let rects = [first, second, third];
    let rectangle_errors = [0, 1, 2].map(|i| {
        let elementary = Rotation3::from_axis_angle(&Unit::new_normalize(g[i]), [nu1, nu2, nu3][i]);
        rotation_distance(&elementary, &rects[i].holonomy())
    });
    Ok(EulerPlan {
        rectangle_errors,
        set: set.to_string(),
        angles: [nu1, nu2, nu3],
        rectangles: [first, second, third],
        error: rotation_distance(&target, &achieved),
        target,
        achieved,
    })
}

/// Plans three rectangles for a target rotation, via its canonical Euler angles of `set`.
///
/// # Errors
/// A non-finite target or an unsupported set.
pub fn euler_plan_for_rotation(
    set: EulerSet,
    target: &Rotation3<f64>,
) -> Result<EulerPlan, HolonomyError> {
    if !target.matrix().iter().all(|v| v.is_finite()) {
        return Err(HolonomyError::Input(input::InputError::NonFinite(
            "target rotation".into(),
        )));
    }
    construction(set)?;
    let mut plan = euler_plan(set, set.angles(target))?;
    plan.error = rotation_distance(target, &plan.achieved);
    plan.target = *target;
    Ok(plan)
}

/// Whether ν2 is at a singular value of the set (3-x-3: 0 or π; 3-x-y: ±π/2), within `tol`.
#[must_use]
pub fn is_singular(set: EulerSet, nu2: f64, tol: f64) -> bool {
    match set.kind() {
        EulerKind::Symmetric => nu2.sin().abs() <= tol,
        EulerKind::Asymmetric => nu2.cos().abs() <= tol,
    }
}
