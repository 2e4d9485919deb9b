//! The arrangement of a scene: which bodies each block rests on (its contact graph),
//! found once from the initial poses.
//!
//! The thesis's stack is one column, whose interface k joins body k−1 (the base for
//! k = 1) and block k (App. G). Blocks placed anywhere (two posts and a lintel, blocks
//! side by side, a statue on a plinth) rest on other bodies: block i rests on body B (the
//! base or another block) when, at t = 0,
//! - the interface B/i of App. G supports i ([`crate::interface::Support::Supported`]: the
//!   faces face each other, e₂ᴮ·e₂ⁱ > 0, i's centre is above the line of B's top face,
//!   and i's bottom face overlaps B's top face along e₁ over a positive length), and
//! - the smaller of the interface's two gaps is at most [`REST_TOL`] times i's height
//!   (i's bottom face lies on B's top face, or a corner of one on the other's face: the
//!   overlap check of the scene has refused deeper penetrations already).
//!
//! A block turned by more than 60° from the body beneath and resting on a corner has its
//! interface, as in a column: while the faces are turned that far, the corner contacts
//! hold the contact in its place ([`crate::interface::InterfaceContacts::holds`]).
//!
//! Each such (lower body, upper block) pair is one interface ([`Seat`]) with its two
//! normal gaps and its friction law (App. H). They are numbered by upper block, then by
//! lower body (base first, then blocks in their order), so that a column has exactly the
//! thesis's numbering: interface k joins body k−1 and block k. A block that rests on
//! nothing (given a height in the air) has no interface and falls; a lintel across two
//! posts has two. Bodies that touch otherwise (side by side, or after a block falls) meet
//! through the corner contacts of [`crate::pairs`].

use crate::coordinates::{BodyState, Frame, Pose, Twist};
use crate::interface::{Interface, Support};
use crate::overlap::Body;
use crate::scene::Scene;
use std::fmt;

/// How close (times the upper block's height) the bottom face of a block must be to a
/// lower body's top face to rest on it: far above the round-off of blocks placed on each
/// other (10⁻¹⁶ of their heights), far below any gap a user means.
pub const REST_TOL: f64 = 1e-9;

/// One interface of the scene: block `upper` (1-based) resting on body `lower` (the
/// base or another block).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct Seat {
    /// The body beneath: [`Body::Base`] or a block.
    pub lower: Body,
    /// The block resting on it, 1-based.
    pub upper: usize,
}

impl fmt::Display for Seat {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.lower, Body::Block(self.upper))
    }
}

/// The interfaces of a scene ([`Seat`]s in the order of the module docs) with, for each
/// block, where its own start (so that the interface of two bodies is found without a
/// search through all of them).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Arrangement {
    seats: Vec<Seat>,
    /// `first[i]..first[i + 1]`: the seats of block i + 1 (0-based i).
    first: Vec<usize>,
}

impl Arrangement {
    /// The arrangement of `scene`'s initial poses (module docs).
    #[must_use]
    pub fn of(scene: &Scene) -> Self {
        Self::among(scene, |states, radius, slack| {
            near_bodies(states, radius, slack)
        })
    }

    /// The arrangement with the bodies each block may rest on listed by `near` (from the
    /// bodies' states, circumscribed radii and the largest rest tolerance: at least
    /// every body whose circle comes within it, in increasing order).
    fn among(
        scene: &Scene,
        near: impl FnOnce(&[BodyState], &[f64], f64) -> Vec<Vec<usize>>,
    ) -> Self {
        let n = scene.n_blocks();
        let q = scene.initial_coordinates();
        let still = Twist::new(0.0, 0.0, 0.0);
        // Body k: the base (k = 0) or block k, at rest in its initial pose.
        let states: Vec<BodyState> = std::iter::once(scene.base().state(0.0))
            .chain((0..n).map(|k| BodyState::new(Pose::from_slice(&q[3 * k..3 * k + 3]), still)))
            .collect();
        let radius: Vec<f64> = (0..=n)
            .map(|k| 0.5 * scene.size(k).width.hypot(scene.size(k).height))
            .collect();
        let tol = |k: usize| REST_TOL * scene.size(k).height;
        let slack = (1..=n).map(tol).fold(0.0, f64::max);
        let near = near(&states, &radius, slack);
        let mut seats = Vec::new();
        let mut first = Vec::with_capacity(n + 1);
        for upper in 1..=n {
            first.push(seats.len());
            let tol = tol(upper);
            for &lower in &near[upper] {
                // Bodies whose circumscribed circles are apart cannot touch.
                let apart = (states[upper].pose.r() - states[lower].pose.r()).norm();
                if apart > radius[lower] + radius[upper] + tol {
                    continue;
                }
                let interface = Interface::new(scene.size(lower), scene.size(upper));
                if rests_on(&interface, &states[lower], &states[upper], tol) {
                    let lower = if lower == 0 {
                        Body::Base
                    } else {
                        Body::Block(lower)
                    };
                    seats.push(Seat { lower, upper });
                }
            }
        }
        first.push(seats.len());
        Self { seats, first }
    }

    /// A column's arrangement: block k on body k − 1, for k = 1..=n.
    #[must_use]
    pub fn column(n: usize) -> Self {
        let seats = (1..=n)
            .map(|upper| Seat {
                lower: if upper == 1 {
                    Body::Base
                } else {
                    Body::Block(upper - 1)
                },
                upper,
            })
            .collect();
        Self {
            seats,
            first: (0..=n).collect(),
        }
    }

    /// The interfaces, in their numbering.
    #[must_use]
    pub fn seats(&self) -> &[Seat] {
        &self.seats
    }

    /// The interfaces on which block `upper` (1-based) rests.
    #[must_use]
    pub fn seats_of(&self, upper: usize) -> std::ops::Range<usize> {
        self.first[upper - 1]..self.first[upper]
    }

    /// The interface joining bodies `a` and `b` (in either order), if one rests on the
    /// other.
    #[must_use]
    pub fn between(&self, a: Body, b: Body) -> Option<usize> {
        let on = |upper: Body, lower: Body| match upper {
            Body::Block(i) if i >= 1 && i < self.first.len() => {
                self.seats_of(i).find(|&k| self.seats[k].lower == lower)
            }
            _ => None,
        };
        on(a, b).or_else(|| on(b, a))
    }
}

/// For each body, the other bodies (in increasing order) whose circumscribed circles
/// (centres at `states`, radii `radius`) may come within `slack` of its own: every pair
/// whose circles do, and others. A sweep along the axis on which the centres spread
/// most (a column: y), so that a column's blocks meet their neighbours only, O(n log n),
/// where every pair cost a 10 000-block scene about a second.
fn near_bodies(states: &[BodyState], radius: &[f64], slack: f64) -> Vec<Vec<usize>> {
    let centre = |k: usize| states[k].pose.r();
    let spread = |axis: usize| {
        let at = |k: usize| if axis == 0 { centre(k).x } else { centre(k).y };
        let (lo, hi) = (0..states.len()).fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), k| {
            (l.min(at(k)), h.max(at(k)))
        });
        hi - lo
    };
    let along_y = spread(1) >= spread(0);
    // (Along the sweep, across it.)
    let coordinates = |k: usize| {
        let c = centre(k);
        if along_y {
            (c.y, c.x)
        } else {
            (c.x, c.y)
        }
    };
    // Round-off must not drop a pair the exact test keeps: a relative margin far above
    // it. (The scene's poses are finite.)
    let grown = |r: f64| r * (1.0 + 1e-9);
    let reach = |i: usize, j: usize| grown(radius[i] + radius[j]) + 2.0 * slack;
    let largest = radius.iter().copied().fold(0.0, f64::max);
    let mut order: Vec<usize> = (0..states.len()).collect();
    order.sort_by(|&i, &j| {
        (coordinates(i).0 - radius[i]).total_cmp(&(coordinates(j).0 - radius[j]))
    });
    let mut near = vec![Vec::new(); states.len()];
    for (at, &i) in order.iter().enumerate() {
        let (along_i, across_i) = coordinates(i);
        for &j in &order[at + 1..] {
            let (along_j, across_j) = coordinates(j);
            // Sorted by the circles' lower ends along the sweep: a circle whose lower
            // end is this far beyond circle i's centre, and every later one, is out of
            // its reach (the largest radius bounds the margin's part).
            let beyond = along_j - radius[j] - along_i;
            if beyond > grown(radius[i]) + (grown(largest) - largest) + 2.0 * slack {
                break;
            }
            if (along_j - along_i).abs() <= reach(i, j)
                && (across_j - across_i).abs() <= reach(i, j)
            {
                near[i].push(j);
                near[j].push(i);
            }
        }
    }
    for list in &mut near {
        list.sort_unstable();
    }
    near
}

/// Whether `upper` rests on `lower` at these states: supported, the smaller gap within
/// `tol`.
fn rests_on(interface: &Interface, lower: &BodyState, upper: &BodyState, tol: f64) -> bool {
    let frames = (Frame::of(&lower.pose), Frame::of(&upper.pose));
    if interface.support_of(&frames.0, &frames.1) != Support::Supported {
        return false;
    }
    let c = interface.contacts(lower, upper);
    c.left.row.value.min(c.right.row.value) <= tol
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenarios::{shaking_column, Shaking};

    /// The sweep finds the arrangement that every pair of bodies gives.
    #[test]
    fn the_sweep_finds_what_every_pair_gives() {
        let mut scenes: Vec<Scene> = ["classical-column", "pile-at-rest", "drums-on-record"]
            .iter()
            .map(|name| {
                let path = format!(
                    "{}/../../examples/scenes/{name}.toml",
                    env!("CARGO_MANIFEST_DIR")
                );
                Scene::from_toml(&std::fs::read_to_string(path).unwrap()).unwrap()
            })
            .collect();
        scenes.push(shaking_column(&Shaking::tall_column(40, false)).unwrap());
        for scene in &scenes {
            let every = Arrangement::among(scene, |states, _, _| {
                (0..states.len())
                    .map(|k| (0..states.len()).filter(|&j| j != k).collect())
                    .collect()
            });
            assert!(!every.seats().is_empty());
            assert_eq!(Arrangement::of(scene), every);
        }
    }
}
