//! One step of a scene with its corner contacts ([`crate::pairs`]) kept current.
//!
//! Before the step, the broad phase ([`crate::broad_phase`]) lists the corner contacts
//! that may close within it; the system puts them into its contact slots
//! ([`StackSystem::assign_corner_contacts`]), and the stepper follows: it re-reads the
//! layout when the slots grew ([`nsga::Stepper::extend_layout`]) and forgets the forces
//! of slots given to another contact ([`nsga::Stepper::forget_contacts`]). Within the
//! step the system's size is fixed, so Newton, its index sets, the warm start x of the
//! last step and the branch bookkeeping see an ordinary system.
//!
//! After the step, the broad phase runs again at the new state (its list serves the next
//! step). A contact it finds *penetrating* that was not in the slots during the step was
//! missed (a body sped up within the step by more than the margin allowed): the step is
//! taken again from the saved state with that contact added. So a fast block cannot
//! tunnel into another unseen; [`CornerStepping::redone_steps`] counts how often it
//! happened.

use crate::broad_phase::{pair_corner_contacts, BroadPhase, Scan};
use crate::coordinates::{same_pose, Pose};
use crate::interface::Size;
use crate::overlap::{penetration_depth, Body};
use crate::pairs::LineContacts;
use crate::scene::Scene;
use crate::system::StackSystem;
use nsga::{StepError, Stepper};

/// How often a step whose bodies still enter each other after the missed contacts were
/// added is split in two (down to Δt/2^MAX_CONTACT_SPLITS), listing the contacts again
/// between the halves. Measured on the `abundance` scene (the base swings blocks at up
/// to five length units per time unit, Δt = 0.022): with no split, blocks 2 and 5 sank
/// into each other by a whole block width at t = 3.4 (`rollstack blocks run abundance`).
pub const MAX_CONTACT_SPLITS: usize = 4;

/// The bookkeeping of the corner contacts over a run.
#[derive(Debug, Clone, Default)]
pub struct CornerStepping {
    /// The broad phase's findings at the current state (step number, findings).
    wanted: Option<(u64, Scan)>,
    /// The broad phase, with what it keeps from one state's scan for the next's.
    broad: BroadPhase,
    /// Steps taken again because a contact was missed.
    pub redone_steps: usize,
    /// Steps (or substeps) split in two because the bodies still entered each other
    /// after the missed contacts were added ([`MAX_CONTACT_SPLITS`]).
    pub split_steps: usize,
    /// The most corner contacts in the slots at once.
    pub most_contacts: usize,
    /// The state before the step being taken, kept to undo it: a buffer reused from
    /// step to step (`State::clone_from`), not a new copy per step.
    before: nsga::State,
}

impl CornerStepping {
    /// A stepper of `scene` from its initial state at t = 0 with `options`, and the
    /// corner bookkeeping that steps it as a run does ([`CornerStepping::step`]; the
    /// commands, [`crate::simulate`]).
    ///
    /// # Errors
    /// As [`Stepper::new`].
    pub fn start_scene(
        scene: &Scene,
        options: nsga::Options,
    ) -> Result<(Self, Stepper<StackSystem>), StepError> {
        let (q0, u0) = (scene.initial_coordinates(), scene.initial_velocities());
        let mut system = StackSystem::new(scene.clone());
        let mut corners = Self::default();
        corners.start(&mut system, &q0, &u0, options.dt);
        let stepper = Stepper::new(system, 0.0, &q0, &u0, options)?;
        Ok((corners, stepper))
    }

    /// The corner contacts of the initial state (t = 0, q0, u0) put into a system before
    /// its stepper is built; the list also serves the first step.
    pub fn start(&mut self, system: &mut StackSystem, q0: &[f64], u0: &[f64], dt: f64) {
        let found = self.broad.scan(system.scene(), 0.0, q0, u0, dt);
        system.assign_corner_contacts(&found.lines);
        // The first decision: no forces to forget yet.
        let _ = system.hold_interfaces(found.holds.clone());
        self.most_contacts = self.most_contacts.max(count(&found.lines));
        self.wanted = Some((0, found));
    }

    /// The bookkeeping for a branch that continues from another state of this run (an
    /// exploration's fork): the counters carry over, the broad phase's list (which
    /// belongs to this run's state) does not.
    #[must_use]
    pub fn for_branch(&self) -> Self {
        Self {
            wanted: None,
            before: nsga::State::default(),
            ..self.clone()
        }
    }

    /// Puts `wanted` into the system's slots and tells the stepper what changed.
    ///
    /// # Errors
    /// Only if the stepper refuses the grown layout (a bug).
    pub fn assign(
        &mut self,
        stepper: &mut Stepper<StackSystem>,
        wanted: &[LineContacts],
    ) -> Result<(), StepError> {
        self.most_contacts = self.most_contacts.max(count(wanted));
        // The stepper forgets what it keeps from the last step whenever the system is
        // borrowed mutably (`Stepper::system_mut`): borrow it only for a change.
        if stepper.system().holds_corner_contacts(wanted) {
            return Ok(());
        }
        let change = stepper.system_mut().assign_corner_contacts(wanted);
        if change.grown {
            stepper.extend_layout()?;
        }
        if !change.normals.is_empty() || !change.laws.is_empty() {
            stepper.forget_contacts(&change.normals, &change.laws)?;
        }
        Ok(())
    }

    /// Puts the decision `holds`, made at the stepper's current state, of which interfaces
    /// hold their contact with their own gaps into the system for the step about to be
    /// taken ([`StackSystem::hold_interfaces`]).
    ///
    /// # Errors
    /// Only if the stepper refuses to forget the flipped interfaces' forces (a bug).
    fn hold_interfaces(
        stepper: &mut Stepper<StackSystem>,
        holds: &[bool],
    ) -> Result<(), StepError> {
        // Borrowed mutably only for a change, as in `assign`.
        if stepper.system().holds_interfaces(holds) {
            return Ok(());
        }
        let change = stepper.system_mut().hold_interfaces(holds.to_vec());
        if change.normals.is_empty() {
            return Ok(());
        }
        stepper.forget_contacts(&change.normals, &change.laws)
    }

    /// The broad phase's findings at the stepper's current state (computed once per
    /// state: after a step, to look for missed contacts, and before the next).
    fn wanted(&mut self, scene: &Scene, stepper: &Stepper<StackSystem>) -> &Scan {
        let st = stepper.state();
        if self.wanted.as_ref().is_some_and(|(k, _)| *k != st.k) {
            self.wanted = None;
        }
        let dt = stepper.options().dt;
        &self
            .wanted
            .get_or_insert_with(|| (st.k, self.broad.scan(scene, st.t, &st.q, &st.u, dt)))
            .1
    }

    /// The broad phase's findings at the state of step number `k`, if they are kept.
    pub(crate) fn found_at(&self, k: u64) -> Option<&Scan> {
        self.wanted
            .as_ref()
            .filter(|(at, _)| *at == k)
            .map(|(_, found)| found)
    }

    /// [`CornerStepping::wanted`] taken out of the bookkeeping, for the step from this
    /// state: the findings at the state after it replace them.
    fn take_wanted(&mut self, scene: &Scene, stepper: &Stepper<StackSystem>) -> Scan {
        self.wanted(scene, stepper);
        let (_, found) = self.wanted.take().expect("`wanted` just kept the findings");
        found
    }

    /// One step of [`nsga::Stepper::step`] with the corner contacts kept current (see the
    /// module docs); `tol` is the penetration that counts as a missed contact.
    ///
    /// # Errors
    /// As [`nsga::Stepper::step`].
    pub fn step(
        &mut self,
        scene: &Scene,
        stepper: &mut Stepper<StackSystem>,
        tol: f64,
    ) -> Result<(), StepError> {
        if stepper.at_rest() {
            // The state is repeated (nsga's `Stepper::at_rest`): the bodies stay where
            // the broad phase and the missed-contact check last found them.
            stepper.step()?;
            return Ok(());
        }
        self.step_within(scene, stepper, tol, MAX_CONTACT_SPLITS)
    }

    /// [`CornerStepping::step`] that may still split the step `splits` times.
    fn step_within(
        &mut self,
        scene: &Scene,
        stepper: &mut Stepper<StackSystem>,
        tol: f64,
        splits: usize,
    ) -> Result<(), StepError> {
        let found = self.take_wanted(scene, stepper);
        self.assign(stepper, &found.lines)?;
        Self::hold_interfaces(stepper, &found.holds)?;
        let mut before = std::mem::take(&mut self.before);
        before.clone_from(stepper.state());
        stepper.step()?;
        let missed = self.penetrating(scene, stepper, &before, tol);
        if missed.is_empty() {
            self.before = before;
            self.broad.recycle(found);
            return Ok(());
        }
        self.redone_steps += 1;
        // The missed pairs' contacts with the faces they meet *before* the step (after
        // it, a corner may already be past the face it should have struck).
        let mut union: Vec<LineContacts> = found
            .lines
            .into_iter()
            .filter(|w| !missed.contains(&[w.line.lo, w.line.hi]))
            .collect();
        for &pair in &missed {
            union.extend(pair_corner_contacts(
                scene,
                (before.t, stepper.options().dt),
                &before.q,
                &before.u,
                pair,
            ));
        }
        stepper.set_state(before);
        union.sort_by_key(|l| l.line.key());
        self.assign(stepper, &union)?;
        // The state the step starts from, sized to the contacts it has now.
        let before = stepper.state().clone();
        self.wanted = None;
        stepper.step()?;
        if splits == 0 || self.penetrating(scene, stepper, &before, tol).is_empty() {
            return Ok(());
        }
        // Still entering each other: within one step the bodies moved or turned so far
        // that the contacts listed at its start no longer describe their meeting (a
        // corner slid past the end of the face it was paired with). Halves of the step
        // list the contacts again between them.
        self.split_steps += 1;
        stepper.set_state(before);
        self.wanted = None;
        let split = stepper.split_step(2, |s| self.step_within(scene, s, tol, splits - 1));
        // The substeps' lists were keyed by their own step numbers.
        self.wanted = None;
        split.map(|_| ())
    }

    /// The pairs of bodies that the broad phase lists at the stepper's state and that
    /// overlap by more than `tol` and by more than `tol` deeper than at `before`.
    fn penetrating(
        &mut self,
        scene: &Scene,
        stepper: &Stepper<StackSystem>,
        before: &nsga::State,
        tol: f64,
    ) -> Vec<[Body; 2]> {
        let st = stepper.state();
        // A body where it was before the step, to the bit: a pair of two such overlaps
        // exactly as deep as before, so it cannot have sunk deeper by tol ≥ 0 (at rest,
        // no pair's overlap is measured).
        let stayed = |x: Body| {
            let (was, is) = (
                body_of(scene, before.t, &before.q, x),
                body_of(scene, st.t, &st.q, x),
            );
            same_pose(&was.0, &is.0)
        };
        let after = self.wanted(scene, stepper);
        // The pairs' overlap, not the corners' gaps: a corner exactly level with a side
        // of the other body is at distance zero from it however deep the faces overlap.
        // A pair's lines lie next to each other (sorted by their bodies first): its
        // overlap is measured once, at its first.
        let mut missed: Vec<[Body; 2]> = Vec::new();
        let mut last: Option<([Body; 2], bool)> = None;
        for l in &after.lines {
            let pair @ [a, b] = [l.line.lo, l.line.hi];
            let deeper = match last {
                Some((p, deeper)) if p == pair => deeper,
                _ if tol >= 0.0 && stayed(a) && stayed(b) => false,
                _ => {
                    let depth = after.pair_depth(a, b);
                    depth > tol && depth > pair_depth(scene, before.t, &before.q, a, b) + tol
                }
            };
            last = Some((pair, deeper));
            if deeper && missed.last() != Some(&pair) {
                missed.push(pair);
            }
        }
        missed
    }
}

/// The corner contacts in a list of lines.
fn count(lines: &[LineContacts]) -> usize {
    lines
        .iter()
        .map(|l| l.contacts.iter().flatten().count())
        .sum()
}

/// How deep two bodies (base or blocks) overlap at time t and block coordinates q.
fn pair_depth(scene: &Scene, t: f64, q: &[f64], a: Body, b: Body) -> f64 {
    let ((pa, sa), (pb, sb)) = (body_of(scene, t, q, a), body_of(scene, t, q, b));
    penetration_depth((&pa, sa), (&pb, sb))
}

/// The pose and size of body `x` (base or block) at time t and block coordinates q.
fn body_of(scene: &Scene, t: f64, q: &[f64], x: Body) -> (Pose, Size) {
    match x {
        Body::Block(k) => (Pose::from_slice(&q[3 * k - 3..]), scene.size(k)),
        Body::Base | Body::Floor => (scene.base().state(t).pose, scene.size(0)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::broad_phase::corner_gap_of;
    use crate::corners::Corner;
    use crate::simulation::{stepper_options, RunOptions};
    use crate::SceneFile;

    /// Within a step a body moves by about Δt times its speed at the step's start, which
    /// the broad phase's margin covers; a miss needs a body that gains speed within the
    /// step beyond the margin. Made here by hiding the contact from the first step: block
    /// 3 falls at 10 onto block 1, 0.02 above it, and would sink 0.03 into it.
    #[test]
    fn a_step_that_missed_a_contact_is_taken_again_with_it() {
        let text = "[base]\nwidth = 0.4\nheight = 0.1\n\
            [[blocks]]\nwidth = 0.2\nheight = 0.2\nx = 1.0\ny = 0.05\n\
            [[blocks]]\nwidth = 0.2\nheight = 0.2\nx = -1.0\ny = 0.05\n\
            [[blocks]]\nwidth = 0.2\nheight = 0.2\nx = 1.0\ny = 0.27\nvelocity = [0.0, -10.0, 0.0]\n\
            [contact]\nmu = 0.3\n[solver]\ndt = 0.005\n[floor]\n";
        let scene = SceneFile::parse(text).unwrap().to_scene().unwrap();
        let options = stepper_options(&scene, &RunOptions::default()).unwrap();
        let (q0, u0) = (scene.initial_coordinates(), scene.initial_velocities());
        let mut stepper =
            Stepper::new(StackSystem::new(scene.clone()), 0.0, &q0, &u0, options).unwrap();
        let mut corners = CornerStepping {
            wanted: Some((
                0,
                Scan {
                    lines: Vec::new(),
                    holds: scene.interfaces_holding(0.0, &q0, &u0),
                    ..Scan::default()
                },
            )),
            ..CornerStepping::default()
        };
        corners.step(&scene, &mut stepper, 1e-9).unwrap();
        assert_eq!(corners.redone_steps, 1);
        let q = &stepper.state().q;
        let depth = pair_depth(&scene, 0.005, q, Body::Block(3), Body::Block(1));
        assert!(depth < 1e-9, "block 3 is {depth} inside block 1");
        for c in [Corner::C, Corner::D] {
            let g = corner_gap_of(&scene, 0.005, q, Body::Block(3), c, Body::Block(1));
            assert!(g > -1e-9, "corner {c:?} of block 3 is {g} inside block 1");
        }
        assert!(stepper.state().u[7] > -10.0 * 0.5, "block 3 was stopped");
    }
}
