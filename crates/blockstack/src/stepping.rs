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

use crate::broad_phase::{corner_contacts, corner_gap_of};
use crate::pairs::CornerContact;
use crate::scene::Scene;
use crate::system::StackSystem;
use nsga::{StepError, Stepper};

/// The bookkeeping of the corner contacts over a run.
#[derive(Debug, Clone, Default)]
pub struct CornerStepping {
    /// The broad phase's list at the current state (step number, list).
    wanted: Option<(u64, Vec<CornerContact>)>,
    /// Steps taken again because a contact was missed.
    pub redone_steps: usize,
    /// The most corner contacts in the slots at once.
    pub most_contacts: usize,
}

impl CornerStepping {
    /// Puts `wanted` into the system's slots and tells the stepper what changed.
    ///
    /// # Errors
    /// Only if the stepper refuses the grown layout (a bug).
    pub fn assign(
        &mut self,
        stepper: &mut Stepper<StackSystem>,
        wanted: &[CornerContact],
    ) -> Result<(), StepError> {
        let change = stepper.system_mut().assign_corner_contacts(wanted);
        if change.grown {
            stepper.extend_layout()?;
        }
        if !change.assigned.is_empty() {
            let (normals, laws): (Vec<usize>, Vec<usize>) = change
                .assigned
                .iter()
                .map(|&s| stepper.system().slot_contacts(s))
                .unzip();
            stepper.forget_contacts(&normals, &laws)?;
        }
        self.most_contacts = self.most_contacts.max(wanted.len());
        Ok(())
    }

    /// The broad phase's list at the stepper's current state (computed once per state).
    fn wanted(&mut self, scene: &Scene, stepper: &Stepper<StackSystem>) -> Vec<CornerContact> {
        let st = stepper.state();
        match &self.wanted {
            Some((k, list)) if *k == st.k => list.clone(),
            _ => {
                let dt = stepper.options().dt;
                let list = corner_contacts(scene, st.t, &st.q, &st.u, dt);
                self.wanted = Some((st.k, list.clone()));
                list
            }
        }
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
        let wanted = self.wanted(scene, stepper);
        self.assign(stepper, &wanted)?;
        let before = stepper.state().clone();
        stepper.step()?;
        let after = self.wanted(scene, stepper);
        let st = stepper.state();
        let missed: Vec<CornerContact> = after
            .into_iter()
            .filter(|c| !wanted.contains(c) && corner_gap_of(scene, st.t, &st.q, c) < -tol)
            .collect();
        if missed.is_empty() {
            return Ok(());
        }
        self.redone_steps += 1;
        stepper.set_state(before);
        let mut union = wanted;
        union.extend(missed);
        union.sort_by_key(CornerContact::key);
        self.assign(stepper, &union)?;
        self.wanted = None;
        stepper.step()?;
        Ok(())
    }
}
