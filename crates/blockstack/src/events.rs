//! Failure events a user can see in a run: a block loses its support, a block tips past
//! its tipping angle, the stack's height drops by a block, a block reaches the floor.
//!
//! `failure_time` (§4.4, Figure 4.6) is only the first of these, the loss of support of
//! (G.2.4) corrected (ERRATA 23). A column can collapse without any block losing its
//! support on its neighbour in that sense (the Lire collapse on a floor topples block by
//! block, each still half on the one below), so each kind of event is reported with its
//! time, once per block, in the order they happen.
//!
//! **The failure of a run** ([`failure`]) is its first event of any kind: a block lost
//! its support, tipped past its tipping angle or reached the floor from above, or the
//! stack's height (its highest corner) dropped by a block. Each means the column no longer stands as it was
//! built; which came first is the failure's kind. In the Lire collapse on a floor no
//! block loses its support in the sense of (G.2.4) (the test compares positions along
//! the faces, and the blocks lie on the floor one beyond the other), the top block
//! reaches the floor at t = 5.53 and the column's highest corner falls by more than a
//! block only at t = 7.05, when block 3 has fallen too
//! (`a_collapse_on_a_floor_is_a_failure_with_its_kind`).
//!
//! Support is per interface ([`crate::arrangement`]): block i lost its support on body B
//! when the interface B/i no longer supports it. A block resting on one body (a column's)
//! has one such event at most; a lintel across two posts may lose its support on each.
//! Blocks side by side, or a block placed in the air, have no interface between them and
//! no such event. Where a block rests on more than one body, the event names the body
//! ([`FailureEvent::on`]). Tipping and touching the floor are per block; the height
//! drop is that of the highest point of any block.

use crate::coordinates::{same_bits, Pose};
use crate::overlap::Body;
use crate::scene::Scene;
use crate::stack::StackContacts;
use std::fmt;

/// What happened.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum EventKind {
    /// The block lost its support on the body beneath ((G.2.4) corrected, ERRATA 23).
    SupportLost,
    /// The block's tilt |θ| passed its tipping angle atan(w/h): resting on a flat
    /// horizontal face, its centre of mass is then beyond the corner it turns about.
    Tipped,
    /// The highest point of the column fell by more than the smallest block height
    /// below its initial height (not tied to one block).
    HeightDropped,
    /// The block touched the floor (its lowest corner within the opening tolerance of
    /// the floor), having started above it.
    TouchedFloor,
}

impl fmt::Display for EventKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::SupportLost => "lost its support",
            Self::Tipped => "tipped past its tipping angle",
            Self::HeightDropped => "the stack's height dropped by a block",
            Self::TouchedFloor => "touched the floor",
        })
    }
}

/// One failure event.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct FailureEvent {
    /// What happened.
    pub kind: EventKind,
    /// When: the end of the step at which it was first seen.
    pub t: f64,
    /// Which block (1-based, in the scene's order); None for
    /// [`EventKind::HeightDropped`].
    pub block: Option<usize>,
    /// For [`EventKind::SupportLost`] by a block that rests on more than one body (a
    /// lintel): the body it lost its support on. JSON: `"on": "block 1"` or
    /// `"on": "the base"`, absent otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub on: Option<Body>,
}

impl FailureEvent {
    /// What happened, with the bodies named by `label` (`block 3 (lintel) lost its
    /// support on block 1 (left post)`), without the time.
    #[must_use]
    pub fn what(&self, label: &dyn Fn(Body) -> String) -> String {
        let mut s = match self.block {
            Some(k) => format!("{} {}", label(Body::Block(k)), self.kind),
            None => self.kind.to_string(),
        };
        if let Some(on) = self.on {
            s = format!("{s} on {}", label(on));
        }
        s
    }
}

impl fmt::Display for FailureEvent {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "t = {:.4}: {}", self.t, self.what(&|b| b.to_string()))
    }
}

/// Watches the states of a run and records each event the first time it happens.
#[derive(Debug, Clone)]
pub struct EventWatch {
    tipping: Vec<f64>,
    initial_height: f64,
    drop: f64,
    floor_tol: f64,
    /// Per block and per kind ([`EventKind`] as index): already reported. Support is
    /// per interface: `support_seen`.
    seen: Vec<[bool; 4]>,
    /// Per interface: its upper block's loss of support on it already reported (or the
    /// interface did not support at the start).
    support_seen: Vec<bool>,
    /// Per interface: the body to name in its event (`None`: its block rests on this
    /// body only).
    named_lower: Vec<Option<Body>>,
    events: Vec<FailureEvent>,
    /// The block coordinates of the last state observed: a state at the same ones, to
    /// the bit, tilts, lowers and raises every block as that one did, so its events of
    /// those kinds are recorded already (at rest, every state after the first).
    observed_q: Vec<f64>,
}

impl EventWatch {
    /// A watch for runs of `scene` from its initial coordinates; `floor_tol` is the gap
    /// below which a corner touches the floor. Blocks already on the floor at the start
    /// are not reported as touching it.
    #[must_use]
    pub fn new(scene: &Scene, floor_tol: f64) -> Self {
        let q0 = scene.initial_coordinates();
        let n = scene.n_blocks();
        // Body k + 1 is block k (body 0 is the base).
        let sizes: Vec<_> = (1..=n).map(|k| scene.size(k)).collect();
        let drop = sizes.iter().map(|s| s.height).fold(f64::INFINITY, f64::min);
        let mut watch = Self {
            tipping: sizes.iter().map(|s| s.width.atan2(s.height)).collect(),
            initial_height: top(scene, &q0),
            drop,
            floor_tol,
            seen: vec![[false; 4]; n],
            support_seen: Vec::new(),
            named_lower: Vec::new(),
            events: Vec::new(),
            observed_q: Vec::new(),
        };
        let arrangement = scene.arrangement();
        watch.named_lower = arrangement
            .seats()
            .iter()
            .map(|s| (arrangement.seats_of(s.upper).len() > 1).then_some(s.lower))
            .collect();
        for k in 0..n {
            watch.seen[k][EventKind::TouchedFloor as usize] =
                floor_gap(scene, &q0, k).is_some_and(|g| g <= floor_tol);
        }
        let contacts = scene.contacts(0.0, &q0, &scene.initial_velocities());
        watch.support_seen = contacts
            .interfaces
            .iter()
            .map(|i| !i.is_supported())
            .collect();
        watch
    }

    /// Records the events of the state at `t` with coordinates `q` and the contacts
    /// evaluated there.
    pub fn observe(&mut self, scene: &Scene, t: f64, q: &[f64], contacts: &StackContacts) {
        let seats = scene.arrangement().seats();
        for (k, interface) in contacts.interfaces.iter().enumerate() {
            if !interface.is_supported() && !self.support_seen[k] {
                self.support_seen[k] = true;
                self.events.push(FailureEvent {
                    kind: EventKind::SupportLost,
                    t,
                    block: Some(seats[k].upper),
                    on: self.named_lower[k],
                });
            }
        }
        if same_bits(q, &self.observed_q) {
            return;
        }
        self.observed_q.clear();
        self.observed_q.extend_from_slice(q);
        // The highest corner of any block ([`top`]), gathered in the loop: each block's
        // sin θ and cos θ serve its tilt, its lowest corner and its highest.
        let mut top = f64::NEG_INFINITY;
        for (k, block) in scene.blocks().iter().enumerate() {
            let pose = Pose::from_slice(&q[3 * k..]);
            let (sin, cos) = (pose.theta.sin(), pose.theta.cos());
            // The tilt from the nearest upright or lying orientation would hide a block
            // that turned over; the tilt from upright is what tipping means here.
            let tilt = sin.atan2(cos).abs();
            if tilt > self.tipping[k] {
                self.record(Some(k), EventKind::Tipped, t);
            }
            let half = block.half_vertical_extent_turned(sin, cos);
            if floor_gap_of(scene, pose.y, half).is_some_and(|g| g <= self.floor_tol) {
                self.record(Some(k), EventKind::TouchedFloor, t);
            }
            top = top.max(pose.y + half);
        }
        if top < self.initial_height - self.drop {
            self.record(None, EventKind::HeightDropped, t);
        }
    }

    /// Records `kind` for block k (0-based; None: the column), unless already recorded.
    /// A column event is kept in block 0's row of `seen`.
    fn record(&mut self, k: Option<usize>, kind: EventKind, t: f64) {
        let seen = &mut self.seen[k.unwrap_or(0)][kind as usize];
        if !*seen {
            *seen = true;
            self.events.push(FailureEvent {
                kind,
                t,
                block: k.map(|k| k + 1),
                on: None,
            });
        }
    }

    /// The events so far, in the order they were seen.
    #[must_use]
    pub fn events(&self) -> &[FailureEvent] {
        &self.events
    }

    /// The time of the first event of `kind`, if any.
    #[must_use]
    pub fn first_time(&self, kind: EventKind) -> Option<f64> {
        self.events.iter().find(|e| e.kind == kind).map(|e| e.t)
    }

    /// The events, moved out.
    #[must_use]
    pub fn into_events(self) -> Vec<FailureEvent> {
        self.events
    }
}

/// The failure of a run with these events (in the order they happened): the first of
/// them, whatever its kind; `None` while the column stands.
#[must_use]
pub fn failure(events: &[FailureEvent]) -> Option<FailureEvent> {
    events.first().copied()
}

/// The one line that says whether a run's column failed: `verdict: failed at t = …
/// (block k …)`, `verdict: standing at t = …` (no failure by the end), or, for a run
/// that stopped on an error before failing, `verdict: undecided` with the time reached.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Verdict {
    failure: Option<FailureEvent>,
    t_final: f64,
    stopped_early: bool,
}

impl Verdict {
    /// The verdict of a run with this `failure` ([`failure`]) that reached `t_final`,
    /// `stopped_early` when an error ended it.
    #[must_use]
    pub fn new(failure: Option<FailureEvent>, t_final: f64, stopped_early: bool) -> Self {
        Self {
            failure,
            t_final,
            stopped_early,
        }
    }
}

impl Verdict {
    /// The verdict line with the bodies named by `label` ([`FailureEvent::what`]).
    #[must_use]
    pub fn line(&self, label: &dyn Fn(Body) -> String) -> String {
        match self.failure {
            Some(e) => format!("verdict: failed, t = {:.4}: {}", e.t, e.what(label)),
            None => self.to_string(),
        }
    }
}

impl fmt::Display for Verdict {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (self.failure, self.stopped_early) {
            (Some(e), _) => write!(f, "verdict: failed, {e}"),
            (None, false) => write!(
                f,
                "verdict: standing at t = {:.4} (no block lost its support, tipped or reached the floor; the stack's height held)",
                self.t_final
            ),
            (None, true) => write!(
                f,
                "verdict: undecided, the run stopped at t = {:.4} before failing or reaching its end",
                self.t_final
            ),
        }
    }
}

/// The highest corner of any block: its centre plus its half vertical extent.
fn top(scene: &Scene, q: &[f64]) -> f64 {
    scene
        .blocks()
        .iter()
        .enumerate()
        .map(|(k, b)| q[3 * k + 1] + b.half_vertical_extent(q[3 * k + 2]))
        .fold(f64::NEG_INFINITY, f64::max)
}

/// The height of block k's lowest corner above the floor, None without a floor.
fn floor_gap(scene: &Scene, q: &[f64], k: usize) -> Option<f64> {
    let half = scene.blocks()[k].half_vertical_extent(q[3 * k + 2]);
    floor_gap_of(scene, q[3 * k + 1], half)
}

/// [`floor_gap`] of a block at height y with half vertical extent `half`
/// ([`crate::block::Block::half_vertical_extent`]).
fn floor_gap_of(scene: &Scene, y: f64, half: f64) -> Option<f64> {
    let floor = scene.floor()?;
    let lowest = y - half;
    Some(lowest - floor.y)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenarios::{lire, Perturbation};

    #[test]
    fn tipping_angles_and_the_drop_are_the_blocks_not_the_base() {
        use crate::scenarios::{shaking_column, Shaking};
        // Base 1 × 0.1, blocks 0.2 × 0.4.
        let p = Shaking {
            blocks: 2,
            amplitude: 0.2,
            omega: 4.0,
            periods: 1.0,
            steps_per_period: 100.0,
            mu: 0.2,
            start_with_base: false,
        };
        let watch = EventWatch::new(&shaking_column(&p).unwrap(), 1e-9);
        for angle in &watch.tipping {
            assert!(
                (angle - 0.5_f64.atan()).abs() < 1e-15,
                "{:?}",
                watch.tipping
            );
        }
        assert_eq!(watch.drop, 0.4);
    }

    #[test]
    fn a_standing_column_has_no_events() {
        let scene = lire(4, Perturbation::None).unwrap();
        let q = scene.initial_coordinates();
        let mut watch = EventWatch::new(&scene, 1e-9);
        let contacts = scene.contacts(0.0, &q, &vec![0.0; q.len()]);
        watch.observe(&scene, 0.0, &q, &contacts);
        assert!(watch.events().is_empty());
    }

    #[test]
    fn a_turned_and_lowered_block_is_reported_once() {
        let scene = lire(4, Perturbation::None).unwrap();
        let q0 = scene.initial_coordinates();
        let mut watch = EventWatch::new(&scene, 1e-9);
        // The whole tower lowered by five block heights, its top block turned on its side.
        let mut q = q0.clone();
        for k in 0..4 {
            q[3 * k + 1] -= 1.0;
        }
        q[9 + 2] = std::f64::consts::FRAC_PI_2;
        let contacts = scene.contacts(0.5, &q, &vec![0.0; q.len()]);
        watch.observe(&scene, 0.5, &q, &contacts);
        watch.observe(&scene, 0.6, &q, &contacts);
        let kinds: Vec<_> = watch.events().iter().map(|e| (e.kind, e.block)).collect();
        assert!(kinds.contains(&(EventKind::Tipped, Some(4))));
        assert!(kinds.contains(&(EventKind::HeightDropped, None)));
        assert_eq!(
            kinds.iter().filter(|k| k.0 == EventKind::Tipped).count(),
            1,
            "{kinds:?}"
        );
    }
}
