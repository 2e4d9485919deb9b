//! The contact between block k and block k+1 (App. G): two normal gaps, one slip speed,
//! and the test for loss of support.
//!
//! Gaps (G.2.2)–(G.2.3): the left gap g_N^{2k−1} is ℓ_b (corner b^k on the bottom face of
//! k+1) when (r_b^k − r_c^{k+1})·e₁^{k+1} > 0, else ℓ_c (corner c^{k+1} on the top face of
//! k); the right gap g_N^{2k} is ℓ_a (corner a^k on the bottom face of k+1) when
//! (r_a^k − r_d^{k+1})·e₁^{k+1} < 0, else ℓ_d (corner d^{k+1} on the top face of k). This
//! covers edge contact (a) and the four corner cases (b)i–iv of Figure 4.2 with the same
//! two constraints, and the switch between them is seamless: at the switch the two
//! candidate distances agree whenever the contact is closed.
//!
//! Slip (G.3.1): the slip speed is the one of the contact whose gap is smaller (the
//! closed one in a corner case; in edge contact both agree), always measured as the
//! velocity of the lower block relative to the upper one along the tangent of the face
//! touched, so it stays continuous across the cases.
//!
//! Support (G.2.4, corrected and made robust per ERRATA 23): as printed, the two
//! inequalities (r_b^k − r_d^{k+1})·e₁^{k+1} > 0 and (r_a^k − r_c^{k+1})·e₁^{k+1} < 0 each
//! describe a *loss* of support (block k+1 entirely left, resp. right, of block k), not the
//! requirement for it; and, being projections on e₁^{k+1}, they flip meaning when block
//! k+1 turns past ±π/2. Here block k supports block k+1 when (i) their faces face
//! each other, e₂^k·e₂^{k+1} > 0, (ii) the centre of k+1 lies above the line of the top
//! face of k, and (iii) the bottom face of k+1 overlaps the top face of k along e₁^k.
//! Otherwise the two gaps cannot close (the upper block has fallen off).

use crate::coordinates::{re, BodyState, Frame, Rotation, Scalar, Vec2};
use crate::corners::Corner;
use crate::gaps::{CornerOnFace, Face, PairRotations, PairRow};
use crate::slip::LowerBody;

/// e₂·e₂ above which a supported interface's gaps hold the contact (cos 60°); see
/// [`InterfaceContacts::holds`].
pub const HOLDS: f64 = 0.5;

/// Depth under a face, relative to its body's height, beyond which a corner over the
/// face that is nearer to the body's side face counts as having entered from the side
/// ([`Support::Sunk`]). Far above the round-off of resting contacts (gaps of −10⁻¹²),
/// far below the depths of that class (a corner 0.037 under a face and 4·10⁻⁵ from
/// the side, two fallen blocks of a shaken column, docs/method.md §10).
pub const SIDE_ENTRY_DEPTH: f64 = 1e-6;

/// The size of a body taking part in a contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Size {
    /// Width w.
    pub width: f64,
    /// Height h.
    pub height: f64,
}

impl Size {
    /// A w × h rectangle.
    #[must_use]
    pub fn new(width: f64, height: f64) -> Self {
        Self { width, height }
    }

    fn corner(self, c: Corner) -> Vec2 {
        c.body_offset(self.width, self.height)
    }
}

/// Which distance of (G.2.3) a gap currently measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GapCase {
    /// ℓ_a or ℓ_b: a top corner of the lower block against the bottom face of the upper.
    LowerCorner(Corner),
    /// ℓ_c or ℓ_d: a bottom corner of the upper block against the top face of the lower.
    UpperCorner(Corner),
}

/// Why an upper block is not supported by the block below.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Support {
    /// The bottom face of the upper block faces the top face of the lower one over a
    /// common stretch: the two gaps are meaningful.
    Supported,
    /// The upper block has turned by more than π/2 relative to the lower one.
    TurnedOver,
    /// The upper block's centre is below the line of the lower block's top face.
    Below,
    /// The faces do not overlap along the lower block's e₁: it has slid or fallen off.
    Beside,
    /// A corner of one body lies over the other's face but deeper in it than half that
    /// body's height, or deeper than it is from that body's side face: the upper block
    /// reached this place from the side (for example a block lying on the floor that the
    /// shaken base slides against, or two fallen blocks touching corner to side), not by
    /// resting on the lower body's top face. The gaps would report a penetration the
    /// bodies do not have, and a position correction through the face, where the
    /// corner contacts of the side resolve it by a short way.
    Sunk,
}

/// One normal gap of an interface, with the distance of (G.2.3) it measures.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InterfaceGap<T = f64> {
    /// The case of (G.2.2).
    pub case: GapCase,
    /// g with W and ζ; `w_first` is on the lower block, `w_second` on the upper.
    pub row: PairRow<T>,
}

/// The contact quantities of one interface k/k+1 (App. G).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InterfaceContacts<T = f64> {
    /// Whether the gaps are meaningful; when not, the contacts cannot close.
    pub support: Support,
    /// The left gap g_N^{2k−1} (ℓ_b or ℓ_c), (G.2.2).
    pub left: InterfaceGap<T>,
    /// The right gap g_N^{2k} (ℓ_a or ℓ_d), (G.2.2).
    pub right: InterfaceGap<T>,
    /// The slip speed γ_F^k, (G.3.1); `w_first` is on the lower block.
    pub slip: PairRow<T>,
    /// e₂ᵏ · e₂ᵏ⁺¹ (real part): how squarely the faces face each other.
    pub facing: f64,
}

impl<T> InterfaceContacts<T> {
    /// Whether block k supports block k+1 (see [`Support`]).
    #[must_use]
    pub fn is_supported(&self) -> bool {
        self.support == Support::Supported
    }

    /// Whether the interface's two gaps hold the contact of the two bodies: supported,
    /// with the faces turned from each other by less than 60° (e₂·e₂ > [`HOLDS`]). A
    /// block turned further rests on a corner or lies on its side against the lower
    /// body; the gaps of (G.2.3), measured along faces that no longer face each other,
    /// would then flicker with the support test at e₂·e₂ = 0, and the corner contacts
    /// between any two bodies ([`crate::pairs`]) hold the contact instead.
    #[must_use]
    pub fn holds(&self) -> bool {
        self.is_supported() && self.facing > HOLDS
    }
}

/// [`Interface::holds`] with the support test of the two frames done already.
pub(crate) fn holds_given(support: Support, lower: &Frame, upper: &Frame) -> bool {
    support == Support::Supported && lower.e2.dot(&upper.e2) > HOLDS
}

/// The corners of an interface's bodies that face each other, in world coordinates (real
/// parts): the lower body's top corners a, b and the upper body's bottom corners c, d.
/// The choice of each gap (G.2.2), the support test and the side-entry test read them
/// all; they are computed once per interface.
#[derive(Debug, Clone, Copy)]
struct FacingCorners {
    a: Vec2,
    b: Vec2,
    c: Vec2,
    d: Vec2,
}

impl FacingCorners {
    fn at(&self, corner: Corner) -> Vec2 {
        match corner {
            Corner::A => self.a,
            Corner::B => self.b,
            Corner::C => self.c,
            Corner::D => self.d,
        }
    }
}

/// [`Interface::bottom_corners_along`] from the corners c and d in world coordinates.
fn along_lower(pl: &Frame, c: Vec2, d: Vec2) -> (f64, f64) {
    let along = |p: Vec2| (p - pl.r).dot(&pl.e1);
    (along(c), along(d))
}

/// One end of an interface for the choice of its gap (G.2.2): the lower block's top
/// corner, the upper block's bottom corner, and the sign that makes "beyond" point
/// outward from the interface along e₁ of the upper block.
#[derive(Debug, Clone, Copy)]
struct InterfaceEnd {
    lower: Corner,
    upper: Corner,
    outward: f64,
}

/// The left end, (G.2.2)₁: ℓ_b when (b − c)·e₁ > 0, else ℓ_c.
const LEFT_END: InterfaceEnd = InterfaceEnd {
    lower: Corner::B,
    upper: Corner::C,
    outward: 1.0,
};

/// The right end, (G.2.2)₂: ℓ_a when (a − d)·e₁ < 0, else ℓ_d.
const RIGHT_END: InterfaceEnd = InterfaceEnd {
    lower: Corner::A,
    upper: Corner::D,
    outward: -1.0,
};

/// The contact between a lower body (block k, or the base) and the upper block k+1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Interface {
    /// Size of the lower body.
    pub lower: Size,
    /// Size of the upper body.
    pub upper: Size,
}

/// The two bodies of an interface with their rotations, evaluated once for the two gaps,
/// the slip and the decisions between the cases (their frames and facing corners): see
/// [`Rotation`].
struct Turned<'a, T> {
    lower: &'a BodyState<T>,
    upper: &'a BodyState<T>,
    rotations: (Rotation<T>, Rotation<T>),
    frames: (Frame, Frame),
    corners: FacingCorners,
}

impl<'a, T: Scalar> Turned<'a, T> {
    fn of(interface: &Interface, lower: &'a BodyState<T>, upper: &'a BodyState<T>) -> Self {
        let rotations = (lower.pose.rotation(), upper.pose.rotation());
        Self::with(interface, lower, upper, rotations)
    }

    /// With the rotations (lower, upper) of the bodies evaluated already.
    fn with(
        interface: &Interface,
        lower: &'a BodyState<T>,
        upper: &'a BodyState<T>,
        rotations: (Rotation<T>, Rotation<T>),
    ) -> Self {
        let frames = (
            Frame::turned(&lower.pose, &rotations.0),
            Frame::turned(&upper.pose, &rotations.1),
        );
        Self {
            lower,
            upper,
            rotations,
            frames,
            corners: interface.facing_corners(&frames.0, &frames.1),
        }
    }

    /// A top corner of the lower body on the bottom face of the upper.
    fn lower_corner(&self) -> PairRotations<T> {
        PairRotations {
            corner: self.rotations.0,
            face: self.rotations.1,
        }
    }

    /// A bottom corner of the upper body on the top face of the lower.
    fn upper_corner(&self) -> PairRotations<T> {
        PairRotations {
            corner: self.rotations.1,
            face: self.rotations.0,
        }
    }
}

impl Interface {
    /// An interface between bodies of the given sizes.
    #[must_use]
    pub fn new(lower: Size, upper: Size) -> Self {
        Self { lower, upper }
    }

    /// Support test (G.2.4), corrected and robust past ±π/2 (ERRATA 23).
    #[must_use]
    pub fn support<T: Scalar>(&self, lower: &BodyState<T>, upper: &BodyState<T>) -> Support {
        self.support_of(&Frame::of(&lower.pose), &Frame::of(&upper.pose))
    }

    /// Whether the interface's gaps hold the contact of the two bodies
    /// ([`InterfaceContacts::holds`], the same decision), from their frames alone: the
    /// support test and the facing, without the gaps and the slip.
    #[must_use]
    pub fn holds(&self, lower: &Frame, upper: &Frame) -> bool {
        holds_given(self.support_of(lower, upper), lower, upper)
    }

    /// [`Interface::support`] from the bodies' frames: a decision, not a value, so real
    /// parts only.
    pub(crate) fn support_of(&self, pl: &Frame, pu: &Frame) -> Support {
        self.support_at(pl, pu, &self.facing_corners(pl, pu))
    }

    /// [`Interface::support_of`] with the facing corners of the two frames at hand.
    fn support_at(&self, pl: &Frame, pu: &Frame, corners: &FacingCorners) -> Support {
        if pl.e2.dot(&pu.e2) <= 0.0 {
            return Support::TurnedOver;
        }
        let rel = pu.r - pl.r;
        if rel.dot(&pl.e2) <= 0.5 * self.lower.height {
            return Support::Below;
        }
        let (sc, sd) = along_lower(pl, corners.c, corners.d);
        let half = 0.5 * self.lower.width;
        if sc.max(sd) <= -half || sc.min(sd) >= half {
            return Support::Beside;
        }
        if self.sunk(pl, pu, corners) {
            return Support::Sunk;
        }
        Support::Supported
    }

    /// How far the two bodies are from the interface's gaps no longer holding their
    /// contact ([`InterfaceContacts::holds`]), as a length: the shorter of the common
    /// stretch of the faces along e₁ of the lower body and the height of the upper centre
    /// above the lower top face's line, scaled by how far e₂·e₂ is above [`HOLDS`]; 0
    /// when the support is lost already. The broad phase ([`crate::broad_phase`]) adds
    /// the pair's corner contacts when this falls below its margin.
    #[must_use]
    pub fn support_margin<T: Scalar>(&self, lower: &BodyState<T>, upper: &BodyState<T>) -> f64 {
        let (pl, pu) = (&Frame::of(&lower.pose), &Frame::of(&upper.pose));
        self.support_margin_given(self.support_of(pl, pu), pl, pu)
    }

    /// [`Interface::support_margin`] from the bodies' frames and their support test
    /// ([`Interface::support_of`]), for a caller that has both at hand.
    pub(crate) fn support_margin_given(&self, support: Support, pl: &Frame, pu: &Frame) -> f64 {
        if support != Support::Supported {
            return 0.0;
        }
        let (sc, sd) = self.bottom_corners_along(pl, pu);
        let half = 0.5 * self.lower.width;
        let common = (sc.max(sd).min(half) - sc.min(sd).max(-half)).max(0.0);
        let above = (pu.r - pl.r).dot(&pl.e2) - 0.5 * self.lower.height;
        // Falls to 0 as the faces turn towards 60° from each other, where the gaps stop
        // holding the contact ([`InterfaceContacts::holds`]): the corner contacts are
        // then in place before they are needed.
        let square = pl.e2.dot(&pu.e2);
        common.min(above) * ((square - HOLDS) / (1.0 - HOLDS)).max(0.0)
    }

    /// The facing corners of the two bodies at frames `pl` (lower) and `pu` (upper).
    fn facing_corners(&self, pl: &Frame, pu: &Frame) -> FacingCorners {
        let lower = |c: Corner| pl.point(&self.lower.corner(c));
        let upper = |c: Corner| pu.point(&self.upper.corner(c));
        FacingCorners {
            a: lower(Corner::A),
            b: lower(Corner::B),
            c: upper(Corner::C),
            d: upper(Corner::D),
        }
    }

    /// Where the upper block's bottom corners c and d lie along e₁ of the lower body,
    /// from its centre (real parts): the extent of the upper bottom face over the lower
    /// top face.
    fn bottom_corners_along(&self, pl: &Frame, pu: &Frame) -> (f64, f64) {
        let upper = |c: Corner| pu.point(&self.upper.corner(c));
        along_lower(pl, upper(Corner::C), upper(Corner::D))
    }

    /// Whether a bottom corner of the upper block lies over the top face of the lower one
    /// and inside the lower body deeper than the gaps can mean, or a top corner of the
    /// lower body lies so under the bottom face of the upper one (see [`Support::Sunk`]):
    /// below the body's centre line, or deeper under the face than it is from the
    /// body's nearer side face (by more than [`SIDE_ENTRY_DEPTH`] of the body's height).
    /// Such a corner entered the body through its side, and the gap to the face would
    /// push it out the long way. A block resting or pivoting on the lower one never
    /// does: its corners over the face are at depth ~0, and a corner pivoting past the
    /// edge is no longer over the face.
    fn sunk(&self, pl: &Frame, pu: &Frame, corners: &FacingCorners) -> bool {
        let deep = |corner: Vec2, face_pose: &Frame, face: Size, outward: f64| {
            let d = corner - face_pose.r;
            // How far inside the face's extent, and below the face's line.
            let side = 0.5 * face.width - d.dot(&face_pose.e1).abs();
            let depth = 0.5 * face.height - outward * d.dot(&face_pose.e2);
            side > 0.0
                && (depth > 0.5 * face.height
                    || (depth > side && depth > SIDE_ENTRY_DEPTH * face.height))
        };
        [corners.c, corners.d]
            .into_iter()
            .any(|c| deep(c, pl, self.lower, 1.0))
            || [corners.a, corners.b]
                .into_iter()
                .any(|c| deep(c, pu, self.upper, -1.0))
    }

    /// The left gap: ℓ_b or ℓ_c per (G.2.2)₁.
    #[must_use]
    pub fn left_gap<T: Scalar>(
        &self,
        lower: &BodyState<T>,
        upper: &BodyState<T>,
    ) -> InterfaceGap<T> {
        self.end_gap(LEFT_END, &Turned::of(self, lower, upper))
    }

    /// The right gap: ℓ_a or ℓ_d per (G.2.2)₂.
    #[must_use]
    pub fn right_gap<T: Scalar>(
        &self,
        lower: &BodyState<T>,
        upper: &BodyState<T>,
    ) -> InterfaceGap<T> {
        self.end_gap(RIGHT_END, &Turned::of(self, lower, upper))
    }

    /// The gap at one end of the interface, (G.2.2): the lower block's top corner against
    /// the upper's bottom face when that corner lies beyond the upper's bottom corner
    /// along e₁ of the upper block, outward from the interface; otherwise the upper
    /// corner against the lower's top face. The bodies' frames decide the case.
    fn end_gap<T: Scalar>(&self, end: InterfaceEnd, bodies: &Turned<'_, T>) -> InterfaceGap<T> {
        let (l, u) = (bodies.corners.at(end.lower), bodies.corners.at(end.upper));
        if end.outward * (l - u).dot(&bodies.frames.1.e1) > 0.0 {
            self.lower_corner_gap(end.lower, bodies)
        } else {
            self.upper_corner_gap(end.upper, bodies)
        }
    }

    /// The pairing of a top corner of the lower block with the bottom face of the upper.
    fn lower_corner_pair<T: Scalar>(
        &self,
        corner: Corner,
        lower: &BodyState<T>,
        upper: &BodyState<T>,
    ) -> CornerOnFace<T> {
        CornerOnFace {
            corner_body: *lower,
            corner: self.lower.corner(corner),
            face_body: *upper,
            face: Face::bottom(self.upper.height),
        }
    }

    /// The pairing of a bottom corner of the upper block with the top face of the lower.
    fn upper_corner_pair<T: Scalar>(
        &self,
        corner: Corner,
        lower: &BodyState<T>,
        upper: &BodyState<T>,
    ) -> CornerOnFace<T> {
        CornerOnFace {
            corner_body: *upper,
            corner: self.upper.corner(corner),
            face_body: *lower,
            face: Face::top(self.lower.height),
        }
    }

    fn lower_corner_gap<T: Scalar>(&self, corner: Corner, b: &Turned<'_, T>) -> InterfaceGap<T> {
        let pair = self.lower_corner_pair(corner, b.lower, b.upper);
        InterfaceGap {
            case: GapCase::LowerCorner(corner),
            row: pair.gap_turned(&b.lower_corner()),
        }
    }

    fn upper_corner_gap<T: Scalar>(&self, corner: Corner, b: &Turned<'_, T>) -> InterfaceGap<T> {
        let pair = self.upper_corner_pair(corner, b.lower, b.upper);
        InterfaceGap {
            case: GapCase::UpperCorner(corner),
            // Stored corner-body first; swap so that the lower block comes first.
            row: pair.gap_turned(&b.upper_corner()).swapped(),
        }
    }

    /// The slip speed (G.3.1) of the contact measured by `gap`.
    #[must_use]
    pub fn slip_at<T: Scalar>(
        &self,
        gap: &InterfaceGap<T>,
        lower: &BodyState<T>,
        upper: &BodyState<T>,
    ) -> PairRow<T> {
        self.turned_slip_at(gap, &Turned::of(self, lower, upper))
    }

    /// [`Interface::slip_at`] with the bodies' rotations at hand.
    fn turned_slip_at<T: Scalar>(&self, gap: &InterfaceGap<T>, b: &Turned<'_, T>) -> PairRow<T> {
        match gap.case {
            GapCase::LowerCorner(c) => self
                .lower_corner_pair(c, b.lower, b.upper)
                .slip_turned(LowerBody::Corner, &b.lower_corner()),
            GapCase::UpperCorner(c) => self
                .upper_corner_pair(c, b.lower, b.upper)
                .slip_turned(LowerBody::Face, &b.upper_corner())
                .swapped(),
        }
    }

    /// Both gaps, the slip speed of the closer contact (left on a tie) and the support
    /// state, App. G.
    #[must_use]
    pub fn contacts<T: Scalar>(
        &self,
        lower: &BodyState<T>,
        upper: &BodyState<T>,
    ) -> InterfaceContacts<T> {
        self.turned_contacts(&Turned::of(self, lower, upper))
    }

    /// [`Interface::contacts`] with the rotations (lower, upper) of the bodies evaluated
    /// already: a block is the upper body of one interface and the lower of the next,
    /// and the scene turns it once for both.
    pub(crate) fn contacts_turned<T: Scalar>(
        &self,
        lower: &BodyState<T>,
        upper: &BodyState<T>,
        rotations: (Rotation<T>, Rotation<T>),
    ) -> InterfaceContacts<T> {
        self.turned_contacts(&Turned::with(self, lower, upper, rotations))
    }

    fn turned_contacts<T: Scalar>(&self, bodies: &Turned<'_, T>) -> InterfaceContacts<T> {
        let frames = &bodies.frames;
        let left = self.end_gap(LEFT_END, bodies);
        let right = self.end_gap(RIGHT_END, bodies);
        let closer = if re(right.row.value) < re(left.row.value) {
            &right
        } else {
            &left
        };
        InterfaceContacts {
            support: self.support_at(&frames.0, &frames.1, &bodies.corners),
            left,
            right,
            slip: self.turned_slip_at(closer, bodies),
            facing: frames.0.e2.dot(&frames.1.e2),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coordinates::Twist;
    use crate::gaps::tests::{fd_oracle, state};

    fn lire() -> Interface {
        Interface::new(Size::new(1.0, 0.2), Size::new(1.0, 0.2))
    }

    /// Regression (shaken column, ω = 4, t ≈ 9.53): a block w = 0.2, h = 0.4 standing on
    /// the floor beside the base (w = 1, h = 0.1, top face 0.1 above the floor) that the
    /// base slides against is not supported by it; its corners over the base's top face
    /// sit a whole base height deep. Reporting it as supported gave a gap of −0.1 and,
    /// once the first Newton update moved the block, a zero Jacobian row (singular).
    #[test]
    fn a_block_beside_a_low_base_is_sunk_not_supported() {
        let i = Interface::new(Size::new(1.0, 0.1), Size::new(0.2, 0.4));
        let base = state(0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        // Bottom of the block at the base's bottom, its left corner 0.01 over the base.
        let beside = state(0.59, 0.15, 0.0, 0.0, 0.0, 0.0);
        assert_eq!(i.support(&base, &beside), Support::Sunk);
        assert!(!i.contacts(&base, &beside).is_supported());
        // Mirrored, and with the upper block wider than the lower one.
        assert_eq!(
            i.support(&base, &state(-0.59, 0.15, 0.0, 0.0, 0.0, 0.0)),
            Support::Sunk
        );
        let wide = Interface::new(Size::new(0.2, 0.1), Size::new(1.0, 0.4));
        assert_eq!(
            wide.support(&base, &state(0.55, 0.15, 0.0, 0.0, 0.0, 0.0)),
            Support::Sunk
        );
        // Resting on the top face, slightly penetrating: supported.
        assert_eq!(
            i.support(&base, &state(0.45, 0.25 - 1e-9, 0.0, 0.0, 0.0, 0.0)),
            Support::Supported
        );
        // Overhanging by half its width and tipped by 10° about the right edge a^k of a
        // Lire block (the edge under the middle of its bottom face): still supported.
        let l = lire();
        let th: f64 = -10f64.to_radians();
        let (s, c) = th.sin_cos();
        // Centre = a^k + R(θ)(0, h/2) with a^k = (0.5, 0.1), h = 0.2.
        let pivot = state(0.5 - 0.1 * s, 0.1 + 0.1 * c, th, 0.0, 0.0, 0.0);
        assert_eq!(l.support(&base, &pivot), Support::Supported);
    }

    /// Regression (a shaken column beyond the 135-run matrix, n = 6, ω = 8, μ = 1,
    /// t = 1.5826): blocks 1 and 2, fallen and lying on the floor side by side with
    /// their former interface faces turned 16° from each other, touch corner to side: a
    /// bottom corner of block 2 lies 4·10⁻⁵ inside block 1's side face, just under the
    /// end of its top face. The support test passed, the gaps said −0.037, and the next
    /// step pushed block 2 out through block 1's top face (3.4 cm in one step, energy
    /// +0.6). 17 of the 135 matrix runs had such phantom gaps, down to −0.14.
    #[test]
    fn a_corner_that_entered_through_the_side_face_is_sunk_not_supported() {
        let size = Size::new(0.2, 0.4);
        let i = Interface::new(size, size);
        let lower = state(
            1.110_255_416_966_587_7,
            0.154_826_542_936_385_92,
            -4.018_012_782_101_156,
            0.0,
            0.0,
            0.0,
        );
        let upper = state(
            0.697_908_640_794_571_4,
            0.139_728_840_945_547,
            1.979_783_427_950_304_8,
            0.0,
            0.0,
            0.0,
        );
        let depth = crate::overlap::penetration_depth((&lower.pose, size), (&upper.pose, size));
        assert!(depth < 1e-4, "{depth}");
        assert_eq!(i.support(&lower, &upper), Support::Sunk);
        // Aligned blocks resting flush, corners at the very ends of the faces, and a
        // corner just inside the face's end at a resting contact's round-off: supported.
        let base = state(0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        for (x, dy) in [(0.0, 1e-12), (0.2 - 1e-9, 1e-12), (0.1, 1e-9)] {
            let on = state(x, 0.4 - dy, 0.0, 0.0, 0.0, 0.0);
            assert_eq!(i.support(&base, &on), Support::Supported, "x = {x}");
        }
    }

    #[test]
    fn flush_blocks_have_zero_gaps_and_edge_slip() {
        let i = lire();
        let lower = state(0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        let upper = state(0.3, 0.2, 0.0, 0.5, 0.0, 0.0);
        let c = i.contacts(&lower, &upper);
        assert!(c.is_supported());
        assert!(c.left.row.value.abs() < 1e-15 && c.right.row.value.abs() < 1e-15);
        // Upper shifted right: its corner c^{k+1} lies over the top face of k (ℓ_c), and
        // the corner a^k lies under the bottom face of k+1 (ℓ_a).
        assert_eq!(c.left.case, GapCase::UpperCorner(Corner::C));
        assert_eq!(c.right.case, GapCase::LowerCorner(Corner::A));
        // Lower relative to upper: −0.5.
        assert!((c.slip.value + 0.5).abs() < 1e-15);
    }

    #[test]
    fn figure_4_2_corner_cases() {
        let i = lire();
        let lower = state(0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        // (b)iv-like: upper tilted clockwise resting on its corner d on the top face of k,
        // upper overhanging to the left so d^{k+1} is inside the face.
        let th: f64 = -0.1;
        let d_body = Corner::D.body_offset(1.0, 0.2);
        // Place the upper block so that its corner d sits at (0.2, 0.1).
        let pose = crate::coordinates::Pose::new(0.0, 0.0, th);
        let d_world = pose.to_world(&d_body);
        let upper = state(0.2 - d_world.x, 0.1 - d_world.y, th, 0.0, 0.0, 0.0);
        let c = i.contacts(&lower, &upper);
        assert_eq!(c.right.case, GapCase::UpperCorner(Corner::D));
        assert!(c.right.row.value.abs() < 1e-14);
        assert!(c.left.row.value > 0.05);
        // (b)ii: upper tilted counter-clockwise and overhanging left, over the corner b^k.
        let upper = state(-0.3, 0.25, 0.1, 0.0, 0.0, 0.0);
        let c = i.contacts(&lower, &upper);
        assert_eq!(c.left.case, GapCase::LowerCorner(Corner::B));
        let g = c.left.row.value;
        // Distance from b^k = (−0.5, 0.1) to the bottom line of the upper block.
        let b = Vec2::new(-0.5, 0.1);
        let up = upper.pose;
        let expected = (up.r() - b).dot(&up.e2()) - 0.1;
        assert!((g - expected).abs() < 1e-15);
    }

    #[test]
    fn switch_between_corner_cases_is_continuous_when_closed() {
        // Upper block resting tilted on the corner b^k; slide it so that its corner c
        // passes over b^k: the left gap switches from ℓ_b to ℓ_c, both zero at the switch.
        let i = lire();
        let lower = state(0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        let th = 0.05_f64;
        let b = Vec2::new(-0.5, 0.1);
        let pose0 = crate::coordinates::Pose::new(0.0, 0.0, th);
        let c_off = pose0.to_world(&Corner::C.body_offset(1.0, 0.2));
        // Corner c of the upper block exactly on b^k.
        let upper = state(b.x - c_off.x, b.y - c_off.y, th, 0.0, 0.0, 0.0);
        let eps = 1e-9;
        let mut left_of = upper;
        left_of.pose.x -= eps;
        let mut right_of = upper;
        right_of.pose.x += eps;
        let g1 = i.left_gap(&lower, &left_of);
        let g2 = i.left_gap(&lower, &right_of);
        assert_ne!(g1.case, g2.case);
        assert!(g1.row.value.abs() < 1e-8 && g2.row.value.abs() < 1e-8);
    }

    #[test]
    fn interface_rows_match_finite_differences_in_every_case() {
        let i = Interface::new(Size::new(1.2, 0.3), Size::new(0.8, 0.25));
        let lower = state(0.1, -0.05, 0.04, 0.3, -0.2, 0.6);
        for (x, th) in [
            (0.5, 0.07),
            (-0.45, -0.09),
            (0.0, 0.0),
            (0.2, -0.03),
            (-0.3, 0.12),
        ] {
            let upper = state(x, 0.3, th, -0.4, 0.25, -0.9);
            for side in 0..2 {
                let pick = |l: &BodyState, u: &BodyState| {
                    if side == 0 {
                        i.left_gap(l, u)
                    } else {
                        i.right_gap(l, u)
                    }
                };
                let g = pick(&lower, &upper);
                let (wl, wu, second) = fd_oracle(&|l, u| pick(l, u).row.value, &lower, &upper);
                for k in 0..3 {
                    assert!(
                        (g.row.w_first[k] - wl[k]).abs() < 1e-7,
                        "{:?} W_lower",
                        g.case
                    );
                    assert!(
                        (g.row.w_second[k] - wu[k]).abs() < 1e-7,
                        "{:?} W_upper",
                        g.case
                    );
                }
                assert!(
                    (g.row.zeta - second).abs() < 1e-4,
                    "{:?} zeta {} vs {}",
                    g.case,
                    g.row.zeta,
                    second
                );
                // The slip of this contact: γ = Wᵀu and γ̇ − Wᵀu̇ = ζ_F.
                let s = i.slip_at(&g, &lower, &upper);
                assert!((s.rate(&lower, &upper) - s.value).abs() < 1e-14);
                let h = 1e-6;
                let z = Twist::default();
                let fd = (i
                    .slip_at(&g, &lower.advanced(h, &z), &upper.advanced(h, &z))
                    .value
                    - i.slip_at(&g, &lower.advanced(-h, &z), &upper.advanced(-h, &z))
                        .value)
                    / (2.0 * h);
                assert!((s.zeta - fd).abs() < 1e-7, "{:?} slip zeta", g.case);
            }
        }
    }

    #[test]
    fn support_is_lost_when_sliding_off_falling_beside_or_turning_over() {
        let i = lire();
        let lower = state(0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        assert_eq!(
            i.support(&lower, &state(0.99, 0.2, 0.0, 0.0, 0.0, 0.0)),
            Support::Supported
        );
        assert_eq!(
            i.support(&lower, &state(1.01, 0.2, 0.0, 0.0, 0.0, 0.0)),
            Support::Beside
        );
        assert_eq!(
            i.support(&lower, &state(-1.01, 0.2, 0.0, 0.0, 0.0, 0.0)),
            Support::Beside
        );
        assert_eq!(
            i.support(&lower, &state(0.0, 0.05, 0.0, 0.0, 0.0, 0.0)),
            Support::Below
        );
        // Turned past ±π/2 (ERRATA 23): a projection on e₁^{k+1} would flip sign here.
        for th in [1.7, -1.7, 3.0, -3.1] {
            assert_eq!(
                i.support(&lower, &state(0.0, 0.7, th, 0.0, 0.0, 0.0)),
                Support::TurnedOver
            );
        }
        // Turned by almost π/2 but still above and overlapping: supported.
        assert_eq!(
            i.support(&lower, &state(0.3, 0.65, 1.5, 0.0, 0.0, 0.0)),
            Support::Supported
        );
    }
}
