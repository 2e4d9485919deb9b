//! The optional floor (beyond the thesis): a fixed horizontal plane y = y_f below the
//! base, touched by any corner of any block, so that a block that topples or loses its
//! support lands instead of falling forever (ERRATA 23).
//!
//! Each block gets four normal gaps, one per corner (G.1.1), g = y_□ − y_f, and one
//! friction law bounded by the sum of the four normal forces (the App. H construction
//! with four gaps instead of two). Its slip speed is the one of the lowest corner,
//! measured like (G.3.1) as the floor's velocity relative to the block's corner along
//! E₁, γ = −ẋ_□. One law per block, not one per corner: when a block lies flat, its two
//! bottom corners have the same horizontal velocity, and two friction rows would be
//! linearly dependent. At a tie of the two lowest corners, the face between them is
//! horizontal, so their slip speeds agree and the choice is continuous.

use crate::coordinates::{re, BodyState, Pose, Rotation, Scalar, Twist};
use crate::corners::Corner;
use crate::gaps::{CornerOnFace, Face, PairRotations, PairRow};
use crate::interface::Size;
use crate::slip::LowerBody;
use crate::turned::TurnedBody;

/// The floor plane y = y_f.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Floor {
    /// Height y_f of the plane.
    pub y: f64,
}

/// The contacts of one block with the floor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FloorContacts<T = f64> {
    /// Gaps of the corners a, b, c, d; `w_first` is on the block (`w_second` is zero).
    pub gaps: [PairRow<T>; 4],
    /// Which corner is lowest (its slip is the law's slip speed).
    pub lowest: Corner,
    /// Slip speed −ẋ of the lowest corner; `w_first` is on the block.
    pub slip: PairRow<T>,
}

impl Floor {
    /// The floor at height y.
    #[must_use]
    pub fn new(y: f64) -> Self {
        Self { y }
    }

    fn state<T: Scalar>(&self) -> BodyState<T> {
        BodyState::lift(&BodyState::new(
            Pose::new(0.0, self.y, 0.0),
            Twist::default(),
        ))
    }

    fn pair<T: Scalar>(&self, corner: Corner, block: &BodyState<T>, size: Size) -> CornerOnFace<T> {
        CornerOnFace {
            corner_body: *block,
            corner: corner.body_offset(size.width, size.height),
            face_body: self.state(),
            face: Face::floor(),
        }
    }

    /// The four corner gaps and the slip of the lowest corner of a block.
    #[must_use]
    pub fn contacts<T: Scalar>(&self, block: &BodyState<T>, size: Size) -> FloorContacts<T> {
        self.contacts_turned(&TurnedBody::of(*block), size)
    }

    /// [`Floor::contacts`] of a block whose rotation is evaluated already.
    #[must_use]
    pub fn contacts_turned<T: Scalar>(
        &self,
        turned: &TurnedBody<T>,
        size: Size,
    ) -> FloorContacts<T> {
        let gaps = Corner::ALL.map(|c| self.gap(c, turned, size));
        let lowest = lowest(gaps.each_ref().map(|g| re(g.value)));
        FloorContacts {
            gaps,
            lowest,
            slip: self.slip(lowest, turned, size),
        }
    }

    /// The rows of [`Floor::contacts_turned`] that are asked for: the gaps of the corners
    /// a, b, c, d whose entry in `corners` is true, and the slip if `slip` is (of the
    /// lowest corner, chosen from the four gaps at the block's real parts: the same
    /// numbers, without derivative directions). For a derivative pass that needs only
    /// some of them (the closed corners of a block lying on the floor).
    #[must_use]
    pub fn rows_turned<T: Scalar>(
        &self,
        turned: &TurnedBody<T>,
        size: Size,
        corners: [bool; 4],
        slip: bool,
    ) -> ([Option<PairRow<T>>; 4], Option<PairRow<T>>) {
        let gaps =
            std::array::from_fn(|j| corners[j].then(|| self.gap(Corner::ALL[j], turned, size)));
        let slip = slip.then(|| {
            let real = turned.re();
            let heights = Corner::ALL.map(|c| self.gap(c, &real, size).value);
            self.slip(lowest(heights), turned, size)
        });
        (gaps, slip)
    }

    /// The gap of a corner of the block (the block's rotation and the floor's, θ = 0:
    /// none).
    fn gap<T: Scalar>(&self, corner: Corner, turned: &TurnedBody<T>, size: Size) -> PairRow<T> {
        let pair = self.pair(corner, &turned.state, size);
        pair.gap_turned(&on_floor(turned))
    }

    /// The slip speed −ẋ of a corner of the block.
    fn slip<T: Scalar>(&self, corner: Corner, turned: &TurnedBody<T>, size: Size) -> PairRow<T> {
        let pair = self.pair(corner, &turned.state, size);
        pair.slip_turned(LowerBody::Face, &on_floor(turned))
    }
}

/// The rotations of a block's corner on the floor: the block's, and the floor's (none).
fn on_floor<T: Scalar>(turned: &TurnedBody<T>) -> PairRotations<T> {
    PairRotations {
        corner: turned.rotation,
        face: Rotation::default(),
    }
}

/// The lowest corner (the first of a, b, c, d at a tie) from the corners' gaps.
fn lowest(gaps: [f64; 4]) -> Corner {
    let mut lowest = 0;
    for i in 1..4 {
        if gaps[i] < gaps[lowest] {
            lowest = i;
        }
    }
    Corner::ALL[lowest]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gaps::tests::{fd_oracle, state};

    #[test]
    fn floor_gaps_are_corner_heights() {
        let f = Floor::new(-0.1);
        let s = state(0.0, 1.0, 0.3, 0.0, 0.0, 0.0);
        let size = Size::new(1.0, 0.4);
        let c = f.contacts(&s, size);
        for (i, corner) in Corner::ALL.iter().enumerate() {
            let p = corner.position(&s.pose, 1.0, 0.4);
            assert!((c.gaps[i].value - (p.y + 0.1)).abs() < 1e-15);
        }
        // Turned counter-clockwise, the bottom-left corner c is lowest.
        assert_eq!(c.lowest, Corner::C);
        // Turned past π/2 the lowest corner changes (no flip of any test, ERRATA 23).
        let c = f.contacts(&state(0.0, 1.0, 2.0, 0.0, 0.0, 0.0), size);
        assert_eq!(c.lowest, Corner::B);
    }

    /// A block's state in the derivative pass's dual numbers, seeded on its own
    /// directions.
    fn seeded(s: &BodyState) -> BodyState<crate::system::Directions> {
        let d = |x: f64, k: usize| crate::system::Directions::from_re(x).derivative(k);
        let (p, v) = (s.pose, s.twist);
        BodyState::new(
            Pose::new(d(p.x, 0), d(p.y, 1), d(p.theta, 2)),
            Twist::new(d(v.vx, 6), d(v.vy, 7), d(v.omega, 8)),
        )
    }

    /// The rows asked for are those of all the contacts, to the bit, the slip's lowest
    /// corner chosen from the real parts as from the dual numbers' (a tie included).
    #[test]
    fn rows_asked_for_equal_those_of_all_the_contacts() {
        let f = Floor::new(-0.05);
        let size = Size::new(0.2, 0.4);
        let flat = std::f64::consts::FRAC_PI_2;
        for s in [
            state(0.1, 0.5, 2.2, 0.3, -0.7, 1.9),
            state(-0.3, 0.2, -0.4, 0.0, 0.1, -0.6),
            state(0.0, 0.05, flat, 0.4, 0.0, 0.3),
        ] {
            let turned = TurnedBody::of(seeded(&s));
            let all = f.contacts_turned(&turned, size);
            let (gaps, slip) = f.rows_turned(&turned, size, [true, false, false, true], true);
            let same = |a: &PairRow<_>, b: &PairRow<_>| format!("{a:?}") == format!("{b:?}");
            assert!(same(gaps[0].as_ref().unwrap(), &all.gaps[0]));
            assert!(same(gaps[3].as_ref().unwrap(), &all.gaps[3]));
            assert!(gaps[1].is_none() && gaps[2].is_none());
            assert!(same(slip.as_ref().unwrap(), &all.slip));
            let (gaps, slip) = f.rows_turned(&turned, size, [false; 4], false);
            assert!(gaps.iter().all(Option::is_none) && slip.is_none());
        }
    }

    /// The rows from the block's rotation evaluated once (and the floor's none) are
    /// those of each corner's pair turning both bodies itself, to the bit, in plain and
    /// in the derivative pass's dual numbers.
    #[test]
    fn turned_floor_rows_equal_each_pairs_own_to_the_bit() {
        let f = Floor::new(-0.05);
        let size = Size::new(0.2, 0.4);
        for s in [
            state(0.1, 0.5, 2.2, 0.3, -0.7, 1.9),
            state(-0.3, 0.2, -0.4, 0.0, 0.1, -0.6),
        ] {
            let c = f.contacts(&s, size);
            for (i, corner) in Corner::ALL.into_iter().enumerate() {
                assert_eq!(c.gaps[i], f.pair(corner, &s, size).gap());
            }
            assert_eq!(c.slip, f.pair(c.lowest, &s, size).slip(LowerBody::Face));
            let seeded = seeded(&s);
            let c = f.contacts(&seeded, size);
            for (i, corner) in Corner::ALL.into_iter().enumerate() {
                let own = f.pair(corner, &seeded, size).gap();
                assert_eq!(format!("{:?}", c.gaps[i]), format!("{own:?}"));
            }
        }
    }

    #[test]
    fn floor_rows_match_finite_differences() {
        let f = Floor::new(0.0);
        let size = Size::new(0.2, 0.4);
        let s = state(0.1, 0.5, 2.2, 0.3, -0.7, 1.9);
        let floor: BodyState = f.state();
        let c = f.contacts(&s, size);
        for i in 0..4 {
            let (w, _, second) = fd_oracle(&|b, _| f.contacts(b, size).gaps[i].value, &s, &floor);
            for k in 0..3 {
                assert!((c.gaps[i].w_first[k] - w[k]).abs() < 1e-8);
            }
            assert!((c.gaps[i].zeta - second).abs() < 1e-5);
        }
        // Slip: −ẋ of the lowest corner.
        let p = c.lowest.velocity(&s, 0.2, 0.4);
        assert!((c.slip.value + p.x).abs() < 1e-15);
    }

    #[test]
    fn slip_choice_is_continuous_when_lying_flat() {
        let f = Floor::new(0.0);
        let size = Size::new(0.2, 0.4);
        // Lying on its side (θ = π/2) and sliding with some spin: the two lowest corners
        // tie and have equal horizontal velocities.
        let s = state(0.0, 0.1, std::f64::consts::FRAC_PI_2, 0.4, 0.0, 0.3);
        let plus = f.contacts(
            &state(0.0, 0.1, std::f64::consts::FRAC_PI_2 + 1e-12, 0.4, 0.0, 0.3),
            size,
        );
        let minus = f.contacts(
            &state(0.0, 0.1, std::f64::consts::FRAC_PI_2 - 1e-12, 0.4, 0.0, 0.3),
            size,
        );
        assert_ne!(plus.lowest, minus.lowest);
        assert!((plus.slip.value - minus.slip.value).abs() < 1e-10);
        assert!(
            f.contacts(&s, size)
                .gaps
                .iter()
                .filter(|g| g.value.abs() < 1e-12)
                .count()
                == 2
        );
    }
}
