//! Overlap of two rectangles (separating-axis test): scenes whose blocks interpenetrate
//! at the start are rejected, and every run measures the deepest penetration between any
//! two bodies after each step ([`deepest_penetration`]).
//!
//! Every corner of every body meets every other body (crate::pairs), so what this
//! measures is how well the contacts are held: the solver's tolerance, or a defect.

use crate::coordinates::{Frame, Pose, Vec2};
use crate::corners::frame_corners;
use crate::interface::Size;
use crate::scene::Scene;
use std::fmt;

/// A body of a scene, as penetration reports name it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Body {
    /// The driven base (or the table of the Lire scenes).
    Base,
    /// A free block, 1-based from the bottom.
    Block(usize),
    /// The floor plane.
    Floor,
}

impl serde::Serialize for Body {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_str(self)
    }
}

impl fmt::Display for Body {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Base => f.write_str("the base"),
            Self::Block(k) => write!(f, "block {k}"),
            Self::Floor => f.write_str("the floor"),
        }
    }
}

/// The penetration of two bodies at one time.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Penetration {
    /// Penetration depth ([`penetration_depth`]; for the floor, how far the lowest
    /// corner lies below it). Negative: the bodies are apart by that distance.
    pub depth: f64,
    /// The first body of the pair.
    pub first: Body,
    /// The second body of the pair.
    pub second: Body,
}

impl fmt::Display for Penetration {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} and {} overlap by {:.3e}",
            self.first, self.second, self.depth
        )
    }
}

/// The deepest penetration among `bodies` (each with its pose and size), None for fewer
/// than two. Pairs whose bounding circles are apart are skipped after sorting the
/// bodies along the axis on which their centres spread most, so that a tall column or a
/// row of blocks on the floor costs O(n log n), not O(n²).
#[must_use]
pub fn deepest_among(bodies: &[(Body, Pose, Size)]) -> Option<Penetration> {
    deepest_in(&mut placed(bodies.iter().copied(), |_, _, _| None))
}

/// The bodies `bodies` yields, each placed once for all its pairs (a body near k others
/// was turned and its corners and radius computed k times), with the radius of its
/// bounding circle: one list a step, where a list of the bodies, their placings and
/// their order took five allocations. The i-th body's placing is the one `known` gives
/// for its pose and size where it gives one ([`deepest_penetration_placed`]).
fn placed(
    bodies: impl Iterator<Item = (Body, Pose, Size)>,
    known: impl Fn(usize, &Pose, Size) -> Option<Placed>,
) -> Vec<(Body, Placed, f64)> {
    bodies
        .enumerate()
        .map(|(i, (b, p, s))| {
            let placed = known(i, &p, s).unwrap_or_else(|| Placed::of(&p, s));
            (b, placed, 0.5 * s.width.hypot(s.height))
        })
        .collect()
}

/// [`deepest_among`] the bodies `placed` lists, which it sorts.
fn deepest_in(placed: &mut [(Body, Placed, f64)]) -> Option<Penetration> {
    // The centres r, the poses' (x, y).
    let spread = |f: fn(&Vec2) -> f64| {
        let (lo, hi) = placed
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), b| {
                (l.min(f(&b.1.frame.r)), h.max(f(&b.1.frame.r)))
            });
        hi - lo
    };
    let along: fn(&Vec2) -> f64 = if spread(|r| r.x) >= spread(|r| r.y) {
        |r| r.x
    } else {
        |r| r.y
    };
    // A stable sort: bodies level along the axis keep the order they were listed in.
    placed.sort_by(|a, b| along(&a.1.frame.r).total_cmp(&along(&b.1.frame.r)));
    let r_max = placed.iter().map(|p| p.2).fold(0.0, f64::max);
    let mut deepest: Option<Penetration> = None;
    for (a, (bi, placed_i, ri)) in placed.iter().enumerate() {
        let pi = placed_i.frame.r;
        for (bj, placed_j, rj) in &placed[a + 1..] {
            let pj = placed_j.frame.r;
            if along(&pj) - along(&pi) > ri + r_max {
                break;
            }
            let apart = (pi - pj).norm() >= ri + rj;
            let depth = if apart {
                // Apart by at least this much: a lower bound is enough to rank the pair.
                ri + rj - (pi - pj).norm()
            } else {
                placed_i.depth(placed_j)
            };
            if deepest.is_none_or(|d| depth > d.depth) {
                deepest = Some(Penetration {
                    depth,
                    first: *bi,
                    second: *bj,
                });
            }
        }
    }
    deepest
}

/// The bodies of `scene` at time `t` with block coordinates `q`: the base, then the
/// blocks bottom to top.
#[must_use]
pub fn scene_bodies(scene: &Scene, t: f64, q: &[f64]) -> Vec<(Body, Pose, Size)> {
    bodies_of(scene, t, q).collect()
}

/// [`scene_bodies`], one by one.
fn bodies_of<'a>(
    scene: &'a Scene,
    t: f64,
    q: &'a [f64],
) -> impl Iterator<Item = (Body, Pose, Size)> + 'a {
    let base = scene.base();
    let base = (
        Body::Base,
        base.state(t).pose,
        Size::new(base.width(), base.height()),
    );
    std::iter::once(base).chain((0..scene.n_blocks()).map(|k| {
        (
            Body::Block(k + 1),
            Pose::from_slice(&q[3 * k..]),
            scene.size(k + 1),
        )
    }))
}

/// The deepest penetration between any two bodies of `scene` (base, blocks and floor)
/// at time `t` with block coordinates `q`. Bodies that only touch give a depth of about
/// zero (the stack's own contacts close to the solver's tolerance).
///
/// # Panics
/// When q holds fewer than 3 coordinates per block.
#[must_use]
pub fn deepest_penetration(scene: &Scene, t: f64, q: &[f64]) -> Penetration {
    deepest_penetration_placed(scene, t, q, |_, _, _| None)
}

/// [`deepest_penetration`] with the placing of body i (0: the base, then the blocks)
/// taken from `known` where it has one for the body's pose and size: the broad phase's
/// of the same state ([`crate::broad_phase::Scan::placed_at`]), the same numbers as
/// [`Placed::of`] without a sin θ and cos θ per body.
pub(crate) fn deepest_penetration_placed(
    scene: &Scene,
    t: f64,
    q: &[f64],
    known: impl Fn(usize, &Pose, Size) -> Option<Placed>,
) -> Penetration {
    let mut placed = placed(bodies_of(scene, t, q), known);
    // The blocks below the floor, read in the blocks' order (the first of equal depths
    // is the one reported) before the bodies are sorted.
    let below = scene.floor().and_then(|floor| {
        let blocks = scene.blocks().iter().zip(&placed[1..]).enumerate();
        blocks.fold(None, |deepest: Option<Penetration>, (k, (block, body))| {
            // The block's lowest corner, with its sin θ and cos θ of the placing.
            let e1 = body.1.frame.e1;
            let lowest = q[3 * k + 1] - block.half_vertical_extent_turned(e1.y, e1.x);
            let depth = floor.y - lowest;
            if depth > deepest.map_or(f64::NEG_INFINITY, |d| d.depth) {
                Some(Penetration {
                    depth,
                    first: Body::Block(k + 1),
                    second: Body::Floor,
                })
            } else {
                deepest
            }
        })
    });
    let between = deepest_in(&mut placed).unwrap_or(Penetration {
        depth: f64::NEG_INFINITY,
        first: Body::Base,
        second: Body::Base,
    });
    // Between the bodies first: the floor where it is strictly deeper.
    match below {
        Some(floor) if floor.depth > between.depth => floor,
        _ => between,
    }
}

/// Penetration depth of two rectangles: the smallest distance one must move along a
/// face normal of either rectangle to separate them. Zero or negative means they are
/// separate or only touch (the value is then minus the largest separating distance).
#[must_use]
pub fn penetration_depth(a: (&Pose, Size), b: (&Pose, Size)) -> f64 {
    Placed::of(a.0, a.1).depth(&Placed::of(b.0, b.1))
}

/// A rectangle placed at a pose, with what the separating-axis test reads of it: its
/// centre and basis (the axes, [`Pose::e1`] and [`Pose::e2`]: the same numbers, see
/// [`Frame`]) and its corners, each computed once. The broad phase places its bodies
/// the same way (`crate::broad_phase`), so that the overlap of the pairs it lists reads
/// its placings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Placed {
    pub(crate) frame: Frame,
    pub(crate) corners: [Vec2; 4],
}

impl Placed {
    pub(crate) fn of(pose: &Pose, size: Size) -> Self {
        let frame = Frame::of(pose);
        Self {
            corners: frame_corners(&frame, size.width, size.height),
            frame,
        }
    }

    /// [`penetration_depth`] of this rectangle and `other`.
    pub(crate) fn depth(&self, other: &Self) -> f64 {
        let axes = [self.frame.e1, self.frame.e2, other.frame.e1, other.frame.e2];
        let mut depth = f64::INFINITY;
        for axis in &axes {
            let (amin, amax) = extent(&self.corners, axis);
            let (bmin, bmax) = extent(&other.corners, axis);
            // Overlap of the two projections along this axis (negative: a gap).
            let overlap = amax.min(bmax) - amin.max(bmin);
            depth = depth.min(overlap);
        }
        depth
    }
}

/// The range (least, greatest) of `points` projected on `axis`.
pub(crate) fn extent(points: &[Vec2; 4], axis: &Vec2) -> (f64, f64) {
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
    fn scene_bodies_have_their_own_sizes() {
        use crate::scenarios::{shaking_column, Shaking};
        let p = Shaking {
            blocks: 2,
            amplitude: 0.2,
            omega: 4.0,
            periods: 1.0,
            steps_per_period: 100.0,
            mu: 0.2,
            start_with_base: false,
        };
        let scene = shaking_column(&p).unwrap();
        let sizes: Vec<_> = scene_bodies(&scene, 0.0, &scene.initial_coordinates())
            .iter()
            .map(|b| (b.0, b.2.width, b.2.height))
            .collect();
        assert_eq!(
            sizes,
            [
                (Body::Base, 1.0, 0.1),
                (Body::Block(1), 0.2, 0.4),
                (Body::Block(2), 0.2, 0.4)
            ]
        );
        // A block pushed into the base by a quarter of its height is an overlap.
        let mut q = scene.initial_coordinates();
        q[1] -= 0.1;
        let deepest = deepest_among(&scene_bodies(&scene, 0.0, &q)).unwrap();
        assert!((deepest.depth - 0.1).abs() < 1e-12, "{deepest:?}");
        // The scene's own measure (no floor here) places the same bodies.
        assert_eq!(deepest_penetration(&scene, 0.0, &q), deepest);
    }

    /// The deepest penetration among bodies placed once each is the deepest of the
    /// pairs' own penetration depths, to the bit.
    /// Two equal blocks tilted alike, apart from each other and the base, sunk equally
    /// into the floor: the floor's penetration is reported, with the lower-numbered
    /// block, at the depth of the block's lowest corner (`Block::half_vertical_extent`).
    #[test]
    fn the_floor_reports_the_first_of_equally_sunken_blocks() {
        use crate::scenarios::{shaking_column, Shaking};
        let scene = shaking_column(&Shaking {
            blocks: 2,
            ..Shaking::default()
        })
        .unwrap();
        let floor = scene.floor().unwrap();
        let theta = 0.3;
        let block = &scene.blocks()[0];
        let y = floor.y - 0.01 + block.half_vertical_extent(theta);
        let q = [2.0, y, theta, 3.0, y, theta];
        let deepest = deepest_penetration(&scene, 0.0, &q);
        assert_eq!(deepest.first, Body::Block(1));
        assert_eq!(deepest.second, Body::Floor);
        let lowest = q[1] - block.half_vertical_extent(theta);
        assert_eq!(deepest.depth, floor.y - lowest);
    }

    #[test]
    fn the_deepest_among_bodies_is_the_deepest_pair() {
        let s = Size::new(1.0, 0.2);
        let bodies = [
            (Body::Base, Pose::new(0.0, 0.0, 0.0), Size::new(2.0, 0.1)),
            (Body::Block(1), Pose::new(0.1, 0.149, 0.01), s),
            (Body::Block(2), Pose::new(0.3, 0.35, -0.3), s),
            (Body::Block(3), Pose::new(-0.2, 0.5, 0.2), s),
        ];
        let deepest = deepest_among(&bodies).unwrap();
        let mut pairs = Vec::new();
        for (i, a) in bodies.iter().enumerate() {
            for b in &bodies[i + 1..] {
                pairs.push((penetration_depth((&a.1, a.2), (&b.1, b.2)), a.0, b.0));
            }
        }
        let best = pairs
            .iter()
            .fold(pairs[0], |m, p| if p.0 > m.0 { *p } else { m });
        assert_eq!(deepest.depth, best.0);
        let pair = [deepest.first, deepest.second];
        assert!(
            pair.contains(&best.1) && pair.contains(&best.2),
            "{deepest:?}"
        );
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
