//! Contacts between any two bodies that can touch (beyond the thesis's model).
//!
//! The thesis's stack has contacts only between neighbours (App. G) and, here, with the
//! floor. Once a block leaves its neighbour it would meet nothing else: fallen blocks
//! would pass through each other and through the base. This module adds the contact of
//! **any corner of any body against any other body**: base and blocks are rectangles, and
//! two rectangles that touch without overlapping touch at a corner of one of them (two
//! parallel faces in contact are two corners on a face), so corner-on-body contacts are
//! all the contacts there are.
//!
//! A [`CornerContact`] is corner P of body A against face f of body B. Its gap is the
//! signed distance of P from the line of f, g = (r_P − r_B) · n_f − d_f, with the value,
//! W, χ and ζ of the corner-on-face gap of (G.2.1)/(G.2.3) (crate::gaps) and the slip of
//! (G.3.1) (crate::slip): the neighbour interface of App. G is the special case P a
//! bottom corner of block k+1 and f the top face of block k.
//!
//! The face is the one P meets, chosen at the start of each step ([`Side::facing`]): of
//! the four faces, the one P is farthest outside of (the separating face: P outside B
//! exactly when that distance is positive; P inside, the least deep way out). It stays
//! fixed within the step, so the gap is smooth for Newton; the next step chooses again.
//! Fixing it matters: a corner that slides level with B's top into B's side (two equal
//! blocks pushed together) is at distance zero from the top face all the way, and only
//! the side face, chosen before it entered, can stop it.
//!
//! Which corner contacts a step needs is the broad phase's business
//! ([`crate::broad_phase`]); how they enter the stepper, the system's
//! ([`crate::StackSystem`]).

use crate::coordinates::{re, Frame, Scalar, Twist};
use crate::corners::Corner;
use crate::gaps::{CornerOnFace, Face, PairRotations, PairRow};
use crate::interface::Size;
use crate::overlap::Body;
use crate::slip::LowerBody;
use crate::stack::{pair_row, ContactRow};
use crate::turned::TurnedBody;

/// Corner `corner` of body `corner_body` against face `face` of body `face_body` (base or
/// block; the floor has its own contacts).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CornerContact {
    /// The body that owns the corner.
    pub corner_body: Body,
    /// The corner.
    pub corner: Corner,
    /// The body whose face the corner may touch.
    pub face_body: Body,
    /// The face, chosen by the broad phase at the start of the step ([`Side::facing`]).
    pub face: Side,
}

/// One of the four faces of a rectangular body.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Side {
    /// The face along +e₂.
    Top,
    /// The face along −e₂.
    Bottom,
    /// The face along +e₁.
    Right,
    /// The face along −e₁.
    Left,
}

impl Side {
    /// The four sides, in the order of [`Face::of_rectangle`].
    pub const ALL: [Side; 4] = [Side::Top, Side::Bottom, Side::Right, Side::Left];

    /// This face of a body of the given size.
    #[must_use]
    pub fn face(self, size: Size) -> Face {
        let i = self.index();
        Face::of_rectangle(size.width, size.height)[i]
    }

    /// The face of body B (at `face`, of size `face_size`) that a corner at the world
    /// point `p` of a body centred at `centre` meets: among the faces whose signed
    /// distance from `p` is largest (within `tie` of the largest: P outside B is beyond
    /// them, P inside B is least deep behind them), the one facing the corner's body
    /// most squarely (largest n_f · (r_A − r_B)). The tie matters: a corner level with a
    /// face's line (two equal blocks side by side, or a corner on a corner) is at
    /// distance zero from two faces, and only the second face is the one it can strike.
    /// Returns the side and its signed distance.
    #[must_use]
    pub fn facing(
        p: &crate::coordinates::Vec2,
        centre: &crate::coordinates::Vec2,
        face: &Frame,
        face_size: Size,
        tie: f64,
    ) -> (Side, f64) {
        let faces = Face::of_rectangle(face_size.width, face_size.height);
        let d = faces.map(|f| f.distance(face, p));
        let best = d.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let towards = |f: &Face| face.to_world(&f.normal).dot(&(*centre - face.r));
        let mut chosen = 0;
        for i in 1..4 {
            let better = d[i] >= best - tie
                && (d[chosen] < best - tie || towards(&faces[i]) > towards(&faces[chosen]));
            if better {
                chosen = i;
            }
        }
        (Self::ALL[chosen], d[chosen])
    }

    /// The position of this side in [`Side::ALL`].
    #[must_use]
    pub const fn index(self) -> usize {
        match self {
            Side::Top => 0,
            Side::Bottom => 1,
            Side::Right => 2,
            Side::Left => 3,
        }
    }

    /// The two faces that meet at `corner` (its letters as in (G.1.1): a is top right).
    #[must_use]
    pub fn through(corner: Corner) -> [Side; 2] {
        match corner {
            Corner::A => [Side::Top, Side::Right],
            Corner::B => [Side::Top, Side::Left],
            Corner::C => [Side::Bottom, Side::Left],
            Corner::D => [Side::Bottom, Side::Right],
        }
    }

    /// How far beyond the nearer end of this face of a body (with frame `frame`, of
    /// `size`) the world point `p` lies along the face (negative: within the face's
    /// extent). A corner beyond the end of a face does not touch it: the other body's
    /// corner there does.
    #[must_use]
    pub fn beyond_end(self, frame: &Frame, size: Size, p: &crate::coordinates::Vec2) -> f64 {
        let d = *p - frame.r;
        let (along, half) = match self {
            Side::Top | Side::Bottom => (d.dot(&frame.e1), 0.5 * size.width),
            Side::Right | Side::Left => (d.dot(&frame.e2), 0.5 * size.height),
        };
        along.abs() - half
    }
}

/// The index of a base or block body in the scene's numbering (base 0, blocks 1..n; the
/// floor, which has no corner contacts, after all of them).
pub(crate) fn body_index(b: Body) -> usize {
    match b {
        Body::Base => 0,
        Body::Block(k) => k,
        Body::Floor => usize::MAX,
    }
}

/// The 0-based free block of a body (`None` for the base).
pub(crate) fn free_block(b: Body) -> Option<usize> {
    match b {
        Body::Block(k) => Some(k - 1),
        Body::Base | Body::Floor => None,
    }
}

impl CornerContact {
    /// A total order key (corner body, corner, face body, face) for deterministic listings.
    #[must_use]
    pub fn key(&self) -> (usize, usize, usize, usize) {
        let corner = Corner::ALL
            .iter()
            .position(|&c| c == self.corner)
            .unwrap_or(0);
        let side = self.face.index();
        (
            body_index(self.corner_body),
            corner,
            body_index(self.face_body),
            side,
        )
    }

    /// How far beyond the nearer end of its face the corner lies (negative: within the
    /// face's extent), with the bodies' frames (real parts; corner body first).
    #[must_use]
    pub fn beyond_end(&self, [corner, face]: &[Frame; 2], sizes: [Size; 2]) -> f64 {
        let offset = self.corner.body_offset(sizes[0].width, sizes[0].height);
        self.face.beyond_end(face, sizes[1], &corner.point(&offset))
    }

    /// Whether this is a contact that the interface of its two bodies, with `lower` the
    /// body beneath ([`crate::arrangement`]), measures while it supports (G.2.3): a top
    /// corner (a, b) of the lower body on the bottom face of the upper, or a bottom
    /// corner (c, d) of the upper on the top face of the lower.
    #[must_use]
    pub fn is_interface_case(&self, lower: Body) -> bool {
        let lower_is_corner = self.corner_body == lower;
        matches!(
            (lower_is_corner, self.corner, self.face),
            (true, Corner::A | Corner::B, Side::Bottom) | (false, Corner::C | Corner::D, Side::Top)
        )
    }

    /// The gap and the slip speed of the contact ([`CornerContact::gap_row`],
    /// [`CornerContact::slip_row`]).
    #[must_use]
    pub fn rows<T: Scalar>(
        &self,
        bodies: [&TurnedBody<T>; 2],
        sizes: [Size; 2],
        base_acc: &Twist<T>,
        along: Option<&crate::coordinates::Vec2<T>>,
    ) -> (ContactRow<T>, ContactRow<T>) {
        (
            self.gap_row(bodies, sizes, base_acc),
            self.slip_row(bodies, sizes, base_acc, along),
        )
    }

    /// The gap of the contact, in the coordinates of the free blocks (W on at most two
    /// blocks; the base's prescribed motion in χ and ζ). `bodies` are the corner's and
    /// the face's bodies turned, `sizes` their sizes.
    #[must_use]
    pub fn gap_row<T: Scalar>(
        &self,
        bodies: [&TurnedBody<T>; 2],
        sizes: [Size; 2],
        base_acc: &Twist<T>,
    ) -> ContactRow<T> {
        let (pair, rotations) = self.pair(bodies, sizes);
        self.fold(&pair.gap_turned(&rotations), bodies, base_acc)
    }

    /// The slip speed of the contact, as [`CornerContact::gap_row`]: the velocity of the
    /// body first in the scene's order (base, then blocks bottom to top) relative to the
    /// other, along the face's tangent, or along `along` when given (the tangent of the
    /// contact's line: the two contacts of a line, one on each body's face, then measure
    /// the same slip).
    #[must_use]
    pub fn slip_row<T: Scalar>(
        &self,
        bodies: [&TurnedBody<T>; 2],
        sizes: [Size; 2],
        base_acc: &Twist<T>,
        along: Option<&crate::coordinates::Vec2<T>>,
    ) -> ContactRow<T> {
        let (pair, rotations) = self.pair(bodies, sizes);
        let lower = if body_index(self.corner_body) < body_index(self.face_body) {
            LowerBody::Corner
        } else {
            LowerBody::Face
        };
        let mut slip = pair.slip_turned(lower, &rotations);
        if let Some(t) = along {
            let tangent = rotations.face.apply(&pair.face.tangent);
            if re(tangent.dot(t)) < 0.0 {
                slip = slip.negated();
            }
        }
        self.fold(&slip, bodies, base_acc)
    }

    /// The corner-on-face pairing of the contact's bodies, with their rotations.
    fn pair<T: Scalar>(
        &self,
        [corner, face]: [&TurnedBody<T>; 2],
        sizes: [Size; 2],
    ) -> (CornerOnFace<T>, PairRotations<T>) {
        let pair = CornerOnFace {
            corner_body: corner.state,
            corner: self.corner.body_offset(sizes[0].width, sizes[0].height),
            face_body: face.state,
            face: self.face.face(sizes[1]),
        };
        let rotations = PairRotations {
            corner: corner.rotation,
            face: face.rotation,
        };
        (pair, rotations)
    }

    /// A row of the pair in the coordinates of the free blocks (a base's terms in χ, ζ).
    fn fold<T: Scalar>(
        &self,
        row: &PairRow<T>,
        [corner, face]: [&TurnedBody<T>; 2],
        base_acc: &Twist<T>,
    ) -> ContactRow<T> {
        let blocks = [free_block(self.corner_body), free_block(self.face_body)];
        let base_vel = match (self.corner_body, self.face_body) {
            (Body::Base, _) => corner.state.twist,
            (_, Body::Base) => face.state.twist,
            _ => Twist::new(T::zero(), T::zero(), T::zero()),
        };
        pair_row(row, blocks, &base_vel, base_acc)
    }
}

/// The line on which two bodies touch: one slot of the system, with up to two corner
/// contacts and one friction law bounded by both (as an interface of App. H).
///
/// Two corner contacts of the same pair whose faces lie flush (a block lying on another,
/// two blocks side by side) slip at the same speed while the faces stay flush; with a
/// friction law each, their two friction rows would be equal and Newton's matrix singular
/// in stick. So they share one law, whose slip is that of the contact with the smaller
/// gap, like the interface's (G.3.1), measured along the tangent of the lower body's face
/// so that it does not change sign when the smaller gap passes from one body's corner to
/// the other's.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ContactLine {
    /// The body first in the scene's order (base, then blocks bottom to top).
    pub lo: Body,
    /// The other body.
    pub hi: Body,
    /// Where on the pair the line is.
    pub kind: LineKind,
}

/// Where a [`ContactLine`] lies.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LineKind {
    /// Along this face of the lower body: contacts of the upper body's corners on it,
    /// and of the lower body's corners on an upper face flush with it.
    Face(Side),
    /// A single contact not on a face of the lower body nor flush with one: a corner of
    /// the lower body against a face of the upper at an angle.
    Corner(Corner, Side),
}

impl ContactLine {
    /// A total order key, for deterministic listings.
    #[must_use]
    pub fn key(&self) -> (usize, usize, usize, usize) {
        let side = Side::index;
        let (a, b) = match self.kind {
            LineKind::Face(s) => (0, side(s)),
            LineKind::Corner(c, s) => (
                1 + Corner::ALL.iter().position(|&x| x == c).unwrap_or(0),
                side(s),
            ),
        };
        (body_index(self.lo), body_index(self.hi), a, b)
    }
}

/// Up to two corner contacts on one [`ContactLine`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LineContacts {
    /// The line.
    pub line: ContactLine,
    /// Its contacts (a line has at most two in the plane).
    pub contacts: [Option<CornerContact>; 2],
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coordinates::{BodyState, Vec2};
    use crate::gaps::tests::{fd_oracle, state};

    fn contact(corner: Corner, face: Side) -> CornerContact {
        CornerContact {
            corner_body: Body::Block(3),
            corner,
            face_body: Body::Block(1),
            face,
        }
    }

    const SIZES: [Size; 2] = [
        Size {
            width: 0.2,
            height: 0.4,
        },
        Size {
            width: 0.3,
            height: 0.1,
        },
    ];

    /// The gap and slip rows of contact `c` of A on B, with a base at rest.
    fn rows_of(c: CornerContact, a: &BodyState, b: &BodyState) -> (ContactRow, ContactRow) {
        let zero = Twist::new(0.0, 0.0, 0.0);
        let turned = [a, b].map(|s| TurnedBody::of(*s));
        c.rows([&turned[0], &turned[1]], SIZES, &zero, None)
    }

    /// The gap of corner `c` of A against face `side` of B.
    fn gap_of(c: Corner, side: Side, a: &BodyState, b: &BodyState) -> f64 {
        rows_of(contact(c, side), a, b).0.value
    }

    /// The side that corner `c` of A meets, and its distance.
    fn facing(c: Corner, a: &BodyState, b: &BodyState) -> (Side, f64) {
        let p = a
            .pose
            .point(&c.body_offset(SIZES[0].width, SIZES[0].height));
        Side::facing(&p, &a.pose.r(), &Frame::of(&b.pose), SIZES[1], 1e-9)
    }

    #[test]
    fn the_face_met_is_the_separating_one_and_level_corners_meet_the_side() {
        let b = state(0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        // Corner c (bottom left, offset (−0.1, −0.2)) of A at (0.5, 0.02): right of B
        // (half width 0.15) by 0.35, within its height: the right face.
        let a = state(0.6, 0.22, 0.0, 0.0, 0.0, 0.0);
        assert_eq!(facing(Corner::C, &a, &b), (Side::Right, 0.35));
        assert!((gap_of(Corner::C, Side::Right, &a, &b) - 0.35).abs() < 1e-15);
        // At (0.1, 0.04): inside B, 0.05 from the right face and 0.01 from the top.
        let a = state(0.2, 0.24, 0.0, 0.0, 0.0, 0.0);
        let (side, d) = facing(Corner::C, &a, &b);
        assert!(side == Side::Top && (d + 0.01).abs() < 1e-15);
        // Corner a (top right) exactly on B's top-left corner, A to the left: level with
        // the top face and touching the left one; A can only strike the left face.
        let a = state(-0.25, -0.15, 0.0, 0.0, 0.0, 0.0);
        let (side, d) = facing(Corner::A, &a, &b);
        assert!(side == Side::Left && d.abs() < 1e-15, "{side:?} {d}");
    }

    #[test]
    fn rows_match_finite_differences_on_every_face() {
        let b = state(-0.1, 0.05, 0.4, -0.3, 0.5, -0.8);
        // One corner position beside each face of B.
        let mut seen = Vec::new();
        for (x, y) in [(0.0, 0.3), (0.05, -0.3), (0.4, 0.1), (-0.5, 0.0)] {
            let a = state(x, y, 0.3, 0.7, -0.4, 1.1);
            let (side, _) = facing(Corner::B, &a, &b);
            seen.push(side);
            let (gap, slip) = rows_of(contact(Corner::B, side), &a, &b);
            let (wa, wb, second) = fd_oracle(&|a, b| gap_of(Corner::B, side, a, b), &a, &b);
            let w: Vec<(usize, f64)> = gap.w.iter().collect();
            for i in 0..3 {
                assert!((w[i].1 - wa[i]).abs() < 1e-7, "W_A[{i}] at ({x}, {y})");
                assert!((w[3 + i].1 - wb[i]).abs() < 1e-7, "W_B[{i}] at ({x}, {y})");
            }
            assert!((gap.zeta - second).abs() < 1e-4, "ζ at ({x}, {y})");
            // The slip is the corner's velocity relative to the face along it: zero when
            // both translate together, the corner's own tangential speed when B rests.
            let moving =
                |s: &BodyState, v: Vec2, w: f64| BodyState::new(s.pose, Twist::new(v.x, v.y, w));
            let v = Vec2::new(0.3, -0.2);
            let (_, together) = rows_of(
                contact(Corner::B, side),
                &moving(&a, v, 0.0),
                &moving(&b, v, 0.0),
            );
            assert!(together.value.abs() < 1e-15, "{}", together.value);
            let still = moving(&b, Vec2::new(0.0, 0.0), 0.0);
            let (_, alone) = rows_of(contact(Corner::B, side), &a, &still);
            let p = a.pose.to_world(&Corner::B.body_offset(0.2, 0.4));
            let speed = a.twist.point_velocity(&p);
            // W_F on A is σ (t, ⊥p·t): read the face tangent t from it.
            let w: Vec<f64> = alone.w.iter().map(|(_, x)| x).collect();
            let along = speed.x * w[0] + speed.y * w[1];
            assert!(
                (alone.value - along).abs() < 1e-14,
                "{} vs {along}",
                alone.value
            );
            assert!(slip.value.is_finite());
        }
        seen.sort_by_key(|s| s.index());
        seen.dedup();
        assert_eq!(seen.len(), 4, "every face is tried: {seen:?}");
    }
}
