//! Overlap of two rectangles (separating-axis test), used to reject scenes whose blocks
//! interpenetrate at the start.

use crate::coordinates::{Pose, Vec2};
use crate::corners::corners;
use crate::interface::Size;

/// Penetration depth of two rectangles: the smallest distance one must move along a
/// face normal of either rectangle to separate them. Zero or negative means they are
/// separate or only touch (the value is then minus the largest separating distance).
#[must_use]
pub fn penetration_depth(a: (&Pose, Size), b: (&Pose, Size)) -> f64 {
    let ca = corners(a.0, a.1.width, a.1.height);
    let cb = corners(b.0, b.1.width, b.1.height);
    let axes = [a.0.e1(), a.0.e2(), b.0.e1(), b.0.e2()];
    let mut depth = f64::INFINITY;
    for axis in &axes {
        let (amin, amax) = extent(&ca, axis);
        let (bmin, bmax) = extent(&cb, axis);
        // Overlap of the two projections along this axis (negative: a gap).
        let overlap = amax.min(bmax) - amin.max(bmin);
        depth = depth.min(overlap);
    }
    depth
}

fn extent(points: &[Vec2; 4], axis: &Vec2) -> (f64, f64) {
    points
        .iter()
        .map(|p| p.dot(axis))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), s| {
            (lo.min(s), hi.max(s))
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stacked_blocks_touch_without_overlap() {
        let s = Size::new(1.0, 0.2);
        let d = penetration_depth(
            (&Pose::new(0.0, 0.0, 0.0), s),
            (&Pose::new(0.4, 0.2, 0.0), s),
        );
        assert!(d.abs() < 1e-15);
        let d = penetration_depth(
            (&Pose::new(0.0, 0.0, 0.0), s),
            (&Pose::new(0.4, 0.15, 0.0), s),
        );
        assert!((d - 0.05).abs() < 1e-12);
        let d = penetration_depth(
            (&Pose::new(0.0, 0.0, 0.0), s),
            (&Pose::new(0.0, 1.0, 0.0), s),
        );
        assert!((d + 0.8).abs() < 1e-12);
    }

    #[test]
    fn rotated_overlap_is_found() {
        let s = Size::new(1.0, 0.2);
        // A block turned by 45° with a corner pushed into the block below.
        let d = penetration_depth(
            (&Pose::new(0.0, 0.0, 0.0), s),
            (&Pose::new(0.0, 0.4, 0.785), s),
        );
        assert!(d > 0.0);
    }
}
