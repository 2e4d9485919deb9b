//! The broad phase: which corner contacts ([`crate::pairs`]) a step may need.
//!
//! Before each step, every body (base and blocks) gets a bounding box grown by a margin
//! that covers how far it can move in the step, m = 2 Δt (|v| + |ω| R) + δ, with R the
//! half diagonal and δ = [`MARGIN`] times the smallest block dimension (what a body can
//! gain in speed within the step, by gravity or an impact, is covered by the factor 2
//! and by δ; a contact missed all the same is caught after the step, see
//! [`crate::simulation`]). Boxes are swept along the axis on which the bodies' centres
//! spread most (a column: y, so each box meets only its neighbours' boxes: O(n log n)),
//! and for each pair of boxes that meet, each corner of one body whose gap to the other
//! body is below the sum of their margins is a candidate.
//!
//! A block and a body it rests on are joined by an interface of App. G
//! ([`crate::arrangement`]): while the lower body firmly supports the block (the
//! interface's [`Interface::support_margin`] exceeds the margins) their corner contacts
//! are not needed, so a standing column has no candidates at all and
//! pays only for the sweep. Near the loss of support they are added; the system then
//! uses either the interface's gaps (supported) or the corner contacts (not), never both.
//!
//! [`Interface::support_margin`]: crate::interface::Interface::support_margin

use crate::coordinates::{BodyState, Frame, Pose, Twist, Vec2};
use crate::corners::{frame_corners, Corner};
use crate::gaps::Face;
use crate::interface::{holds_given, Size, Support};
use crate::overlap::Body;
use crate::pairs::{body_index, ContactLine, CornerContact, LineContacts, LineKind, Side};
use crate::scene::Scene;

/// The fixed part δ of the margin, as a fraction of the smallest block dimension.
pub const MARGIN: f64 = 0.05;

/// Two faces face each other (flush) when their normals' dot product is below −FLUSH.
const FLUSH: f64 = 0.999;

/// Two faces whose distances from a corner differ by less than this fraction of the
/// smallest block dimension are a tie ([`Side::facing`]).
pub const TIE: f64 = 1e-6;

/// One body as the broad phase sees it.
#[derive(Debug, Clone, Copy)]
struct Boxed {
    body: Body,
    /// The state's frame: each body's sin θ, cos θ once for all its corners and faces.
    frame: Frame,
    size: Size,
    lo: [f64; 2],
    hi: [f64; 2],
    margin: f64,
}

fn boxed(body: Body, state: BodyState, size: Size, dt: f64, delta: f64) -> Boxed {
    let frame = Frame::of(&state.pose);
    let corners = frame_corners(&frame, size.width, size.height);
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for c in corners {
        lo = [lo[0].min(c.x), lo[1].min(c.y)];
        hi = [hi[0].max(c.x), hi[1].max(c.y)];
    }
    let radius = 0.5 * size.width.hypot(size.height);
    let speed = state.twist.v().norm() + state.twist.omega.abs() * radius;
    Boxed {
        body,
        frame,
        size,
        lo,
        hi,
        margin: 2.0 * dt * speed + delta,
    }
}

/// The face of `b` that corner `c` of `a` meets and its signed distance from it
/// ([`Side::facing`], ties within `tie`).
fn corner_face(a: &Boxed, c: Corner, b: &Boxed, tie: f64) -> (Side, f64) {
    let p = a.frame.point(&c.body_offset(a.size.width, a.size.height));
    Side::facing(&p, &a.frame.r, &b.frame, b.size, tie)
}

/// Body `b` of the scene at time t (a block's pose from q, its velocity from u, or at
/// rest without u), boxed for a step of `dt` with the fixed margin `delta`.
fn scene_box(
    scene: &Scene,
    (t, q, u): (f64, &[f64], Option<&[f64]>),
    b: Body,
    dt: f64,
    delta: f64,
) -> Boxed {
    match b {
        Body::Block(k) => {
            let twist = u.map_or_else(Twist::default, |u| Twist::from_slice(&u[3 * k - 3..3 * k]));
            let state = BodyState::new(Pose::from_slice(&q[3 * k - 3..3 * k]), twist);
            boxed(b, state, scene.size(k), dt, delta)
        }
        Body::Base | Body::Floor => {
            boxed(Body::Base, scene.base().state(t), scene.size(0), dt, delta)
        }
    }
}

/// The gap of corner `c` of `a` against the body `b`: the largest signed distance from
/// b's faces, positive exactly when the corner is outside b.
fn corner_gap(a: &Boxed, c: Corner, b: &Boxed) -> f64 {
    let p = a.frame.point(&c.body_offset(a.size.width, a.size.height));
    Face::of_rectangle(b.size.width, b.size.height)
        .iter()
        .map(|f| f.distance(&b.frame, &p))
        .fold(f64::NEG_INFINITY, f64::max)
}

/// The corner contacts that the step from (t, q, u) with step size `dt` may need, grouped
/// into the lines they lie on ([`LineContacts`]), in a deterministic order.
///
/// # Panics
/// When q or u holds fewer than 3 entries per block.
#[must_use]
pub fn corner_contacts(scene: &Scene, t: f64, q: &[f64], u: &[f64], dt: f64) -> Vec<LineContacts> {
    scan(scene, t, q, u, dt).lines
}

/// What the broad phase finds at one state, for the step from it.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Scan {
    /// [`corner_contacts`].
    pub lines: Vec<LineContacts>,
    /// Whether each interface's gaps hold its contact ([`Scene::interfaces_holding`]).
    pub holds: Vec<bool>,
}

/// [`corner_contacts`] and [`Scene::interfaces_holding`] at (t, q, u) together: both read
/// every body's frame and every interface's support test, which are computed here once
/// (apart, the two and the support margins turned each body three times and tested each
/// interface twice: 1.7 % of the instructions of the Lire collapse's steps).
///
/// # Panics
/// When q or u holds fewer than 3 entries per block.
#[must_use]
pub fn scan(scene: &Scene, t: f64, q: &[f64], u: &[f64], dt: f64) -> Scan {
    let delta = MARGIN * scene.smallest_block_dimension();
    let bodies: Vec<Boxed> = std::iter::once(Body::Base)
        .chain((1..=scene.n_blocks()).map(Body::Block))
        .map(|b| scene_box(scene, (t, q, Some(u)), b, dt, delta))
        .collect();
    // Interface k joins its lower body and its upper block (`bodies` holds the base,
    // then the blocks: body i is block i).
    let frames = |k: usize| {
        let seat = scene.arrangement().seats()[k];
        (
            &bodies[body_index(seat.lower)].frame,
            &bodies[seat.upper].frame,
        )
    };
    let supports: Vec<Support> = (0..scene.n_interfaces())
        .map(|k| {
            let (lower, upper) = frames(k);
            scene.interface(k).support_of(lower, upper)
        })
        .collect();
    let holds = supports
        .iter()
        .enumerate()
        .map(|(k, &s)| {
            let (lower, upper) = frames(k);
            holds_given(s, lower, upper)
        })
        .collect();
    Scan {
        lines: lines_near(scene, &bodies, &supports, delta),
        holds,
    }
}

/// The corner contacts among the boxed `bodies` (the base, then the blocks), with the
/// support test of each interface done already.
fn lines_near(
    scene: &Scene,
    bodies: &[Boxed],
    supports: &[Support],
    delta: f64,
) -> Vec<LineContacts> {
    let axis = sweep_axis(bodies);
    let mut order: Vec<usize> = (0..bodies.len()).collect();
    order.sort_by(|&i, &j| {
        let (a, b) = (&bodies[i], &bodies[j]);
        (a.lo[axis] - a.margin).total_cmp(&(b.lo[axis] - b.margin))
    });
    let mut out = Vec::new();
    let mut buffers = PairBuffers::default();
    for (pos, &i) in order.iter().enumerate() {
        let a = &bodies[i];
        for &j in &order[pos + 1..] {
            let b = &bodies[j];
            if b.lo[axis] - b.margin > a.hi[axis] + a.margin {
                break;
            }
            let other = 1 - axis;
            let m = a.margin + b.margin;
            if b.lo[other] > a.hi[other] + m || a.lo[other] > b.hi[other] + m {
                continue;
            }
            if firmly_supported(scene, supports, a, b, m) || !may_touch(scene, a.body, b.body) {
                continue;
            }
            pair_candidates(
                a,
                b,
                (m, m - 2.0 * delta),
                TIE * delta / MARGIN,
                &mut buffers,
            );
            lines_of(a, b, &mut buffers, &mut out);
        }
    }
    out.sort_by_key(|l| l.line.key());
    out
}

/// Whether bodies `a` and `b` may touch: any two may, unless the scene keeps to
/// neighbour contacts ([`Scene::neighbours_only`]), where only two bodies an interface
/// joins do.
fn may_touch(scene: &Scene, a: Body, b: Body) -> bool {
    !scene.neighbours_only()
        || scene.arrangement().seats().iter().any(|s| {
            let upper = Body::Block(s.upper);
            (s.lower, upper) == (a, b) || (s.lower, upper) == (b, a)
        })
}

/// The buffers of one pair's corner contacts, reused from pair to pair within a scan
/// (a pair's lists are short, but a fresh list per pair and line cost 5 % of the
/// instructions of a pile of six blocks at rest).
#[derive(Debug, Default)]
struct PairBuffers {
    /// The pair's corner contacts ([`pair_candidates`]).
    found: Vec<Candidate>,
    /// [`flush_sides`] of the pair (a, b) given to [`pair_candidates`], then of (b, a).
    flush: [[Option<Side>; 4]; 2],
    /// Each with the line it lies on.
    lined: Vec<(ContactLine, Candidate)>,
    /// The contacts of one line.
    line: Vec<Candidate>,
}

/// The corner contacts of one pair (`buffers.found`) grouped into the lines they lie on
/// ([`ContactLine`]), appended to `out`. A line holds at most two contacts: where more
/// were found (two faces lying flush, each body's corners on the other's face), the two
/// at the ends of the line among those within the pair's margin of the closest are
/// kept, since a line contact in the plane has two independent contact forces and more
/// would make Newton's matrix singular.
fn lines_of(a: &Boxed, b: &Boxed, buffers: &mut PairBuffers, out: &mut Vec<LineContacts>) {
    let (lo, hi) = if body_index(a.body) < body_index(b.body) {
        (a, b)
    } else {
        (b, a)
    };
    // A corner of `lo` on a face of `hi` lies on the line of the face of `lo` flush
    // with that face, if any.
    let flush = buffers.flush[usize::from(hi.body == b.body)];
    let line_of = |c: &CornerContact| {
        let kind = if c.face_body == lo.body {
            LineKind::Face(c.face)
        } else {
            flush[c.face.index()].map_or(LineKind::Corner(c.corner, c.face), LineKind::Face)
        };
        ContactLine {
            lo: lo.body,
            hi: hi.body,
            kind,
        }
    };
    let PairBuffers {
        found, lined, line, ..
    } = buffers;
    lined.clear();
    lined.extend(found.iter().map(|c| (line_of(&c.contact), *c)));
    // The lines in the order their first contact was found, each with its contacts in
    // the order found.
    for (first, &(l, _)) in lined.iter().enumerate() {
        if lined[..first].iter().any(|(seen, _)| *seen == l) {
            continue;
        }
        line.clear();
        line.extend(
            lined[first..]
                .iter()
                .filter(|(on, _)| *on == l)
                .map(|&(_, c)| c),
        );
        out.push(line_ends(l, line, (lo, hi), a.margin + b.margin));
    }
}

/// The world tangent of face `side` of `body`.
fn tangent(body: &Boxed, side: Side) -> Vec2 {
    body.frame.to_world(&side.face(body.size).tangent)
}

/// The contacts `list` found on `line` of the pair (`lo`, `hi`: its bodies in the
/// order of the line) cut to the two at its ends ([`lines_of`]); `near` is the pair's
/// margin.
fn line_ends(
    line: ContactLine,
    list: &mut Vec<Candidate>,
    (lo, hi): (&Boxed, &Boxed),
    near: f64,
) -> LineContacts {
    if list.len() > 2 {
        // The ends of the contact region: among the corners within `near` of the
        // closest (far corners of a long body lie on the line's ends too).
        let closest = list.iter().map(|c| c.gap).fold(f64::INFINITY, f64::min);
        list.retain(|c| c.gap <= closest + near);
    }
    if list.len() > 2 {
        let along = match line.kind {
            LineKind::Face(side) => tangent(lo, side),
            LineKind::Corner(..) => tangent(hi, list[0].contact.face),
        };
        let s = |c: &Candidate| c.point.dot(&along);
        list.sort_by(|x, y| s(x).total_cmp(&s(y)));
        let last = list[list.len() - 1];
        list.truncate(1);
        list.push(last);
    }
    list.sort_by_key(|c| c.contact.key());
    let mut contacts = [None; 2];
    for (slot, c) in contacts.iter_mut().zip(list.iter()) {
        *slot = Some(c.contact);
    }
    LineContacts { line, contacts }
}

/// The corner contacts of one pair of bodies whose gap is below `m`, with their points,
/// into `buffers.found`. A corner counts against the face it meets only within that
/// face's extent, or beyond its end by no more than `reach` (how far the bodies move
/// within the step): a corner beyond the end of a face does not touch it, the other
/// body's corner at that end does, unless the two meet head-on.
fn pair_candidates(
    a: &Boxed,
    b: &Boxed,
    (m, reach): (f64, f64),
    tie: f64,
    buffers: &mut PairBuffers,
) {
    let PairBuffers {
        found,
        flush: flush_of,
        ..
    } = buffers;
    found.clear();
    for ((x, y), flush) in [(a, b), (b, a)].into_iter().zip(flush_of) {
        *flush = flush_sides(x, y);
        for c in Corner::ALL {
            let point = x.frame.point(&c.body_offset(x.size.width, x.size.height));
            let (face, gap) = match flush_face(flush, c, &point, y, tie) {
                Flush::Meets(face, gap) => (face, gap),
                Flush::Hangs => continue,
                Flush::No => corner_face(x, c, y, tie),
            };
            if gap >= m || face.beyond_end(&y.frame, y.size, &point) > reach + tie {
                continue;
            }
            let contact = CornerContact {
                corner_body: x.body,
                corner: c,
                face_body: y.body,
                face,
            };
            found.push(Candidate {
                contact,
                point,
                gap,
            });
        }
    }
}

/// What a face lying flush decides for a corner ([`flush_face`]).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Flush {
    /// The corner lies on that face's line within its extent: it meets that face, at
    /// this signed distance.
    Meets(Side, f64),
    /// It lies on that face's line beyond its end: it hangs over the edge.
    Hangs,
    /// No face of its body through it lies flush on a face of the other whose line
    /// holds it: the largest distance decides ([`Side::facing`]).
    No,
}

/// For each face of `x` (in the order of [`Side::ALL`]), the face of `y` it lies flush
/// with (normals anti-parallel within [`FLUSH`]), if any: once per pair, for
/// [`flush_face`].
fn flush_sides(x: &Boxed, y: &Boxed) -> [Option<Side>; 4] {
    let normals = |f: &Frame| [f.e2, -f.e2, f.e1, -f.e1];
    let (nx, ny) = (normals(&x.frame), normals(&y.frame));
    Side::ALL.map(|own| {
        let n = nx[own.index()];
        Side::ALL
            .into_iter()
            .find(|&s| ny[s.index()].dot(&n) < -FLUSH)
    })
}

/// The face of `y` that corner `c` of `x` (at `point`) meets where a face of `x` through
/// that corner lies flush on a face F of `y` (`flush`, from [`flush_sides`]: a block
/// lying on another or standing beside it) and the corner is on F's line (within
/// `tie`): F within its extent, none beyond its end, where the corner hangs over the
/// edge and the corner of `y` at that end meets x's flush face instead. The largest
/// distance alone would pair a corner level with F just past its end with the side
/// face of `y` there, whose line the corner, moving along F, cannot cross: a block
/// sliding back onto a base it overhung stopped with its corner at the base's corner
/// (crates/blockstack/tests/hard_cases.rs,
/// `a_block_sliding_back_onto_the_base_is_not_caught_at_its_corner`).
fn flush_face(flush: &[Option<Side>; 4], c: Corner, point: &Vec2, y: &Boxed, tie: f64) -> Flush {
    for own in Side::through(c) {
        let Some(side) = flush[own.index()] else {
            continue;
        };
        let distance = side.face(y.size).distance(&y.frame, point);
        if distance.abs() > tie {
            continue;
        }
        return if side.beyond_end(&y.frame, y.size, point) > tie {
            Flush::Hangs
        } else {
            Flush::Meets(side, distance)
        };
    }
    Flush::No
}

/// A corner contact found by the broad phase, with where its corner is.
#[derive(Debug, Clone, Copy)]
struct Candidate {
    contact: CornerContact,
    point: Vec2,
    gap: f64,
}

/// The gap of corner `corner` of `corner_body` against `face_body` at time t and block
/// coordinates q: the largest signed distance from the faces, positive exactly when the
/// corner is outside (what the missed-contact check and the tests measure).
///
/// # Panics
/// When q holds fewer than 3 entries per block.
#[must_use]
pub fn corner_gap_of(
    scene: &Scene,
    t: f64,
    q: &[f64],
    corner_body: Body,
    corner: Corner,
    face_body: Body,
) -> f64 {
    let body = |b| scene_box(scene, (t, q, None), b, 0.0, 0.0);
    corner_gap(&body(corner_body), corner, &body(face_body))
}

/// Every corner contact between bodies `a` and `b` (base or blocks, corners of each
/// against the other, within the faces' extents up to how far the bodies move in a step
/// of `dt`), with the faces chosen at (t, q, u) whatever the distance, grouped into
/// lines: what a step that missed the pair's contact is taken again with
/// ([`crate::stepping`]).
///
/// # Panics
/// When q or u holds fewer than 3 entries per block.
#[must_use]
pub fn pair_corner_contacts(
    scene: &Scene,
    (t, dt): (f64, f64),
    q: &[f64],
    u: &[f64],
    pair: [Body; 2],
) -> Vec<LineContacts> {
    let dimension = scene.smallest_block_dimension();
    let delta = MARGIN * dimension;
    let body = |b| scene_box(scene, (t, q, Some(u)), b, dt, delta);
    let (a, b) = (body(pair[0]), body(pair[1]));
    let reach = a.margin + b.margin - 2.0 * delta;
    let mut buffers = PairBuffers::default();
    pair_candidates(
        &a,
        &b,
        (f64::INFINITY, reach),
        TIE * dimension,
        &mut buffers,
    );
    let mut lines = Vec::new();
    lines_of(&a, &b, &mut buffers, &mut lines);
    lines
}

/// The axis (0: x, 1: y) along which the bodies' centres spread most.
fn sweep_axis(bodies: &[Boxed]) -> usize {
    let spread = |k: usize| {
        let c = |b: &Boxed| 0.5 * (b.lo[k] + b.hi[k]);
        let lo = bodies.iter().map(c).fold(f64::INFINITY, f64::min);
        let hi = bodies.iter().map(c).fold(f64::NEG_INFINITY, f64::max);
        hi - lo
    };
    usize::from(spread(1) >= spread(0))
}

/// Whether `a` and `b` are joined by an interface that supports the upper one by more
/// than `margin` (then the interface's own gaps are all the contact needed); `supports`
/// holds each interface's support test.
fn firmly_supported(
    scene: &Scene,
    supports: &[Support],
    a: &Boxed,
    b: &Boxed,
    margin: f64,
) -> bool {
    let Some(k) = scene.interface_between(a.body, b.body) else {
        return false;
    };
    let (lower, upper) = if scene.arrangement().seats()[k].lower == b.body {
        (b, a)
    } else {
        (a, b)
    };
    scene
        .interface(k)
        .support_margin_given(supports[k], &lower.frame, &upper.frame)
        > margin
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenarios::{shaking_column, Shaking};

    /// The flush faces of two boxes: each face's world normal read from the frame is the
    /// face's own normal turned, and a block lying on its side on the base has its side
    /// faces flush with the base's top and bottom (a tilt within 0.999 counts).
    #[test]
    fn flush_sides_pair_the_faces_whose_normals_are_opposite() {
        let boxed_at = |x: f64, theta: f64, size: Size| Boxed {
            body: Body::Block(1),
            frame: Frame::of(&Pose::new(x, 0.0, theta)),
            size,
            lo: [0.0; 2],
            hi: [0.0; 2],
            margin: 0.0,
        };
        let base = boxed_at(0.0, 0.0, Size::new(1.0, 0.1));
        let lying = boxed_at(0.3, std::f64::consts::FRAC_PI_2 + 0.04, Size::new(0.2, 0.4));
        for side in Side::ALL {
            let turned = lying.frame.to_world(&side.face(lying.size).normal);
            let from_frame = [
                lying.frame.e2,
                -lying.frame.e2,
                lying.frame.e1,
                -lying.frame.e1,
            ];
            assert!(
                (turned - from_frame[side.index()]).norm() < 1e-15,
                "{side:?}"
            );
        }
        // Turned by π/2 + 0.04: e₁ points up, so its Left face (normal −e₁) faces the
        // base's Top.
        let flush = flush_sides(&lying, &base);
        assert_eq!(flush[Side::Left.index()], Some(Side::Top));
        assert_eq!(flush[Side::Right.index()], Some(Side::Bottom));
        assert_eq!(flush[Side::Top.index()], Some(Side::Right));
        let tilted = boxed_at(0.3, 0.1, Size::new(0.2, 0.4));
        assert_eq!(flush_sides(&tilted, &base), [None; 4]);
    }

    /// A block lying on the base, turned a quarter turn, its face Left (normal −e₁)
    /// down on the base's top and overhanging the base's right end: the base's top
    /// right corner touches the block's face Left, and its contact lies on the line of
    /// the base's face Top, which is flush with it, with the block's corner on that
    /// face.
    #[test]
    fn a_corner_on_a_face_flush_with_its_own_lies_on_that_line() {
        let scene = shaking_column(&Shaking {
            blocks: 1,
            ..Shaking::default()
        })
        .unwrap();
        let base = scene.base().state(0.0).pose;
        let (base_size, block) = (scene.size(0), scene.size(1));
        let q = vec![
            base.x + 0.5 * base_size.width,
            base.y + 0.5 * base_size.height + 0.5 * block.width,
            std::f64::consts::FRAC_PI_2,
        ];
        let u = vec![0.0; 3];
        let pair = [Body::Base, Body::Block(1)];
        let lines = pair_corner_contacts(&scene, (0.0, 1e-3), &q, &u, pair);
        let top: Vec<_> = lines
            .iter()
            .filter(|l| l.line.kind == LineKind::Face(Side::Top))
            .flat_map(|l| l.contacts.iter().flatten())
            .collect();
        let on_block_left = |c: &&CornerContact| {
            c.corner_body == Body::Base && c.face_body == Body::Block(1) && c.face == Side::Left
        };
        assert!(top.iter().any(on_block_left), "{lines:?}");
        assert!(
            top.iter().any(|c| c.corner_body == Body::Block(1)),
            "{lines:?}"
        );
    }

    #[test]
    fn a_standing_column_needs_no_corner_contacts() {
        let scene = shaking_column(&Shaking {
            blocks: 6,
            ..Shaking::default()
        })
        .unwrap();
        let q = scene.initial_coordinates();
        let u = vec![0.0; q.len()];
        assert!(corner_contacts(&scene, 0.0, &q, &u, 1e-3).is_empty());
    }

    /// A column of two blocks with block 2 (seated on block 1) moved down onto the base
    /// beside block 1, its left face 1e-4 from block 1's right face: the scene, q and u.
    fn block_beside_another() -> (Scene, Vec<f64>, Vec<f64>) {
        let scene = shaking_column(&Shaking {
            blocks: 2,
            ..Shaking::default()
        })
        .unwrap();
        let mut q = scene.initial_coordinates();
        let u = vec![0.0; q.len()];
        let (w1, w2) = (scene.size(1).width, scene.size(2).width);
        q[3] = q[0] + 0.5 * (w1 + w2) + 1e-4;
        q[4] = q[1];
        (scene, q, u)
    }

    #[test]
    fn a_block_beside_another_is_found_and_a_far_one_is_not() {
        let (scene, mut q, u) = block_beside_another();
        let found = corner_contacts(&scene, 0.0, &q, &u, 1e-3);
        // One line along block 1's right face, with one contact at each end (the flush
        // faces' four corners are two contact points).
        let beside: Vec<_> = found
            .iter()
            .filter(|l| l.line.lo == Body::Block(1) && l.line.hi == Body::Block(2))
            .collect();
        assert_eq!(beside.len(), 1, "{found:?}");
        assert_eq!(beside[0].line.kind, LineKind::Face(Side::Right));
        assert!(beside[0].contacts.iter().all(Option::is_some));
        q[3] += 1.0;
        let found = corner_contacts(&scene, 0.0, &q, &u, 1e-3);
        assert!(found
            .iter()
            .all(|l| l.line.lo != Body::Block(2) && l.line.hi != Body::Block(2)));
    }

    #[test]
    fn neighbours_only_leaves_out_the_bodies_no_interface_joins() {
        let (scene, q, u) = block_beside_another();
        let pair = |found: &[LineContacts], lo: Body| {
            found
                .iter()
                .any(|l| l.line.lo == lo && l.line.hi == Body::Block(2))
        };
        let found = corner_contacts(&scene, 0.0, &q, &u, 1e-3);
        assert!(
            pair(&found, Body::Base) && pair(&found, Body::Block(1)),
            "{found:?}"
        );
        let scene = scene.with_neighbours_only(true);
        let found = corner_contacts(&scene, 0.0, &q, &u, 1e-3);
        assert!(!pair(&found, Body::Base), "{found:?}");
        assert!(pair(&found, Body::Block(1)), "{found:?}");
    }
}
