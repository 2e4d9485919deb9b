//! The corner contacts of one pair of boxed bodies: each corner of either body against
//! the other's faces, within reach, grouped into the contact lines the block stack's
//! slots take ([`super::BroadPhase`] runs this for the pairs its sweep finds close).

use super::*;

/// The buffers of one pair's corner contacts, reused from pair to pair within a scan
/// (a pair's lists are short, but a fresh list per pair and line cost 5 % of the
/// instructions of a pile of six blocks at rest).
#[derive(Debug, Clone, Default)]
pub(super) struct PairBuffers {
    /// The pair's corner contacts ([`pair_candidates`]).
    found: Vec<Candidate>,
    /// [`flush_sides`] of the pair (a, b) given to [`pair_candidates`], then of (b, a).
    flush: [[Option<Side>; 4]; 2],
    /// Each with the line it lies on.
    lined: Vec<(ContactLine, Candidate)>,
    /// The contacts of one line.
    line: Vec<Candidate>,
    /// The distance within which [`pair_candidates`] took two values as tied.
    tie: f64,
}

/// The corner contacts of one pair (`buffers.found`) grouped into the lines they lie on
/// ([`ContactLine`]), appended to `out`. A line holds at most two contacts: where more
/// were found (two faces lying flush, each body's corners on the other's face), the two
/// at the ends of the line among those within the pair's margin of the closest are
/// kept, since a line contact in the plane has two independent contact forces and more
/// would make Newton's matrix singular.
pub(super) fn lines_of(
    a: &Boxed,
    b: &Boxed,
    buffers: &mut PairBuffers,
    out: &mut Vec<LineContacts>,
) {
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
        out.push(line_ends(
            l,
            line,
            (lo, hi),
            (a.margin + b.margin, buffers.tie),
        ));
    }
}

/// The world tangent of face `side` of `body`.
fn tangent(body: &Boxed, side: Side) -> Vec2 {
    body.frame.to_world(&side.face(body.size).tangent)
}

/// The contacts `list` found on `line` of the pair (`lo`, `hi`: its bodies in the
/// order of the line) cut to the two at its ends ([`lines_of`]); `near` is the pair's
/// margin, `tie` the distance within which two points count as one.
fn line_ends(
    line: ContactLine,
    list: &mut Vec<Candidate>,
    (lo, hi): (&Boxed, &Boxed),
    (near, tie): (f64, f64),
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
        let (first, last) = list
            .iter()
            .map(s)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
                (l.min(v), h.max(v))
            });
        // Where the two bodies' corners meet at an end of the line (flush faces ending
        // together), both describe one contact point: the least key picks one, where
        // round-off picked either from step to step (a drum lying on another, at rest,
        // lost its contact's force and the kept factors at every step).
        let at_end = |end: f64, other: Option<CornerContact>| {
            list.iter()
                .filter(|c| (s(c) - end).abs() <= tie && Some(c.contact) != other)
                .min_by_key(|c| c.contact.key())
                .copied()
        };
        let first = at_end(first, None).expect("the least point is a candidate's");
        let last = at_end(last, Some(first.contact)).unwrap_or_else(|| {
            *list
                .iter()
                .filter(|c| c.contact != first.contact)
                .max_by(|x, y| s(x).total_cmp(&s(y)))
                .expect("three candidates or more")
        });
        list.clear();
        list.extend([first, last]);
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
pub(super) fn pair_candidates(
    a: &Boxed,
    b: &Boxed,
    (m, reach): (f64, f64),
    tie: f64,
    buffers: &mut PairBuffers,
) {
    let PairBuffers {
        found,
        flush: flush_of,
        tie: tied,
        ..
    } = buffers;
    *tied = tie;
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Two blocks side by side, their facing sides flush and their corners meeting at
    /// both ends of the line: which body's corner stands for each end is the same
    /// whatever round-off does to the points (shifted by an ulp up or down, the order of
    /// the coincident corners flips), and each end keeps one contact.
    #[test]
    fn coincident_corners_at_a_lines_end_give_the_same_contacts_under_round_off() {
        let size = Size::new(0.2, 0.4);
        let at = |x: f64, y: f64| {
            let state = BodyState::new(Pose::new(x, y, 0.0), Twist::default());
            boxed(Body::Block(2), state, size, (0.0, 0.0), None)
        };
        let lines = |dy: f64| {
            let (a, mut b) = (at(0.0, 0.2), at(0.2, 0.2 + dy));
            b.body = Body::Block(3);
            let mut buffers = PairBuffers::default();
            pair_candidates(&a, &b, (0.01, 0.01), 1e-6, &mut buffers);
            let mut out = Vec::new();
            lines_of(&a, &b, &mut buffers, &mut out);
            out
        };
        let reference = lines(0.0);
        assert_eq!(reference.len(), 1, "{reference:?}");
        let ends = reference[0].contacts;
        assert!(
            ends.iter().all(Option::is_some) && ends[0] != ends[1],
            "{ends:?}"
        );
        for dy in [1e-16, -1e-16, 3e-16, -3e-16] {
            assert_eq!(lines(dy), reference, "shifted by {dy:e}");
        }
    }

    /// The flush faces of two boxes: each face's world normal read from the frame is the
    /// face's own normal turned, and a block lying on its side on the base has its side
    /// faces flush with the base's top and bottom (a tilt within 0.999 counts).
    #[test]
    fn flush_sides_pair_the_faces_whose_normals_are_opposite() {
        let boxed_at = |x: f64, theta: f64, size: Size| {
            let state = BodyState::new(Pose::new(x, 0.0, theta), Twist::default());
            boxed(Body::Block(1), state, size, (0.0, 0.0), None)
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
}
