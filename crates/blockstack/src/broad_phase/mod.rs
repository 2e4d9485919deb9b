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

use crate::coordinates::{same_pose, BodyState, Frame, Pose, Twist, Vec2};
use crate::corners::Corner;
use crate::gaps::Face;
use crate::interface::{holds_given, Size, Support};
use crate::overlap::{Body, Placed};
use crate::pairs::{body_index, ContactLine, CornerContact, LineContacts, LineKind, Side};
use crate::scene::Scene;

mod pair;
use pair::{lines_of, pair_candidates, PairBuffers};

/// The fixed part δ of the margin, as a fraction of the smallest block dimension.
/// Halved or doubled, it costs the 135-run matrix 4.7 % more linear solves (354 426 and
/// 354 300 against 338 488), the Lire collapse, its floor landing and kicked30 within two
/// solves (`scripts/reference_workload.py --repeat 1 --only
/// matrix,lire_collapse,lire_floor,kicked30` with builds of 0.025 and 0.1, at commit
/// 4fd3da9).
pub const MARGIN: f64 = 0.05;

/// Two faces face each other (flush) when their normals' dot product is below −FLUSH.
/// Measured as [`MARGIN`] (the same harness and commit): 0.99 took the matrix 335 794
/// linear solves (−0.8 %, within the chaos of its piles), 0.9999 349 236 (+3.2 %); the
/// other workloads the same counts. Kept, as no neighbour pays 5 %.
const FLUSH: f64 = 0.999;

/// Two faces whose distances from a corner differ by less than this fraction of the
/// smallest block dimension are a tie ([`Side::facing`]); so are two corners of a pair
/// that lie this close along a contact line (`pair::pair_candidates`), which then count
/// as one, the same one at every step. That second use pays on the reference workload:
/// the 135-run matrix took 338 488 linear solves against 359 510 when round-off decided
/// which of two coincident corners a line kept (−5.8 %;
/// `scripts/reference_workload.py --only matrix`).
pub const TIE: f64 = 1e-6;

/// One body as the broad phase sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Boxed {
    body: Body,
    /// The pose it is boxed at.
    pose: Pose,
    /// The state's frame: each body's sin θ, cos θ once for all its corners and faces.
    frame: Frame,
    /// Its corners, as [`Placed`] places them.
    corners: [Vec2; 4],
    size: Size,
    /// The half diagonal R.
    radius: f64,
    lo: [f64; 2],
    hi: [f64; 2],
    margin: f64,
}

impl Boxed {
    /// Whether `other` is this body boxed alike: the same pose, size and margin to the
    /// bit, so that every decision of the broad phase about it comes out the same.
    fn same(&self, other: &Self) -> bool {
        self.body == other.body
            && same_pose(&self.pose, &other.pose)
            && self.size == other.size
            && self.margin.to_bits() == other.margin.to_bits()
    }

    /// Its placing, for the overlap of two bodies ([`Placed::depth`]).
    fn placed(&self) -> Placed {
        Placed {
            frame: self.frame,
            corners: self.corners,
        }
    }
}

/// The body `body` at `state` boxed for a step of `dt` with the fixed margin `delta`;
/// its placing is that of `last` (no sin θ, cos θ) where `last` was boxed at the same
/// pose and size, and so is its radius where it has the same size.
fn boxed(
    body: Body,
    state: BodyState,
    size: Size,
    (dt, delta): (f64, f64),
    last: Option<&Boxed>,
) -> Boxed {
    let last = last.filter(|l| l.size == size);
    let radius = last.map_or_else(|| 0.5 * size.width.hypot(size.height), |l| l.radius);
    let speed = state.twist.v().norm() + state.twist.omega.abs() * radius;
    let margin = 2.0 * dt * speed + delta;
    if let Some(last) = last.filter(|l| same_pose(&l.pose, &state.pose)) {
        return Boxed {
            body,
            margin,
            ..*last
        };
    }
    let Placed { frame, corners } = Placed::of(&state.pose, size);
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for c in corners {
        lo = [lo[0].min(c.x), lo[1].min(c.y)];
        hi = [hi[0].max(c.x), hi[1].max(c.y)];
    }
    Boxed {
        body,
        pose: state.pose,
        frame,
        corners,
        size,
        radius,
        lo,
        hi,
        margin,
    }
}

/// The face of `b` that corner `c` of `a` meets and its signed distance from it
/// ([`Side::facing`], ties within `tie`).
fn corner_face(a: &Boxed, c: Corner, b: &Boxed, tie: f64) -> (Side, f64) {
    let p = a.frame.point(&c.body_offset(a.size.width, a.size.height));
    Side::facing(&p, &a.frame.r, &b.frame, b.size, tie)
}

/// Body `b` of the scene at time t (a block's pose from q, its velocity from u, or at
/// rest without u), boxed for a step of `dt` with the fixed margin `delta` (placed as
/// `last` where that was boxed at the same pose, [`boxed`]).
fn scene_box(
    scene: &Scene,
    (t, q, u): (f64, &[f64], Option<&[f64]>),
    b: Body,
    margin: (f64, f64),
    last: Option<&Boxed>,
) -> Boxed {
    match b {
        Body::Block(k) => {
            let twist = u.map_or_else(Twist::default, |u| Twist::from_slice(&u[3 * k - 3..3 * k]));
            let state = BodyState::new(Pose::from_slice(&q[3 * k - 3..3 * k]), twist);
            boxed(b, state, scene.size(k), margin, last)
        }
        Body::Base | Body::Floor => boxed(
            Body::Base,
            scene.base().state(t),
            scene.size(0),
            margin,
            last,
        ),
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
    /// The bodies as boxed at that state (the base, then the blocks).
    pub(crate) bodies: Vec<Boxed>,
}

impl Scan {
    /// How deep bodies `a` and `b` (the base or blocks) overlap at the scanned state
    /// ([`crate::overlap::penetration_depth`], from the scan's placings).
    ///
    /// # Panics
    /// For the floor, which the scan does not box.
    #[must_use]
    pub fn pair_depth(&self, a: Body, b: Body) -> f64 {
        let placed = |x: Body| self.bodies[body_index(x)].placed();
        placed(a).depth(&placed(b))
    }

    /// The scan's placing of body i (0: the base, then the blocks) where it boxed that
    /// body at `pose` (to the bit) with `size`.
    pub(crate) fn placed_at(&self, i: usize, pose: &Pose, size: Size) -> Option<Placed> {
        let body = self.bodies.get(i)?;
        (body.size == size && same_pose(&body.pose, pose)).then(|| body.placed())
    }
}

/// [`corner_contacts`] and [`Scene::interfaces_holding`] at (t, q, u) together
/// ([`BroadPhase::scan`], with nothing kept from an earlier scan).
///
/// # Panics
/// When q or u holds fewer than 3 entries per block.
#[must_use]
pub fn scan(scene: &Scene, t: f64, q: &[f64], u: &[f64], dt: f64) -> Scan {
    BroadPhase::default().scan(scene, t, q, u, dt)
}

/// The broad phase of a run: [`scan`] with what one scan keeps for the next. A pair of
/// bodies both boxed as at the last scan (the same poses, sizes and margins, to the bit:
/// `Boxed::same`) has the same corner contacts, copied instead of found again, and a
/// body at the same pose keeps its placing (no sin θ, cos θ). Where every body is boxed
/// as at the last scan, so are the support tests and the sweep: the last findings are
/// copied whole. So at rest a scan costs the boxing of the bodies: in a pile of six
/// blocks lying at rest, 17.6 k of a step's 90 k instructions were the scan, two thirds
/// of them the corners of its four pairs. Only inputs are compared, never results: a
/// scan finds what a fresh one would, to the bit. The inputs compared are the bodies',
/// not the scene's arrangement: one broad phase serves the states of one scene.
#[derive(Debug, Clone, Default)]
pub struct BroadPhase {
    /// The fixed margin δ the kept pairs were found with.
    delta: f64,
    /// The bodies as boxed at the last scan, and what it found.
    last: Vec<Boxed>,
    last_holds: Vec<bool>,
    last_lines: Vec<LineContacts>,
    /// The pairs whose corners the last scan that swept looked at, sorted.
    pairs: Vec<PairLines>,
    /// Their lines, each pair's at its range.
    pair_lines: Vec<LineContacts>,
    /// `pairs` and `pair_lines` of the sweep under way.
    next_pairs: Vec<PairLines>,
    next_lines: Vec<LineContacts>,
    /// The bodies in the order of the sweep.
    order: Vec<usize>,
    /// Each interface's support test.
    supports: Vec<Support>,
    buffers: PairBuffers,
    /// The lists of a scan whose step is taken, reused by the next
    /// ([`BroadPhase::recycle`]): a scan allocates nothing once they have grown.
    spare: Scan,
    /// The pairs whose corners were searched, not copied, over all scans.
    searched: usize,
}

/// The lines a scan found for one pair of bodies.
#[derive(Debug, Clone)]
struct PairLines {
    /// The pair's bodies (indices of [`Scan::bodies`]), in the order they were given to
    /// [`pair_candidates`], which orders what it finds.
    pair: [usize; 2],
    /// Where its lines are in their list.
    lines: std::ops::Range<usize>,
}

impl BroadPhase {
    /// [`corner_contacts`] and [`Scene::interfaces_holding`] at (t, q, u) together: both
    /// read every body's frame and every interface's support test, which are computed
    /// here once (apart, the two and the support margins turned each body three times and
    /// tested each interface twice: 1.7 % of the instructions of the Lire collapse's
    /// steps).
    ///
    /// # Panics
    /// When q or u holds fewer than 3 entries per block.
    pub fn scan(&mut self, scene: &Scene, t: f64, q: &[f64], u: &[f64], dt: f64) -> Scan {
        let delta = MARGIN * scene.smallest_block_dimension();
        if delta.to_bits() != self.delta.to_bits() {
            // Another scene's: nothing to keep.
            *self = Self {
                delta,
                ..Self::default()
            };
        }
        let mut found = std::mem::take(&mut self.spare);
        let Scan {
            lines,
            holds,
            bodies,
        } = &mut found;
        bodies.clear();
        bodies.extend(
            std::iter::once(Body::Base)
                .chain((1..=scene.n_blocks()).map(Body::Block))
                .enumerate()
                .map(|(i, b)| {
                    let last = self.last.get(i);
                    scene_box(scene, (t, q, Some(u)), b, (dt, delta), last)
                }),
        );
        holds.clear();
        lines.clear();
        let unchanged = bodies.len() == self.last.len()
            && bodies.iter().zip(&self.last).all(|(b, l)| b.same(l));
        if unchanged {
            holds.extend_from_slice(&self.last_holds);
            lines.extend_from_slice(&self.last_lines);
            return found;
        }
        // Interface k joins its lower body and its upper block (`bodies` holds the base,
        // then the blocks: body i is block i).
        let frames = |k: usize| {
            let seat = scene.arrangement().seats()[k];
            (
                &bodies[body_index(seat.lower)].frame,
                &bodies[seat.upper].frame,
            )
        };
        self.supports.clear();
        self.supports.extend((0..scene.n_interfaces()).map(|k| {
            let (lower, upper) = frames(k);
            scene.interface(k).support_of(lower, upper)
        }));
        holds.extend(self.supports.iter().enumerate().map(|(k, &s)| {
            let (lower, upper) = frames(k);
            holds_given(s, lower, upper)
        }));
        self.lines_near(scene, bodies, lines);
        self.last.clone_from(bodies);
        self.last_holds.clone_from(holds);
        self.last_lines.clone_from(lines);
        found
    }

    /// Gives back the lists of a scan whose step is taken, for the next scan to fill.
    pub fn recycle(&mut self, used: Scan) {
        self.spare = used;
    }

    /// The corner contacts among the boxed `bodies` (the base, then the blocks), with
    /// the support test of each interface done already, into `out`.
    fn lines_near(&mut self, scene: &Scene, bodies: &[Boxed], out: &mut Vec<LineContacts>) {
        let delta = self.delta;
        let axis = sweep_axis(bodies);
        self.order.clear();
        self.order.extend(0..bodies.len());
        self.order.sort_by(|&i, &j| {
            let (a, b) = (&bodies[i], &bodies[j]);
            (a.lo[axis] - a.margin).total_cmp(&(b.lo[axis] - b.margin))
        });
        self.next_pairs.clear();
        self.next_lines.clear();
        for (pos, &i) in self.order.iter().enumerate() {
            let a = &bodies[i];
            for &j in &self.order[pos + 1..] {
                let b = &bodies[j];
                if b.lo[axis] - b.margin > a.hi[axis] + a.margin {
                    break;
                }
                let other = 1 - axis;
                let m = a.margin + b.margin;
                if b.lo[other] > a.hi[other] + m || a.lo[other] > b.hi[other] + m {
                    continue;
                }
                if firmly_supported(scene, &self.supports, a, b, m)
                    || !may_touch(scene, a.body, b.body)
                {
                    continue;
                }
                let start = self.next_lines.len();
                if let Some(kept) = kept_lines(&self.last, &self.pairs, bodies, [i, j]) {
                    self.next_lines.extend_from_slice(&self.pair_lines[kept]);
                } else {
                    self.searched += 1;
                    let reach = (m, m - 2.0 * delta);
                    pair_candidates(a, b, reach, TIE * delta / MARGIN, &mut self.buffers);
                    lines_of(a, b, &mut self.buffers, &mut self.next_lines);
                }
                self.next_pairs.push(PairLines {
                    pair: [i, j],
                    lines: start..self.next_lines.len(),
                });
            }
        }
        out.extend_from_slice(&self.next_lines);
        out.sort_by_key(|l| l.line.key());
        std::mem::swap(&mut self.pairs, &mut self.next_pairs);
        std::mem::swap(&mut self.pair_lines, &mut self.next_lines);
        self.pairs.sort_unstable_by_key(|p| p.pair);
    }
}

/// The range in the last scan's lines of the lines of `pair` (bodies in the order given
/// to [`pair_candidates`]), where the last scan (boxes `last`, `pairs` sorted) looked at
/// that pair with both bodies boxed as in `bodies`.
fn kept_lines(
    last: &[Boxed],
    pairs: &[PairLines],
    bodies: &[Boxed],
    pair: [usize; 2],
) -> Option<std::ops::Range<usize>> {
    let unchanged = |k: usize| last.get(k).is_some_and(|l| l.same(&bodies[k]));
    if !(unchanged(pair[0]) && unchanged(pair[1])) {
        return None;
    }
    let at = pairs.binary_search_by_key(&pair, |p| p.pair).ok()?;
    Some(pairs[at].lines.clone())
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
    let body = |b| scene_box(scene, (t, q, None), b, (0.0, 0.0), None);
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
    let body = |b| scene_box(scene, (t, q, Some(u)), b, (dt, delta), None);
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

    /// A broad phase that keeps what it found finds what a fresh scan finds, to the bit,
    /// at a state it scanned before, at one where a block moved and back; at the same
    /// state again it copies every pair's corners instead of searching them.
    #[test]
    fn a_kept_scan_finds_what_a_fresh_one_finds_and_searches_only_what_moved() {
        let (scene, q, mut u) = block_beside_another();
        u[3] = 0.3;
        let mut moved = q.clone();
        moved[5] += 0.01;
        let mut broad = BroadPhase::default();
        for (state, anew) in [(&q, None), (&q, Some(0)), (&moved, None), (&q, None)] {
            let before = broad.searched;
            let kept = broad.scan(&scene, 0.0, state, &u, 1e-3);
            assert_eq!(kept, scan(&scene, 0.0, state, &u, 1e-3));
            assert!(!kept.lines.is_empty());
            if let Some(n) = anew {
                assert_eq!(broad.searched - before, n);
            }
            broad.recycle(kept);
        }
    }

    /// A scan's placings are those of the overlap measure: the depth of a pair and the
    /// deepest penetration read from them are those placed anew, to the bit; a pose it
    /// did not box has no placing.
    #[test]
    fn a_scans_placings_measure_the_overlap_to_the_bit() {
        use crate::overlap::{deepest_penetration, deepest_penetration_placed, penetration_depth};
        let (scene, mut q, u) = block_beside_another();
        q[5] = 0.3;
        q[3] -= 0.05;
        let found = scan(&scene, 0.0, &q, &u, 1e-3);
        let pose = |k: usize| Pose::from_slice(&q[3 * k - 3..]);
        let fresh = penetration_depth((&pose(1), scene.size(1)), (&pose(2), scene.size(2)));
        assert!(fresh > 0.0);
        assert_eq!(found.pair_depth(Body::Block(1), Body::Block(2)), fresh);
        let deepest =
            deepest_penetration_placed(&scene, 0.0, &q, |i, p, s| found.placed_at(i, p, s));
        assert_eq!(deepest, deepest_penetration(&scene, 0.0, &q));
        assert!(found.placed_at(2, &pose(2), scene.size(2)).is_some());
        let turned_back = Pose {
            theta: 0.0,
            ..pose(2)
        };
        assert!(found.placed_at(2, &turned_back, scene.size(2)).is_none());
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
