//! The block stack as an nsga [`System`] (§4.2, App. G, H).
//!
//! Coordinates q = (x¹, y¹, θ¹, …, xⁿ, yⁿ, θⁿ) of the free blocks, (4.2.1)–(4.2.2), with
//! q̇ = u; the mass matrix is diag(m, m, I) per block with I = m(w² + h²)/12; the applied
//! forces are gravity (0, −m g, 0) (no gyroscopic terms in 2D). The base (block 0) has
//! no coordinates: its prescribed motion enters the gaps and slips of the interface 0/1
//! through χ and ζ, evaluated at the integrator's own time (ERRATA 20).
//!
//! Constraints, in the numbering of [`crate::stack`]:
//! - normal gaps: the two gaps of each interface, (G.2.2)–(G.2.3), with the seamless
//!   switch between edge and corner contact; a gap of an interface whose upper block has
//!   lost its support ((G.2.4) corrected, ERRATA 23) cannot close and is reported as an
//!   open contact ([`UNSUPPORTED_GAP`], W = 0); with a floor, the four corners of every
//!   block against it;
//! - friction: one Coulomb law per interface with the slip speed of (G.3.1)–(G.3.2),
//!   bounded by μ (λ_N^{2k−1} + λ_N^{2k}) (App. H); with a floor, one law per block bounded
//!   by μ times the sum of its four corner forces.
//!
//! # Exact sparse derivatives
//!
//! The default [`System::derivatives`] differentiates the evaluation once per coordinate
//! and per velocity, 6n passes over an O(n) evaluation: O(n²) per Newton iteration.
//! Here every constraint row touches at most two blocks joined by an interface, or one
//! block (a floor corner). The blocks are given two colours so that the two blocks of
//! an interface differ (a column: the parity of their number; `BlockColours`); then
//! seeding the same coordinate (x, y or θ) of all blocks of one colour with one
//! direction and of the other colour with another gives every derivative exactly
//! (forward-mode dual numbers) with 6 directions over q and 6 over u, whatever n. All 12
//! are carried in one pass of vector dual numbers ([`Directions`]): the real parts (and
//! their sines and cosines) are computed once, and the cost per iteration is linear in
//! n. An interface whose blocks got the same colour (an odd cycle in the arrangement,
//! which two colours cannot separate) is differentiated on its own afterwards, as the
//! contact lines of the slots are.

use crate::coordinates::re;
use crate::coordinates::{BodyState, Pose, Twist};
use crate::overlap::Body;
use crate::pairs::{body_index, free_block, CornerContact, LineContacts, LineKind};
use crate::scene::{ContactParams, Scene};
use crate::stack::{holds_contact, ContactRow, RowGroup, StackContacts};
use crate::turned::TurnedBody;
use nsga::{Derivatives, Evaluation, FrictionLaw, Layout, Probes, Scalar, System};
use num_dual::DualSVec64;
use std::cell::RefCell;

/// The 12 seeding directions of the derivative pass: (parity, coordinate) over q, then
/// over u.
const DIRECTIONS: usize = 12;

/// Vector dual numbers carrying the 12 derivative directions of one derivative pass.
pub type Directions = DualSVec64<DIRECTIONS>;

/// The direction of coordinate `coord` (0, 1, 2 = x, y, θ) of the blocks of `parity`, over
/// q (`velocity` false) or u.
fn direction(parity: usize, coord: usize, velocity: bool) -> usize {
    usize::from(velocity) * 6 + parity * 3 + coord
}

/// Component `d` of the derivative part (0 when none is carried).
fn part(x: &Directions, d: usize) -> f64 {
    x.eps.0.as_ref().map_or(0.0, |v| v[d])
}

/// The value reported for a gap that cannot close (its upper block has fallen off, or a
/// slot's corner has slid past the end of its face), with no W: positive, so the contact
/// opens once its multipliers are zero (with a multiplier κ̂_N ≥ r left from an iterate
/// where it was closed, the prox test still counts it closed; docs/method.md §8.2).
pub const UNSUPPORTED_GAP: f64 = 1.0;

/// How far past the end of its face (times the smallest block dimension) a corner contact
/// still holds: equal blocks flush have their corners exactly at the ends of each other's
/// faces, and a slight tilt must not open them; a corner farther out has left the face
/// (held on its line, the position projection of the last resort would throw the body
/// back across).
pub const END_TOL: f64 = 0.05;

/// A [`Scene`] seen by the nsga stepper.
#[derive(Debug)]
pub struct StackSystem {
    scene: Scene,
    mass: Vec<f64>,
    forces: Vec<f64>,
    laws: Vec<FrictionLaw>,
    e_n: Vec<f64>,
    /// The contact lines beyond the stack's own (crate::pairs), one per slot; `None` is
    /// a free slot. Each slot has two normal contacts and one friction law, after the
    /// scene's.
    slots: Vec<Option<LineContacts>>,
    /// μ, e_N, e_F of each slot, fixed when the slot is made: the stepper reads the
    /// layout only when it grows ([`nsga::Stepper::extend_layout`]), so a slot takes only
    /// lines of its own material ([`StackSystem::assign_corner_contacts`]).
    slot_materials: Vec<ContactParams>,
    /// Whether each neighbour interface's gaps hold its contact, decided once per step
    /// at the step's start ([`StackSystem::hold_interfaces`]); `None`: decided at every
    /// evaluation from the evaluated q.
    interface_holds: Option<Vec<bool>>,
    /// How far past the end of its face a corner contact's corner may be and still touch
    /// it: [`END_TOL`] times the smallest block dimension.
    end_tol: f64,
    /// The colour of each block for the seeding of the derivative pass (module docs).
    colours: BlockColours,
    /// Reused buffers of the derivative passes (the system is evaluated from one thread).
    scratch: RefCell<DualScratch>,
    /// The contact lists of [`System::evaluate_real`], reused: allocating them per
    /// evaluation was a third of the Lire collapse's allocations.
    real_contacts: RefCell<StackContacts<f64>>,
}

/// What [`StackSystem::assign_corner_contacts`] changed.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct SlotChange {
    /// The number of slots grew: the stepper must re-read the layout
    /// ([`nsga::Stepper::extend_layout`]).
    pub grown: bool,
    /// Normal contacts that now hold another corner contact than before, and friction
    /// laws of slots given to another line: the stepper must forget their forces
    /// ([`nsga::Stepper::forget_contacts`]).
    pub normals: Vec<usize>,
    /// See `normals`.
    pub laws: Vec<usize>,
}

#[derive(Debug, Default)]
struct DualScratch {
    q: Vec<Directions>,
    u: Vec<Directions>,
    contacts: StackContacts<Directions>,
}

impl Clone for StackSystem {
    fn clone(&self) -> Self {
        let mut copy = Self::new(self.scene.clone());
        copy.slots.clone_from(&self.slots);
        copy.slot_materials.clone_from(&self.slot_materials);
        copy.interface_holds.clone_from(&self.interface_holds);
        copy
    }
}

impl StackSystem {
    /// The system of a (validated) scene, with its neighbour interfaces and no corner
    /// contacts.
    ///
    /// Step it as a run does, through [`crate::stepping::CornerStepping`] (`start`
    /// before the stepper is built, then `step`): that adds the corner contacts the
    /// broad phase finds and decides once per step which interfaces hold their contact
    /// (docs/contacts.md, "Who holds a neighbour contact"). Stepped bare, the system
    /// decides the holding at every Newton iterate and has no corner contact to take
    /// over, so that blocks can sink into each other (a column kicked by its base,
    /// [`crate::scenarios::shaking_column`], does within its first hundred steps).
    #[must_use]
    pub fn new(scene: Scene) -> Self {
        let laws = scene
            .friction_laws()
            .into_iter()
            .map(|law| FrictionLaw {
                components: 1,
                mu: law.mu,
                e_f: law.e_f,
                normals: law.normals,
            })
            .collect();
        Self {
            mass: scene.mass_diagonal(),
            forces: scene.gravity_forces(),
            e_n: scene.normal_restitutions(),
            laws,
            slots: Vec::new(),
            slot_materials: Vec::new(),
            interface_holds: None,
            end_tol: END_TOL * scene.smallest_block_dimension(),
            colours: BlockColours::of(&scene),
            scratch: RefCell::new(DualScratch::default()),
            real_contacts: RefCell::new(StackContacts::for_scene(&scene)),
            scene,
        }
    }

    /// The contact lines in the slots (`None`: a free slot).
    #[must_use]
    pub fn corner_contacts(&self) -> &[Option<LineContacts>] {
        &self.slots
    }

    /// The two normal contacts and the friction law of slot `s`.
    #[must_use]
    pub fn slot_contacts(&self, s: usize) -> ([usize; 2], usize) {
        let first = self.e_n.len() + 2 * s;
        ([first, first + 1], self.laws.len() + s)
    }

    /// Decides which neighbour interfaces hold their contact with their own two gaps
    /// (one entry per interface, as [`Scene::interfaces_holding`] gives them at the
    /// state a step starts from) for every evaluation until the next call; the corner
    /// contacts of the slots hold the others. Within a step the choice is fixed, as the
    /// face of a corner contact is: decided from each evaluated q, it made the step's
    /// equations discontinuous where a block turns or slides across the limit of
    /// [`crate::interface::InterfaceContacts::holds`] (the same corner passes from an
    /// interface gap to a slot's contact, with other unknowns), and Newton could cycle
    /// between the two sides with no solution on either at any Δt (docs/method.md §8.2).
    ///
    /// Returns the normal contacts and friction laws of the interfaces whose choice
    /// changed: their forces belong to the other side of the handover, and the stepper
    /// must forget them ([`nsga::Stepper::forget_contacts`]), as for a slot given to
    /// another contact. (With the forces of a held interface kept, a closed gap that no
    /// longer has a W column made the next Newton matrix singular.)
    ///
    /// # Panics
    /// When `holds` does not have one entry per interface.
    pub fn hold_interfaces(&mut self, holds: Vec<bool>) -> SlotChange {
        assert_eq!(
            holds.len(),
            self.scene.n_interfaces(),
            "one entry per interface"
        );
        let mut change = SlotChange::default();
        if let Some(before) = &self.interface_holds {
            for (k, (was, is)) in before.iter().zip(&holds).enumerate() {
                if was != is {
                    // Interface k: normal contacts 2k, 2k + 1 and friction law k
                    // (`Scene::friction_laws`).
                    change.normals.extend([2 * k, 2 * k + 1]);
                    change.laws.push(k);
                }
            }
        }
        self.interface_holds = Some(holds);
        change
    }

    /// Whether [`StackSystem::hold_interfaces`] with `holds` would change nothing.
    #[must_use]
    pub fn holds_interfaces(&self, holds: &[bool]) -> bool {
        self.interface_holds.as_deref() == Some(holds)
    }

    /// Whether interface `k`, with contacts `c` at the evaluated q, holds its contact:
    /// the decision of [`StackSystem::hold_interfaces`] if one was made.
    fn interface_holds<T>(&self, k: usize, c: &crate::interface::InterfaceContacts<T>) -> bool {
        holds_contact(self.interface_holds.as_deref(), k, c)
    }

    /// Whether the slots hold exactly the `wanted` contact lines with their contacts, so
    /// that [`StackSystem::assign_corner_contacts`] would change nothing.
    #[must_use]
    pub fn holds_corner_contacts(&self, wanted: &[LineContacts]) -> bool {
        let held = self.slots.iter().flatten();
        // Slots filled from a list in its order hold it in that order: one pass.
        if held.clone().eq(wanted) {
            return true;
        }
        held.clone().count() == wanted.len()
            && wanted.iter().all(|w| {
                held.clone().any(|s| {
                    s.line == w.line
                        && s.contacts.iter().all(|c| w.contacts.contains(c))
                        && w.contacts.iter().all(|c| s.contacts.contains(c))
                })
            })
    }

    /// Puts the `wanted` contact lines (from the broad phase, [`crate::broad_phase`])
    /// into the slots: a line already in a slot stays there, and so do its contacts that
    /// are still wanted; a slot whose line is no longer wanted is freed (the broad phase
    /// wants every contact that may close within the step, so a freed one is open); new
    /// lines take the free slots of their material ([`Scene::contact_between`]) in order,
    /// the number of slots doubling when none is left (the new slots beyond those lines
    /// take the scene's default material). Deterministic.
    pub fn assign_corner_contacts(&mut self, wanted: &[LineContacts]) -> SlotChange {
        let mut change = SlotChange::default();
        let mut keep = vec![false; self.slots.len()];
        let mut new: Vec<LineContacts> = Vec::new();
        for w in wanted {
            let Some(i) = self
                .slots
                .iter()
                .position(|s| s.as_ref().is_some_and(|s| s.line == w.line))
            else {
                new.push(*w);
                continue;
            };
            keep[i] = true;
            let old = self.slots[i].expect("a slot with this line").contacts;
            let mut contacts = [None; 2];
            for (p, c) in old.iter().enumerate() {
                if c.is_some() && w.contacts.contains(c) {
                    contacts[p] = *c;
                }
            }
            for c in w.contacts.iter().filter(|c| c.is_some()) {
                if !contacts.contains(c) {
                    let p = contacts
                        .iter()
                        .position(Option::is_none)
                        .expect("two places");
                    contacts[p] = *c;
                }
            }
            let (normals, _) = self.slot_contacts(i);
            for p in 0..2 {
                if contacts[p] != old[p] {
                    change.normals.push(normals[p]);
                }
            }
            self.slots[i] = Some(LineContacts {
                line: w.line,
                contacts,
            });
        }
        for (slot, kept) in self.slots.iter_mut().zip(&keep) {
            if !kept {
                *slot = None;
            }
        }
        let mut free: Vec<usize> = (0..self.slots.len())
            .filter(|&i| self.slots[i].is_none())
            .collect();
        let mut placed = Vec::with_capacity(new.len());
        let mut homeless = Vec::new();
        for w in new {
            let material = self.line_material(&w);
            match free
                .iter()
                .position(|&i| self.slot_materials[i] == material)
            {
                Some(p) => placed.push((w, free.remove(p))),
                None => homeless.push((w, material)),
            }
        }
        if !homeless.is_empty() {
            let first = self.slots.len();
            let capacity = (first + homeless.len()).max(2 * first).max(4);
            self.slots.resize(capacity, None);
            // The spare slots take the defaults, the material of most lines.
            self.slot_materials.resize(capacity, self.scene.contact);
            for (k, (w, material)) in homeless.into_iter().enumerate() {
                self.slot_materials[first + k] = material;
                placed.push((w, first + k));
            }
            change.grown = true;
        }
        for (w, i) in placed {
            self.slots[i] = Some(w);
            let (normals, law) = self.slot_contacts(i);
            change.normals.extend(normals);
            change.laws.push(law);
        }
        change
    }

    /// μ, e_N, e_F of the contacts of a line: those of its two bodies.
    fn line_material(&self, line: &LineContacts) -> ContactParams {
        self.scene.contact_between(line.line.lo, line.line.hi)
    }

    /// The gap rows of a slot's contacts and the slip of its friction law, with the
    /// bodies turned as `turned` gives them and the base's acceleration `base_acc`;
    /// `None` when the line's bodies are neighbours whose interface supports the upper
    /// one and the interface's gaps hold all its contacts.
    fn slot_rows<'b, T: Scalar + 'b>(
        &self,
        line: &LineContacts,
        turned: impl Fn(Body) -> &'b TurnedBody<T>,
        base_acc: &Twist<T>,
        interfaces: &[crate::interface::InterfaceContacts<T>],
    ) -> Option<SlotRows<T>> {
        // While the interface supports, it holds the corners it measures (ℓ_a…ℓ_d of
        // (G.2.3)); the line keeps only its other contacts (a corner against a side).
        let interface = self.scene.interface_between(line.line.lo, line.line.hi);
        let supported = interface.is_some_and(|k| self.interface_holds(k, &interfaces[k]));
        let lower = interface.map(|k| self.scene.arrangement().seats()[k].lower);
        let size = |b| self.scene.size(body_index(b));
        // A corner that has slid past the end of its face no longer touches it (its face
        // was chosen at the start of the step): the contact opens rather than hold the
        // corner on the face's line beyond the body.
        let on_face = |c: &CornerContact| {
            let sizes = [size(c.corner_body), size(c.face_body)];
            let frames = [c.corner_body, c.face_body].map(|b| turned(b).frame());
            c.beyond_end(&frames, sizes) <= self.end_tol
        };
        let contacts = line.contacts.map(|c| {
            c.filter(|c| {
                !(supported && lower.is_some_and(|l| c.is_interface_case(l))) && on_face(c)
            })
        });
        if contacts.iter().all(Option::is_none) {
            return None;
        }
        let along = match line.line.kind {
            LineKind::Face(side) => {
                let lo = turned(line.line.lo);
                Some(lo.rotation.apply(&side.face(size(line.line.lo)).tangent))
            }
            LineKind::Corner(..) => None,
        };
        let bodies = |c: &CornerContact| [turned(c.corner_body), turned(c.face_body)];
        let sizes = |c: &CornerContact| [size(c.corner_body), size(c.face_body)];
        let gaps = contacts.map(|c| c.map(|c| c.gap_row(bodies(&c), sizes(&c), base_acc)));
        // The law's slip: the contact with the smaller gap, as (G.3.1) (the other's
        // slip is not needed).
        let closer = match (&gaps[0], &gaps[1]) {
            (Some(a), Some(b)) if re(b.value) < re(a.value) => contacts[1],
            (Some(_), _) => contacts[0],
            (None, Some(_)) => contacts[1],
            (None, None) => return None,
        }?;
        let slip = closer.slip_row(bodies(&closer), sizes(&closer), base_acc, along.as_ref());
        Some(SlotRows { gaps, slip })
    }

    /// The state of a body of a corner contact: the base's prescribed one, or a block's
    /// from q and u (through `lift`, which may seed derivative directions).
    fn body_state<T: Scalar>(
        &self,
        t: f64,
        body: Body,
        mut lift: impl FnMut(usize) -> BodyState<T>,
    ) -> BodyState<T> {
        match free_block(body) {
            Some(i) => lift(i),
            None => BodyState::lift(&self.scene.base().state(t)),
        }
    }

    /// The scene.
    #[must_use]
    pub fn scene(&self) -> &Scene {
        &self.scene
    }
}

/// The rows of one slot: its two gaps (`None`: no contact in that place) and its slip.
struct SlotRows<T> {
    gaps: [Option<ContactRow<T>>; 2],
    slip: ContactRow<T>,
}

/// Writes one slip row (friction component `j`): W and χ, ζ (v = Wᵀu + χ is formed by
/// the stepper).
fn put_slip<T: Scalar>(row: &ContactRow<T>, j: usize, out: &mut Evaluation<T>) {
    for (i, wi) in row.w.iter() {
        out.velocity_w.push(i, j, wi);
    }
    out.velocity_chi[j] = row.chi;
    out.velocity_zeta[j] = row.zeta;
}

/// Writes one constraint row into a family (value, W column `col`, χ, ζ); `None` is an
/// open contact that cannot close.
fn put_row<T: Scalar>(
    row: Option<&ContactRow<T>>,
    col: usize,
    value: &mut [T],
    w: &mut nsga::Triplets<T>,
    chi: &mut [T],
    zeta: &mut [T],
) {
    match row {
        Some(r) => {
            value[col] = r.value;
            for (i, wi) in r.w.iter() {
                w.push(i, col, wi);
            }
            chi[col] = r.chi;
            zeta[col] = r.zeta;
        }
        None => value[col] = T::from(UNSUPPORTED_GAP),
    }
}

impl System for StackSystem {
    fn layout(&self) -> Layout {
        let n = 3 * self.scene.n_blocks();
        let mut e_n = self.e_n.clone();
        let mut friction = self.laws.clone();
        for s in 0..self.slots.len() {
            let (normals, _) = self.slot_contacts(s);
            let c = self.slot_materials[s];
            e_n.extend([c.e_n; 2]);
            friction.push(FrictionLaw {
                components: 1,
                mu: c.mu,
                e_f: c.e_f,
                normals: normals.to_vec(),
            });
        }
        Layout {
            nq: n,
            nu: n,
            e_n,
            friction,
            ..Layout::default()
        }
    }

    fn evaluate<T: Scalar>(&self, t: f64, q: &[T], u: &[T], out: &mut Evaluation<T>) {
        self.evaluate_into(t, q, u, out, &mut StackContacts::for_scene(&self.scene));
    }

    /// Gravity and the contact laws do not change with time: the stack is autonomous
    /// once its base stands still for good ([`crate::Base::still_from`]).
    fn autonomous_from(&self, t: f64) -> bool {
        self.scene.base().still_from(t)
    }

    /// 4/3: a corner of a rectangle of any aspect needs μ ≥ 4/3 for b ≤ 0 (App. I,
    /// ERRATA 18: b m = 1 + (a² + μ s a c)/k² with a, c the corner's lever arms about the
    /// normal and the tangent, a² + c² = r², k² = r²/3, whose least value over the angle is
    /// 1 + 3(1 − √(1 + μ²))/2, zero at μ = 4/3). A contact between two blocks adds one such
    /// term per block, and the base and the floor are not bodies, so no contact of a stack
    /// is in Painlevé's region below 4/3.
    fn least_painleve_friction(&self) -> f64 {
        4.0 / 3.0
    }

    fn evaluate_real(&self, t: f64, q: &[f64], u: &[f64], out: &mut Evaluation<f64>) {
        self.evaluate_into(t, q, u, out, &mut self.real_contacts.borrow_mut());
    }

    /// M and h are constant: only the contact rows have derivatives. See the module docs
    /// for the colour seeding.
    fn derivatives(
        &self,
        t: f64,
        q: &[f64],
        u: &[f64],
        probes: &Probes<'_>,
        out: &mut Derivatives,
    ) {
        let mut guard = self.scratch.borrow_mut();
        let s = &mut *guard;
        // Into the reused buffers: this runs once per Newton iteration.
        let colour = &self.colours.colour;
        let seed = |out: &mut Vec<Directions>, x: &[f64], velocity: bool| {
            out.clear();
            out.extend(x.iter().enumerate().map(|(i, &v)| {
                let d = direction(colour[i / 3], i % 3, velocity);
                Directions::from_re(v).derivative(d)
            }));
        };
        seed(&mut s.q, q, false);
        seed(&mut s.u, u, true);
        // The rows of an interface (its law k and the gaps bounding it) are skipped when
        // the stepper uses none of them, and so is each row of a block's floor (its
        // corners and its law m + i) it does not use: an open contact's, pruned (a
        // column fallen on the floor has most).
        let m = self.scene.n_interfaces();
        let used = |law: usize| {
            probes.uses_velocity(law)
                || self.laws[law]
                    .normals
                    .iter()
                    .any(|&k| probes.uses_position(k))
        };
        let needed = |group| match group {
            // A same-coloured interface is differentiated on its own (below).
            RowGroup::Interface(k) => used(k) && !self.colours.same[k],
            RowGroup::FloorCorner(i, j) => probes.uses_position(self.laws[m + i].normals[j]),
            RowGroup::FloorLaw(i) => probes.uses_velocity(m + i),
        };
        self.scene.contacts_into_needed(
            t,
            &s.q,
            &s.u,
            needed,
            self.interface_holds.as_deref(),
            &mut s.contacts,
        );
        for parity in 0..2 {
            for coord in 0..3 {
                let (dq, du) = (
                    direction(parity, coord, false),
                    direction(parity, coord, true),
                );
                // The rows of a same-coloured interface (normals 2k, 2k + 1, law k) are
                // differentiated on their own below.
                let own = |k: usize| k < m && self.colours.same[k];
                for (i, row) in s.contacts.normals.iter().enumerate() {
                    let Some(row) = row.as_ref().filter(|_| probes.uses_position(i)) else {
                        continue;
                    };
                    let Some(j) = seeded_coordinate(row, colour, parity, coord) else {
                        continue;
                    };
                    if !own(i / 2) {
                        gap_derivatives(row, (dq, du), i, j, u, probes, out);
                    }
                }
                for (i, row) in s.contacts.slips.iter().enumerate() {
                    if !probes.uses_velocity(i) || own(i) {
                        continue;
                    }
                    let Some(j) = seeded_coordinate(row, colour, parity, coord) else {
                        continue;
                    };
                    slip_derivatives(row, (dq, du), i, j, u, probes, out);
                }
            }
        }
        self.same_colour_derivatives(t, q, u, probes, out);
        self.slot_derivatives(t, q, u, probes, &s.contacts.interfaces, out);
    }
}

impl StackSystem {
    /// [`System::evaluate`] with the contact lists `c` (cleared and filled here).
    fn evaluate_into<T: Scalar>(
        &self,
        t: f64,
        q: &[T],
        u: &[T],
        out: &mut Evaluation<T>,
        c: &mut StackContacts<T>,
    ) {
        for (i, (&m, &h)) in self.mass.iter().zip(&self.forces).enumerate() {
            out.mass.push(i, i, T::from(m));
            out.forces[i] = T::from(h);
        }
        self.scene
            .contacts_into_needed(t, q, u, |_| true, self.interface_holds.as_deref(), c);
        for (i, row) in c.normals.iter().enumerate() {
            put_row(
                row.as_ref(),
                i,
                &mut out.position,
                &mut out.position_w,
                &mut out.position_chi,
                &mut out.position_zeta,
            );
        }
        // Slips: v = Wᵀu + χ is formed by the stepper; only W, χ, ζ are reported.
        for (j, row) in c.slips.iter().enumerate() {
            put_slip(row, j, out);
        }
        for (s, line) in self.slots.iter().enumerate() {
            let (normals, law) = self.slot_contacts(s);
            let bodies = &c.bodies;
            let rows = line.as_ref().and_then(|l| {
                let turned = |b| bodies.get(b);
                self.slot_rows(l, turned, bodies.base_acceleration(), &c.interfaces)
            });
            let Some(rows) = rows else {
                for i in normals {
                    out.position[i] = T::from(UNSUPPORTED_GAP);
                }
                continue;
            };
            for (gap, i) in rows.gaps.iter().zip(normals) {
                put_row(
                    gap.as_ref(),
                    i,
                    &mut out.position,
                    &mut out.position_w,
                    &mut out.position_chi,
                    &mut out.position_zeta,
                );
            }
            put_slip(&rows.slip, law, out);
        }
    }

    /// The derivatives of the rows of the interfaces whose two blocks have the same
    /// colour (module docs), each interface on its own: its lower body's (x, y, θ) on
    /// directions 0–2 (over q) and 6–8 (over u), its upper body's on 3–5 and 9–11.
    fn same_colour_derivatives(
        &self,
        t: f64,
        q: &[f64],
        u: &[f64],
        probes: &Probes<'_>,
        out: &mut Derivatives,
    ) {
        let seats = self.scene.arrangement().seats();
        for (k, seat) in seats
            .iter()
            .enumerate()
            .filter(|(k, _)| self.colours.same[*k])
        {
            let normals = [2 * k, 2 * k + 1];
            let used = normals.map(|i| probes.uses_position(i));
            let use_v = probes.uses_velocity(k);
            if !used.contains(&true) && !use_v {
                continue;
            }
            let bodies = [seat.lower, Body::Block(seat.upper)];
            let state = |role: usize| self.body_state(t, bodies[role], |b| seeded(q, u, b, role));
            let (gaps, slip) = self.scene.interface_rows_at(
                k,
                t,
                [&state(0), &state(1)],
                self.interface_holds.as_deref(),
            );
            let rows = SlotRows { gaps, slip };
            rows_derivatives(&rows, bodies, (normals, k), (used, use_v), u, probes, out);
        }
    }

    /// The derivatives of the contact-line rows. A line may join any two blocks, so the
    /// colour seeding does not apply; each slot is differentiated on its own, with its
    /// lower body's (x, y, θ) on directions 0–2 (over q) and 6–8 (over u) and its upper
    /// body's on 3–5 and 9–11: one pass of the same 12-direction dual numbers per slot
    /// in use.
    fn slot_derivatives(
        &self,
        t: f64,
        q: &[f64],
        u: &[f64],
        probes: &Probes<'_>,
        interfaces: &[crate::interface::InterfaceContacts<Directions>],
        out: &mut Derivatives,
    ) {
        let (base, base_acc) = self.scene.base().state_and_acceleration(t);
        let (base, base_acc) = (BodyState::lift(&base), Twist::lift(&base_acc));
        for (slot, line) in self.slots.iter().enumerate() {
            let Some(line) = line else { continue };
            let (normals, law) = self.slot_contacts(slot);
            let used = normals.map(|i| probes.uses_position(i));
            let use_v = probes.uses_velocity(law);
            if !used.contains(&true) && !use_v {
                continue;
            }
            let bodies = [line.line.lo, line.line.hi];
            // Each body seeded on its role's directions and turned once for the slot.
            let pair = [0, 1].map(|role| {
                let state = free_block(bodies[role]).map_or(base, |k| seeded(q, u, k, role));
                TurnedBody::of(state)
            });
            let turned = |b: Body| &pair[usize::from(b == bodies[1])];
            let Some(rows) = self.slot_rows(line, turned, &base_acc, interfaces) else {
                continue;
            };
            rows_derivatives(&rows, bodies, (normals, law), (used, use_v), u, probes, out);
        }
    }
}

/// The state of free block `b` from q and u, seeded on the derivative directions of
/// `role` (0: directions 0–2 over q and 6–8 over u; 1: 3–5 and 9–11).
fn seeded(q: &[f64], u: &[f64], b: usize, role: usize) -> BodyState<Directions> {
    let x = |k: usize, d: usize| Directions::from_re(q[3 * b + k]).derivative(3 * role + d);
    let v = |k: usize, d: usize| Directions::from_re(u[3 * b + k]).derivative(6 + 3 * role + d);
    BodyState::new(
        Pose::new(x(0, 0), x(1, 1), x(2, 2)),
        Twist::new(v(0, 0), v(1, 1), v(2, 2)),
    )
}

/// The derivatives of two gap rows (normal contacts `normals`, those `used`) and a slip
/// row (law `law`, if `use_v`) on two bodies seeded by role ([`seeded`]).
fn rows_derivatives(
    rows: &SlotRows<Directions>,
    bodies: [Body; 2],
    (normals, law): ([usize; 2], usize),
    (used, use_v): ([bool; 2], bool),
    u: &[f64],
    probes: &Probes<'_>,
    out: &mut Derivatives,
) {
    for (role, body) in bodies.into_iter().enumerate() {
        let Some(b) = free_block(body) else { continue };
        for coord in 0..3 {
            let (dq, du, j) = (3 * role + coord, 6 + 3 * role + coord, 3 * b + coord);
            for ((gap, i), used) in rows.gaps.iter().zip(normals).zip(used) {
                let Some(gap) = gap.as_ref().filter(|_| used) else {
                    continue;
                };
                gap_derivatives(gap, (dq, du), i, j, u, probes, out);
            }
            if use_v {
                slip_derivatives(&rows.slip, (dq, du), law, j, u, probes, out);
            }
        }
    }
}

/// Two colours for the blocks, so that the two blocks of as many interfaces as possible
/// differ (module docs): each connected group of blocks joined by interfaces is coloured
/// breadth first from its first block, which takes the parity of its number (a column:
/// block k has the parity of k − 1, as the thesis's numbering seeded them).
#[derive(Debug, Clone)]
struct BlockColours {
    /// Per block (0-based): 0 or 1.
    colour: Vec<usize>,
    /// Per interface: whether its two blocks have the same colour.
    same: Vec<bool>,
}

impl BlockColours {
    fn of(scene: &Scene) -> Self {
        let n = scene.n_blocks();
        let seats = scene.arrangement().seats();
        // Block–block interfaces as an adjacency list (0-based blocks).
        let mut next: Vec<Vec<usize>> = vec![Vec::new(); n];
        let pairs = seats
            .iter()
            .filter_map(|s| Some((free_block(s.lower)?, s.upper - 1)));
        for (a, b) in pairs.clone() {
            next[a].push(b);
            next[b].push(a);
        }
        let mut colour: Vec<Option<usize>> = vec![None; n];
        for start in 0..n {
            if colour[start].is_some() {
                continue;
            }
            colour[start] = Some(start % 2);
            let mut queue = std::collections::VecDeque::from([start]);
            while let Some(a) = queue.pop_front() {
                let c = colour[a].unwrap_or(0);
                for &b in &next[a] {
                    if colour[b].is_none() {
                        colour[b] = Some(1 - c);
                        queue.push_back(b);
                    }
                }
            }
        }
        let colour: Vec<usize> = colour.into_iter().map(|c| c.unwrap_or(0)).collect();
        let same = seats
            .iter()
            .map(|s| free_block(s.lower).is_some_and(|a| colour[a] == colour[s.upper - 1]))
            .collect();
        Self { colour, same }
    }
}

/// The coordinate index seeded for this row: `coord` of the one block of colour `parity`
/// the row touches (a row touches one block, or two of different colours).
fn seeded_coordinate(
    row: &ContactRow<Directions>,
    colour: &[usize],
    parity: usize,
    coord: usize,
) -> Option<usize> {
    row.w
        .iter()
        .map(|(i, _)| i / 3)
        .find(|&b| colour[b] == parity)
        .map(|b| 3 * b + coord)
}

fn push_nonzero(t: &mut nsga::Triplets<f64>, r: usize, c: usize, v: f64) {
    if v != 0.0 {
        t.push(r, c, v);
    }
}

/// The derivatives of gap row `i` with respect to coordinate `j`, seeded on directions
/// `(dq, du)` (over q and over u): into the position-level matrices of `out`.
fn gap_derivatives(
    row: &ContactRow<Directions>,
    (dq, du): (usize, usize),
    i: usize,
    j: usize,
    u: &[f64],
    probes: &Probes<'_>,
    out: &mut Derivatives,
) {
    q_row(
        row,
        dq,
        i,
        j,
        u,
        probes,
        |k| probes.dynamics[k].1,
        &mut out.dynamics_q,
        &mut PositionRows {
            value: Some(&mut out.position_q),
            rate: &mut out.position_rate_q,
            accel: &mut out.position_accel_q,
        },
    );
    // Only ζ depends on u.
    push_nonzero(&mut out.position_accel_u, i, j, part(&row.zeta, du));
}

/// The derivatives of slip row `i` (a friction component) with respect to coordinate
/// `j`: v = Wᵀu + χ is the velocity-level "value", so its q-derivatives go into
/// velocity_q, like ṗ's into position_rate_q.
fn slip_derivatives(
    row: &ContactRow<Directions>,
    (dq, du): (usize, usize),
    i: usize,
    j: usize,
    u: &[f64],
    probes: &Probes<'_>,
    out: &mut Derivatives,
) {
    q_row(
        row,
        dq,
        i,
        j,
        u,
        probes,
        |k| probes.dynamics[k].2,
        &mut out.dynamics_q,
        &mut PositionRows {
            value: None,
            rate: &mut out.velocity_q,
            accel: &mut out.velocity_accel_q,
        },
    );
    push_nonzero(&mut out.velocity_accel_u, i, j, part(&row.zeta, du));
}

/// Where the q-derivatives of one constraint family go (`value`: none for the velocity
/// family, whose "value" v = Wᵀu + χ is formed by the stepper).
struct PositionRows<'a> {
    value: Option<&'a mut nsga::Triplets<f64>>,
    rate: &'a mut [nsga::Triplets<f64>; 2],
    accel: &'a mut nsga::Triplets<f64>,
}

/// The q-derivatives of row `i` with respect to coordinate `j` (the seeded one), in the
/// conventions of [`Derivatives`]: ∂(−W μ)/∂q for the three probes, ∂value/∂q,
/// ∂(Wᵀu + χ)/∂q at u and u_old, ∂(Wᵀa + ζ)/∂q.
#[allow(clippy::too_many_arguments)]
fn q_row<'p>(
    row: &ContactRow<Directions>,
    d: usize,
    i: usize,
    j: usize,
    u: &[f64],
    probes: &Probes<'p>,
    multiplier: impl Fn(usize) -> &'p [f64],
    dynamics: &mut [nsga::Triplets<f64>; 3],
    rows: &mut PositionRows<'_>,
) {
    for (r, w) in row.w.iter() {
        let dw = part(&w, d);
        if dw == 0.0 {
            continue;
        }
        for (k, dyn_k) in dynamics.iter_mut().enumerate() {
            dyn_k.push(r, j, -dw * multiplier(k)[i]);
        }
        rows.rate[0].push(i, j, dw * u[r]);
        rows.rate[1].push(i, j, dw * probes.u_old[r]);
        rows.accel.push(i, j, dw * probes.a[r]);
    }
    if let Some(value) = rows.value.as_deref_mut() {
        push_nonzero(value, i, j, part(&row.value, d));
    }
    let dchi = part(&row.chi, d);
    push_nonzero(&mut rows.rate[0], i, j, dchi);
    push_nonzero(&mut rows.rate[1], i, j, dchi);
    push_nonzero(rows.accel, i, j, part(&row.zeta, d));
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenarios::{lire_on_floor, shaking_column, Perturbation, Shaking};
    use nsga::system::forward_derivatives;
    use nsga::Triplets;

    fn dense(t: &Triplets<f64>, rows: usize, cols: usize) -> Vec<f64> {
        let mut m = vec![0.0; rows * cols];
        for &(r, c, v) in &t.entries {
            m[r * cols + c] += v;
        }
        m
    }

    fn all(d: &Derivatives, nq: usize, np: usize, nv: usize) -> Vec<Vec<f64>> {
        let mut out = Vec::new();
        for t in &d.dynamics_q {
            out.push(dense(t, nq, nq));
        }
        out.push(dense(&d.position_q, np, nq));
        for t in &d.position_rate_q {
            out.push(dense(t, np, nq));
        }
        out.push(dense(&d.position_accel_q, np, nq));
        out.push(dense(&d.position_accel_u, np, nq));
        for t in &d.velocity_q {
            out.push(dense(t, nv, nq));
        }
        out.push(dense(&d.velocity_accel_q, nv, nq));
        out.push(dense(&d.velocity_accel_u, nv, nq));
        out
    }

    /// The parity-seeded derivatives equal the default one-pass-per-coordinate ones.
    fn check(scene: Scene, t: f64) {
        check_with_unused(scene, t, &[], &[]);
    }

    /// As [`check`], with the rows of the `unused` constraints left out (their
    /// multipliers zero, as the stepper guarantees): those rows must be absent, every
    /// other entry exact.
    fn check_with_unused(scene: Scene, t: f64, unused_p: &[bool], unused_v: &[bool]) {
        check_system(&StackSystem::new(scene), t, unused_p, unused_v);
    }

    fn check_system(sys: &StackSystem, t: f64, unused_p: &[bool], unused_v: &[bool]) {
        let layout = sys.layout();
        let (nq, np, nv) = (layout.nq, layout.n_position(), layout.n_velocity());
        let mut q = sys.scene().initial_coordinates();
        // Tilt and move every block a little, so that no derivative vanishes by symmetry.
        let wave = |i: usize, s: f64| s * ((i as f64) * 1.7 + 0.3).sin();
        for (i, x) in q.iter_mut().enumerate() {
            *x += wave(i, 0.01);
        }
        let u: Vec<f64> = (0..nq).map(|i| wave(i + 5, 0.3)).collect();
        let a: Vec<f64> = (0..nq).map(|i| wave(i + 11, 0.7)).collect();
        let uo: Vec<f64> = (0..nq).map(|i| wave(i + 17, 0.2)).collect();
        let used = |mask: &[bool], i: usize| mask.get(i) != Some(&true);
        let mp: Vec<Vec<f64>> = (0..3)
            .map(|k| {
                (0..np)
                    .map(|i| wave(i + 23 * k, f64::from(u8::from(used(unused_p, i)))))
                    .collect()
            })
            .collect();
        let mv: Vec<Vec<f64>> = (0..3)
            .map(|k| {
                (0..nv)
                    .map(|i| wave(i + 29 * k, f64::from(u8::from(used(unused_v, i)))))
                    .collect()
            })
            .collect();
        let probes = Probes {
            a: &a,
            u_old: &uo,
            dynamics: [
                (&u, &mp[0], &mv[0]),
                (&a, &mp[1], &mv[1]),
                (&uo, &mp[2], &mv[2]),
            ],
            unused_position: unused_p,
            unused_velocity: unused_v,
        };
        let mut sparse = Derivatives::default();
        sys.derivatives(t, &q, &u, &probes, &mut sparse);
        let mut reference = Derivatives::default();
        forward_derivatives(sys, t, &q, &u, &probes, &mut reference);
        for (k, (x, mut y)) in all(&sparse, nq, np, nv)
            .into_iter()
            .zip(all(&reference, nq, np, nv))
            .enumerate()
        {
            // Matrices 3..8 have a row per position-level constraint, 8.. per velocity one.
            let mask = match k {
                0..3 => &[][..],
                3..8 => unused_p,
                _ => unused_v,
            };
            let cols = y.len() / mask.len().max(1);
            for (i, _) in mask.iter().enumerate().filter(|(_, &u)| u) {
                y[i * cols..(i + 1) * cols].fill(0.0);
            }
            let err = x
                .iter()
                .zip(&y)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            let size = y.iter().map(|v| v.abs()).fold(0.0, f64::max);
            assert!(err <= 1e-13 * (1.0 + size), "matrix {k}: error {err}");
            assert!(size > 0.0 || k == 0, "matrix {k} vanishes");
        }
    }

    #[test]
    fn sparse_derivatives_equal_forward_ad_on_the_lire_tower() {
        check(lire_on_floor(4, Perturbation::Bottom).unwrap(), 0.3);
    }

    #[test]
    fn unused_floor_rows_are_left_out_and_the_rest_is_exact() {
        let scene = lire_on_floor(4, Perturbation::Bottom).unwrap();
        let (nn, nl) = (scene.n_normal_contacts(), scene.friction_laws().len());
        // The floor rows come after the 2 × 4 interface gaps and the 4 interface laws.
        let unused_p: Vec<bool> = (0..nn).map(|i| i >= 8).collect();
        let unused_v: Vec<bool> = (0..nl).map(|i| i >= 4).collect();
        assert!(unused_p.iter().any(|&u| u) && unused_v.iter().any(|&u| u));
        check_with_unused(scene, 0.3, &unused_p, &unused_v);
    }

    use crate::corners::Corner;
    use crate::pairs::{ContactLine, CornerContact, LineKind, Side};

    fn contact(a: Body, c: Corner, b: Body, face: Side) -> Option<CornerContact> {
        Some(CornerContact {
            corner_body: a,
            corner: c,
            face_body: b,
            face,
        })
    }

    fn line(
        lo: Body,
        hi: Body,
        kind: LineKind,
        contacts: [Option<CornerContact>; 2],
    ) -> LineContacts {
        LineContacts {
            line: ContactLine { lo, hi, kind },
            contacts,
        }
    }

    #[test]
    fn corner_contact_derivatives_equal_forward_ad() {
        let mut sys = StackSystem::new(lire_on_floor(4, Perturbation::Bottom).unwrap());
        let (b1, b2, b3, b4) = (
            Body::Block(1),
            Body::Block(2),
            Body::Block(3),
            Body::Block(4),
        );
        // Same-parity blocks with a contact on each body, the base on either side, a
        // corner line, neighbours whose interface supports (so the slot stays open), and
        // a free slot.
        let mut wanted = vec![
            line(
                b1,
                b3,
                LineKind::Face(Side::Top),
                [
                    contact(b3, Corner::C, b1, Side::Top),
                    contact(b1, Corner::A, b3, Side::Bottom),
                ],
            ),
            line(
                Body::Base,
                b2,
                LineKind::Corner(Corner::B, Side::Left),
                [contact(Body::Base, Corner::B, b2, Side::Left), None],
            ),
            line(
                Body::Base,
                b3,
                LineKind::Face(Side::Top),
                [None, contact(b3, Corner::D, Body::Base, Side::Top)],
            ),
            line(
                b1,
                b2,
                LineKind::Face(Side::Top),
                [contact(b2, Corner::C, b1, Side::Top), None],
            ),
            line(
                b2,
                b4,
                LineKind::Face(Side::Right),
                [contact(b4, Corner::C, b2, Side::Right), None],
            ),
        ];
        let change = sys.assign_corner_contacts(&wanted);
        let laws: Vec<usize> = (0..5).map(|s| sys.slot_contacts(s).1).collect();
        assert!(change.grown && change.laws == laws);
        wanted.pop();
        let change = sys.assign_corner_contacts(&wanted);
        assert!(change.laws.is_empty() && change.normals.is_empty());
        assert_eq!(sys.corner_contacts()[4], None, "a free slot");
        check_system(&sys, 0.3, &[], &[]);
    }

    /// Block k's corner d on the base's top face, alone on its line.
    fn on_base_top(k: usize) -> LineContacts {
        line(
            Body::Base,
            Body::Block(k),
            LineKind::Face(Side::Top),
            [
                contact(Body::Block(k), Corner::D, Body::Base, Side::Top),
                None,
            ],
        )
    }

    /// Some corners of each block's floor unused, and one block's floor law: only
    /// those rows are left out, the lowest corner's slip of the others stays exact.
    #[test]
    fn partly_used_floor_rows_are_left_out_and_the_rest_is_exact() {
        let scene = lire_on_floor(4, Perturbation::Bottom).unwrap();
        let (nn, nl) = (scene.n_normal_contacts(), scene.friction_laws().len());
        // After the 2 × 4 interface gaps and the 4 interface laws: corners b and d of
        // every block, and block 1's floor law.
        let unused_p: Vec<bool> = (0..nn).map(|i| i >= 8 && i % 2 == 1).collect();
        let unused_v: Vec<bool> = (0..nl).map(|i| i == 4).collect();
        check_with_unused(scene, 0.3, &unused_p, &unused_v);
    }

    /// The rows of an interface the stepper does not use are left out of the derivative
    /// pass, and a slot on its two bodies still reads its holding: the rest is exact.
    #[test]
    fn unused_interface_rows_are_left_out_and_the_rest_is_exact() {
        let mut sys = StackSystem::new(shaken_column(3));
        let (b1, b2) = (Body::Block(1), Body::Block(2));
        let beside = line(
            b1,
            b2,
            LineKind::Face(Side::Top),
            [contact(b2, Corner::C, b1, Side::Top), None],
        );
        sys.assign_corner_contacts(&[beside, on_base_top(3)]);
        let layout = sys.layout();
        // Interface 1 joins blocks 1 and 2: normals 2 and 3, law 1.
        let unused_p: Vec<bool> = (0..layout.n_position()).map(|i| i == 2 || i == 3).collect();
        let unused_v: Vec<bool> = (0..layout.n_velocity()).map(|i| i == 1).collect();
        check_system(&sys, 0.4, &unused_p, &unused_v);
    }

    /// The stepper's evaluations reuse one set of contact lists: each must fill its
    /// output as a fresh generic evaluation does, to the bit, whatever the call before.
    #[test]
    fn real_evaluations_equal_generic_ones_bitwise() {
        // A moving base (so t matters), a floor, and two corner contacts in slots.
        let mut sys = StackSystem::new(shaken_column(3));
        sys.assign_corner_contacts(&[on_base_top(1), on_base_top(2)]);
        let layout = sys.layout();
        let q0 = sys.scene().initial_coordinates();
        let tilted: Vec<f64> = q0
            .iter()
            .enumerate()
            .map(|(i, x)| x + 0.02 * ((i as f64) * 1.3).sin())
            .collect();
        let u: Vec<f64> = (0..q0.len()).map(|i| 0.4 * (i as f64).cos()).collect();
        for (t, q) in [(0.0, &q0), (0.7, &tilted), (1.1, &q0)] {
            let mut generic = Evaluation::new(&layout);
            sys.evaluate::<f64>(t, q, &u, &mut generic);
            let mut real = Evaluation::new(&layout);
            sys.evaluate_real(t, q, &u, &mut real);
            assert_eq!(format!("{real:?}"), format!("{generic:?}"), "t = {t}");
        }
    }

    /// The holding of an interface decided for a step stays across the limit of
    /// `InterfaceContacts::holds` (faces turned 60° from each other): evaluated per q,
    /// the gaps of interface 1 vanish there (the contact passes to the slots, with
    /// other unknowns), which made the step's equations discontinuous; held, they go on
    /// continuously and their derivatives stay exact. A flip of the decision names the
    /// interface's contacts and law, whose forces the stepper must forget.
    #[test]
    fn the_interface_holding_decided_for_a_step_is_kept_across_the_limit() {
        let mut sys = StackSystem::new(shaken_column(2));
        let layout = sys.layout();
        let q0 = sys.scene().initial_coordinates();
        // The upper block turned by θ about its centre and moved left so that its bottom
        // corner stays over the lower block's top face, the lower one upright: the faces
        // are turned from each other by θ, and e₂·e₂ = cos θ passes `HOLDS` = cos 60°
        // between the two.
        let turned = |theta: f64| {
            let mut q = q0.clone();
            q[3] -= 0.15;
            q[5] = theta;
            q
        };
        let (before, after) = (turned(59.9_f64.to_radians()), turned(60.1_f64.to_radians()));
        let u = vec![0.1; q0.len()];
        let scene = sys.scene().clone();
        assert_eq!(scene.interfaces_holding(0.3, &before, &u), [true, true]);
        assert_eq!(scene.interfaces_holding(0.3, &after, &u), [true, false]);
        for q in [&q0, &before, &after] {
            let each: Vec<bool> = scene
                .contacts(0.3, q, &u)
                .interfaces
                .iter()
                .map(crate::interface::InterfaceContacts::holds)
                .collect();
            assert_eq!(scene.interfaces_holding(0.3, q, &u), each);
        }
        let gaps = |sys: &StackSystem, q: &[f64]| {
            let mut e = Evaluation::new(&layout);
            sys.evaluate_real(0.3, q, &u, &mut e);
            [e.position[2], e.position[3]]
        };
        assert_eq!(gaps(&sys, &after), [UNSUPPORTED_GAP; 2]);
        let first = sys.hold_interfaces(scene.interfaces_holding(0.3, &before, &u));
        assert_eq!(first, SlotChange::default());
        let (held, across) = (gaps(&sys, &before), gaps(&sys, &after));
        for (g0, g1) in held.into_iter().zip(across) {
            assert!(
                g1 != UNSUPPORTED_GAP && (g1 - g0).abs() < 2e-3,
                "{g0} → {g1}"
            );
        }
        check_system(&sys, 0.3, &[], &[]);
        let flipped = sys.hold_interfaces(scene.interfaces_holding(0.3, &after, &u));
        assert_eq!((flipped.normals, flipped.laws), (vec![2, 3], vec![1]));
        assert!(sys.holds_interfaces(&[true, false]));
        assert_eq!(gaps(&sys, &before), [UNSUPPORTED_GAP; 2]);
    }

    #[test]
    fn slots_keep_their_lines_and_reuse_freed_ones() {
        let mut sys = StackSystem::new(lire_on_floor(3, Perturbation::Bottom).unwrap());
        let c = on_base_top;
        sys.assign_corner_contacts(&[c(1), c(2)]);
        let change = sys.assign_corner_contacts(&[c(2), c(3)]);
        assert!(!change.grown);
        let ([n0, n1], law) = sys.slot_contacts(0);
        assert_eq!(change.laws, vec![law], "c(3) takes the slot c(1) left");
        assert_eq!(change.normals, vec![n0, n1]);
        assert_eq!(
            sys.corner_contacts()[1],
            Some(c(2)),
            "c(2) stays where it was"
        );
        // A second contact on a kept line: only its normal is new.
        let mut two = c(2);
        two.contacts[1] = contact(Body::Block(2), Corner::C, Body::Base, Side::Top);
        let change = sys.assign_corner_contacts(&[two, c(3)]);
        assert_eq!(change.normals, vec![sys.slot_contacts(1).0[1]]);
        assert!(change.laws.is_empty());
        let n = sys.layout().n_normal();
        let change = sys.assign_corner_contacts(&[c(1), c(2), c(3), c(4), c(5)]);
        assert!(change.grown && sys.layout().n_normal() == n + 2 * 4);
    }

    /// A slot keeps the material it was made with (the stepper reads the layout only when
    /// it grows): a line of another material does not take a free slot but grows the
    /// slots, and its contacts have its own μ and e_N.
    #[test]
    fn a_slot_takes_only_lines_of_its_own_material() {
        use crate::materials::{Materials, Override, PairMaterial};
        let pair = Override {
            mu: Some(0.9),
            e_n: Some(0.4),
            e_f: None,
        };
        let scene = lire_on_floor(3, Perturbation::Bottom)
            .unwrap()
            .with_materials(Materials {
                pairs: vec![PairMaterial {
                    bodies: [Body::Block(3), Body::Base],
                    label: "3/base".into(),
                    params: pair,
                }],
                ..Materials::default()
            })
            .unwrap();
        let default = scene.contact;
        let mut sys = StackSystem::new(scene);
        let c = on_base_top;
        assert!(sys.assign_corner_contacts(&[c(1), c(2)]).grown);
        let slots = sys.corner_contacts().len();
        let change = sys.assign_corner_contacts(&[c(1), c(3)]);
        assert!(change.grown, "the free slots have the default material");
        let s = sys
            .corner_contacts()
            .iter()
            .position(|l| *l == Some(c(3)))
            .unwrap();
        assert!(s >= slots);
        let layout = sys.layout();
        let ([n, _], law) = sys.slot_contacts(s);
        assert_eq!((layout.friction[law].mu, layout.e_n[n]), (0.9, 0.4));
        let ([n, _], law) = sys.slot_contacts(0);
        assert_eq!(
            (layout.friction[law].mu, layout.e_n[n]),
            (default.mu, default.e_n)
        );
        // Freed and taken again by a line of its material: no growth.
        sys.assign_corner_contacts(&[c(1)]);
        assert!(!sys.assign_corner_contacts(&[c(1), c(3)]).grown);
    }

    #[test]
    fn the_slots_hold_a_list_exactly_when_assigning_it_changes_nothing() {
        let mut sys = StackSystem::new(lire_on_floor(3, Perturbation::Bottom).unwrap());
        let c = on_base_top;
        let mut two = c(2);
        two.contacts[1] = contact(Body::Block(2), Corner::C, Body::Base, Side::Top);
        sys.assign_corner_contacts(&[c(1), two]);
        let mut swapped = two;
        swapped.contacts.swap(0, 1);
        for held in [vec![c(1), two], vec![two, c(1)], vec![c(1), swapped]] {
            assert!(sys.holds_corner_contacts(&held));
            let before = sys.corner_contacts().to_vec();
            let change = sys.assign_corner_contacts(&held);
            assert!(change.normals.is_empty() && change.laws.is_empty() && !change.grown);
            assert_eq!(sys.corner_contacts(), before.as_slice());
        }
        // A contact less on a kept line, a line less, a line more.
        for other in [vec![c(1), c(2)], vec![c(1)], vec![c(1), two, c(3)]] {
            assert!(!sys.holds_corner_contacts(&other), "{other:?}");
        }
    }

    /// The built-in shaken column of `blocks` blocks, on its moving base above a floor.
    fn shaken_column(blocks: usize) -> Scene {
        shaking_column(&Shaking {
            blocks,
            ..Shaking::default()
        })
        .unwrap()
    }

    #[test]
    fn sparse_derivatives_equal_forward_ad_on_a_shaken_column() {
        check(shaken_column(5), 0.77);
    }

    /// The built-in trilith, shaken: the lintel's two interfaces join it to both posts,
    /// which the colours separate (posts one colour, lintel the other).
    #[test]
    fn sparse_derivatives_equal_forward_ad_on_a_trilith() {
        let scene = crate::scenes::find("trilith")
            .unwrap()
            .load()
            .unwrap()
            .scene;
        let sys = StackSystem::new(scene.clone());
        assert_eq!(sys.colours.colour, [0, 0, 1]);
        assert_eq!(sys.colours.same, [false; 4]);
        check(scene, 0.3);
    }

    /// Five blocks whose interfaces make a cycle of five (a slab on the base; a tall post
    /// and a stack of two short ones on the slab; a beam across the post and the stack):
    /// two colours cannot separate every interface, and the one left with a single
    /// colour is differentiated on its own, exactly.
    #[test]
    fn sparse_derivatives_are_exact_on_an_odd_cycle_of_interfaces() {
        let block = |name: &str, w: f64, h: f64, x: f64, on: &str| {
            format!(
                "[[blocks]]\nname = \"{name}\"\nwidth = {w:?}\nheight = {h:?}\nx = {x:?}\non = {on}\n"
            )
        };
        let text = [
            "[base]\nwidth = 3.0\nheight = 0.1\nmotion = \"harmonic\"\namplitude = 0.1\nomega = 3.0\n".to_owned(),
            block("slab", 2.0, 0.2, 0.0, "\"base\""),
            block("post", 0.2, 0.6, -0.6, "\"slab\""),
            block("low", 0.2, 0.3, 0.6, "\"slab\""),
            block("high", 0.2, 0.3, 0.6, "\"low\""),
            block("beam", 1.6, 0.2, 0.0, "[\"post\", \"high\"]"),
            "[contact]\nmu = 0.5\n[floor]\n".to_owned(),
        ]
        .concat();
        let scene = Scene::from_toml(&text).unwrap();
        assert_eq!(scene.n_interfaces(), 6);
        let sys = StackSystem::new(scene.clone());
        assert_eq!(sys.colours.same.iter().filter(|&&s| s).count(), 1);
        check(scene, 0.4);
    }
}
