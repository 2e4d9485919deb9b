//! The four corners a, b, c, d of a block, (G.1.1), and their velocities, (G.3.2).

use crate::coordinates::{BodyState, Frame, Pose, Scalar, Vec2};

/// A corner of a block, labelled as in (G.1.1) and Figure 4.1(b).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Corner {
    /// a: top right, r + (w/2) e₁ + (h/2) e₂.
    A,
    /// b: top left, r − (w/2) e₁ + (h/2) e₂.
    B,
    /// c: bottom left, r − (w/2) e₁ − (h/2) e₂.
    C,
    /// d: bottom right, r + (w/2) e₁ − (h/2) e₂.
    D,
}

impl Corner {
    /// All four corners in the order a, b, c, d.
    pub const ALL: [Corner; 4] = [Corner::A, Corner::B, Corner::C, Corner::D];

    /// Components (±w/2, ±h/2) of the corner on the block's basis {e₁, e₂}, (G.1.1).
    #[must_use]
    pub fn body_offset(self, width: f64, height: f64) -> Vec2 {
        let (hw, hh) = (0.5 * width, 0.5 * height);
        match self {
            Self::A => Vec2::new(hw, hh),
            Self::B => Vec2::new(-hw, hh),
            Self::C => Vec2::new(-hw, -hh),
            Self::D => Vec2::new(hw, -hh),
        }
    }

    /// The corner's position r_□ of a block of the given size at `pose`, (G.1.1).
    #[must_use]
    pub fn position<T: Scalar>(self, pose: &Pose<T>, width: f64, height: f64) -> Vec2<T> {
        pose.point(&self.body_offset(width, height))
    }

    /// The corner's velocity v_□ = v + ω × (r_□ − r), (G.3.2).
    #[must_use]
    pub fn velocity<T: Scalar>(self, state: &BodyState<T>, width: f64, height: f64) -> Vec2<T> {
        let offset = state.pose.to_world(&self.body_offset(width, height));
        state.twist.point_velocity(&offset)
    }

    /// Lower-case letter of the corner, as in the thesis.
    #[must_use]
    pub fn letter(self) -> char {
        match self {
            Self::A => 'a',
            Self::B => 'b',
            Self::C => 'c',
            Self::D => 'd',
        }
    }
}

/// The four corner positions [a, b, c, d] of a block at `pose`, (G.1.1).
#[must_use]
pub fn corners<T: Scalar>(pose: &Pose<T>, width: f64, height: f64) -> [Vec2<T>; 4] {
    Corner::ALL.map(|c| c.position(pose, width, height))
}

/// [`corners`] of a block whose frame is evaluated already (real parts; the same bits).
#[must_use]
pub fn frame_corners(frame: &Frame, width: f64, height: f64) -> [Vec2; 4] {
    Corner::ALL.map(|c| frame.point(&c.body_offset(width, height)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn corners_of_an_unrotated_block() {
        let p = Pose::new(1.0, 2.0, 0.0);
        let [a, b, c, d] = corners(&p, 2.0, 1.0);
        assert_eq!((a.x, a.y), (2.0, 2.5));
        assert_eq!((b.x, b.y), (0.0, 2.5));
        assert_eq!((c.x, c.y), (0.0, 1.5));
        assert_eq!((d.x, d.y), (2.0, 1.5));
    }

    #[test]
    fn a_quarter_turn_moves_a_to_the_top_left() {
        let p = Pose::new(0.0, 0.0, std::f64::consts::FRAC_PI_2);
        let a = Corner::A.position(&p, 2.0, 1.0);
        assert!((a - Vec2::new(-0.5, 1.0)).norm() < 1e-15);
    }

    /// The corners from a frame are the pose's corners to the bit.
    #[test]
    fn frame_corners_are_the_poses_corners() {
        for theta in [0.0, 0.3, -2.1, std::f64::consts::FRAC_PI_2] {
            let p = Pose::new(0.4, -1.2, theta);
            assert_eq!(
                frame_corners(&Frame::of(&p), 0.2, 0.4),
                corners(&p, 0.2, 0.4)
            );
        }
    }
}
