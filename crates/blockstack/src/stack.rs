//! All contacts of a scene in the generalized coordinates q = (x¹, y¹, θ¹, …, xⁿ, yⁿ, θⁿ)
//! of the free blocks (q̇ = u): what a time stepper evaluates at each iterate.
//!
//! Numbering (fixed for a scene, so that the solver's sizes never change), with m
//! interfaces (the (lower body, upper block) pairs of [`crate::arrangement`], in its
//! order; a column: interface k joins body k and block k+1, k = 0 the base, m = n):
//! - normal contacts: interface k has the left gap 2k and the right gap 2k+1
//!   (g_N^{2k−1}, g_N^{2k} of (G.2.2) in the thesis's one-based count); with a floor,
//!   block i's corner j ∈ (a, b, c, d) is 2m + 4i + j;
//! - friction laws: interface k is law k, bounded by the sum of its two normal forces
//!   (App. H); with a floor, block i's floor law is m + i, bounded by its four corners.
//!
//! For every row: ġ = wᵀu + χ and g̈ = wᵀu̇ + ζ (gaps); γ = wᵀu + χ and γ̇ = wᵀu̇ + ζ
//! (slips). χ and the base-acceleration part of ζ come from the prescribed base motion,
//! evaluated at the time asked for (ERRATA 20).
//!
//! Wiring to a stepper (e.g. an nsga `System`, whose evaluation is generic over a dual
//! scalar): per evaluation call [`Scene::contacts_into`] with the same scalar type; the
//! mass matrix is diagonal ([`Scene::mass_diagonal`]), the forces are
//! [`Scene::gravity_forces`]; each `Some(row)` of `normals` gives g_N = `value`, its W
//! column (`w.iter()`: coordinate index, entry), χ and ζ; a `None` is a contact that
//! cannot close — report it as open (any positive gap, W = 0, χ = ζ = 0); each slip gives
//! one friction component with W, χ, ζ, bounded by the normals of
//! [`Scene::friction_laws`]; every normal contact has e_N
//! ([`Scene::normal_restitutions`]) and every law e_F and μ, those of the two bodies it
//! joins ([`Scene::contact_between`]). Each row touches at most two bodies, so exact
//! sparse Jacobians can be formed row by row.

use crate::coordinates::{BodyState, Frame, Pose, Scalar, Twist};
use crate::gaps::PairRow;
use crate::interface::{Interface, InterfaceContacts};
use crate::overlap::Body as SceneBody;
use crate::pairs::body_index;
use crate::scene::Scene;
use crate::turned::{TurnedBodies, TurnedBody};

/// A column of W with at most six nonzero entries (two bodies × (x, y, θ)).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SparseColumn<T = f64> {
    index: [usize; 6],
    value: [T; 6],
    len: usize,
}

impl<T: Scalar> SparseColumn<T> {
    fn empty() -> Self {
        Self {
            index: [0; 6],
            value: [T::zero(); 6],
            len: 0,
        }
    }

    fn push3(&mut self, body: usize, w: &[T; 3]) {
        for (i, &wi) in w.iter().enumerate() {
            self.index[self.len] = 3 * body + i;
            self.value[self.len] = wi;
            self.len += 1;
        }
    }

    /// The nonzero entries (coordinate index, value).
    pub fn iter(&self) -> impl Iterator<Item = (usize, T)> + '_ {
        self.index[..self.len]
            .iter()
            .copied()
            .zip(self.value[..self.len].iter().copied())
    }

    /// wᵀv for a vector v of length 3n.
    #[must_use]
    pub fn dot(&self, v: &[T]) -> T {
        self.iter().fold(T::zero(), |acc, (i, w)| acc + w * v[i])
    }

    /// Adds `scale`·w to the dense vector `out` (length 3n).
    pub fn add_scaled_to(&self, scale: T, out: &mut [T]) {
        for (i, w) in self.iter() {
            out[i] += scale * w;
        }
    }
}

/// One contact quantity in the coordinates of the free blocks.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ContactRow<T = f64> {
    /// g (a gap) or γ (a slip speed, at the u given).
    pub value: T,
    /// W column: ∂g/∂q, or ∂γ/∂u.
    pub w: SparseColumn<T>,
    /// Explicit time dependence from the base: ġ = wᵀu + χ, γ = wᵀu + χ.
    pub chi: T,
    /// ζ: g̈ = wᵀu̇ + ζ, γ̇ = wᵀu̇ + ζ.
    pub zeta: T,
}

impl<T: Scalar> ContactRow<T> {
    /// A row on no coordinate: zero value, W, χ and ζ (the slip of a law left out).
    fn zero() -> Self {
        Self {
            value: T::zero(),
            w: SparseColumn::empty(),
            chi: T::zero(),
            zeta: T::zero(),
        }
    }
}

/// A group of rows of [`Scene::contacts_into_needed`], computed or left out together.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RowGroup {
    /// Interface k: its gaps 2k, 2k + 1 and its friction law k.
    Interface(usize),
    /// The floor gap of corner j (a, b, c, d) of block i (0-based).
    FloorCorner(usize, usize),
    /// The floor's friction law of block i (0-based).
    FloorLaw(usize),
}

/// A body of the scene as seen by the contacts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Body {
    /// The base: prescribed motion, no coordinates.
    Base,
    /// Free block i (0-based), coordinates 3i..3i+3.
    Block(usize),
}

/// One friction law: which normal contacts bound it (App. H), μ and e_F.
#[derive(Debug, Clone, PartialEq)]
pub struct FrictionLaw {
    /// Indices of the normal contacts whose forces add up to the bound μ Σ λ_N.
    pub normals: Vec<usize>,
    /// Friction coefficient μ.
    pub mu: f64,
    /// Tangential restitution e_F.
    pub e_f: f64,
}

/// Every contact of a scene at one (t, q, u).
#[derive(Debug, Clone, PartialEq)]
pub struct StackContacts<T = f64> {
    /// Normal gaps; `None` where the contact cannot close (support lost, G.2.4 /
    /// ERRATA 23): treat as open with zero force.
    pub normals: Vec<Option<ContactRow<T>>>,
    /// Slip speeds, one per friction law.
    pub slips: Vec<ContactRow<T>>,
    /// Per interface, the geometric detail (cases of (G.2.2), support state).
    pub interfaces: Vec<InterfaceContacts<T>>,
    /// The base and the blocks, each turned once for all the rows above (and for the
    /// corner contacts of the system's slots, which read them from here).
    pub bodies: TurnedBodies<T>,
}

impl<T: Scalar> Default for StackContacts<T> {
    fn default() -> Self {
        Self {
            normals: Vec::new(),
            slips: Vec::new(),
            interfaces: Vec::new(),
            bodies: TurnedBodies::default(),
        }
    }
}

impl<T: Scalar> StackContacts<T> {
    /// Empty buffers sized for the contacts of `scene`, so that filling them allocates
    /// once per list (the system's evaluation, generic over the scalar, cannot keep a
    /// buffer between calls).
    #[must_use]
    pub fn for_scene(scene: &Scene) -> Self {
        let (n, m) = (scene.n_blocks(), scene.n_interfaces());
        let floors = if scene.floor().is_some() { n } else { 0 };
        Self {
            normals: Vec::with_capacity(2 * m + 4 * floors),
            slips: Vec::with_capacity(m + floors),
            interfaces: Vec::with_capacity(m),
            bodies: TurnedBodies::default(),
        }
    }

    /// The smallest gap (real part) among the contacts that can close (`None` if none can).
    #[must_use]
    pub fn min_gap(&self) -> Option<f64> {
        self.normals
            .iter()
            .flatten()
            .map(|r| crate::coordinates::re(r.value))
            .reduce(f64::min)
    }

    /// The first interface (in the scene's numbering: a column's lowest) whose upper
    /// block has lost its support (G.2.4, ERRATA 23): the failure of §4.4 / Figure 4.6.
    #[must_use]
    pub fn first_unsupported(&self) -> Option<usize> {
        self.interfaces.iter().position(|i| !i.is_supported())
    }

    /// The first interface that is open completely: unsupported, or both gaps above
    /// `tol` (the blocks no longer touch at all).
    #[must_use]
    pub fn first_open(&self, tol: f64) -> Option<usize> {
        self.interfaces.iter().position(|i| {
            !i.is_supported()
                || (crate::coordinates::re(i.left.row.value) > tol
                    && crate::coordinates::re(i.right.row.value) > tol)
        })
    }
}

impl Scene {
    /// Number of normal contacts: 2 per interface, plus 4 per block with a floor.
    #[must_use]
    pub fn n_normal_contacts(&self) -> usize {
        let n = self.n_blocks();
        2 * self.n_interfaces() + if self.floor().is_some() { 4 * n } else { 0 }
    }

    /// The two bodies of interface k.
    fn interface_bodies(&self, k: usize) -> (SceneBody, SceneBody) {
        let seat = self.arrangement().seats()[k];
        (seat.lower, SceneBody::Block(seat.upper))
    }

    /// The interface joining bodies `a` and `b` (either order), if one rests on the other.
    #[must_use]
    pub fn interface_between(&self, a: SceneBody, b: SceneBody) -> Option<usize> {
        self.arrangement().between(a, b)
    }

    /// The friction laws (one slip speed each), in the numbering of the module docs, with
    /// the μ and e_F of the bodies each joins ([`Scene::contact_between`]).
    #[must_use]
    pub fn friction_laws(&self) -> Vec<FrictionLaw> {
        let (n, m) = (self.n_blocks(), self.n_interfaces());
        let law = |normals: Vec<usize>, (a, b)| {
            let c = self.contact_between(a, b);
            FrictionLaw {
                normals,
                mu: c.mu,
                e_f: c.e_f,
            }
        };
        let mut laws: Vec<FrictionLaw> = (0..m)
            .map(|k| law(vec![2 * k, 2 * k + 1], self.interface_bodies(k)))
            .collect();
        if self.floor().is_some() {
            laws.extend((0..n).map(|i| {
                law(
                    (0..4).map(|j| 2 * m + 4 * i + j).collect(),
                    (SceneBody::Block(i + 1), SceneBody::Floor),
                )
            }));
        }
        laws
    }

    /// e_N of every normal contact, in the numbering of the module docs
    /// ([`Scene::contact_between`] of the bodies each joins).
    #[must_use]
    pub fn normal_restitutions(&self) -> Vec<f64> {
        let n = self.n_blocks();
        let e_n = |(a, b)| self.contact_between(a, b).e_n;
        let mut out: Vec<f64> = (0..self.n_interfaces())
            .flat_map(|k| [e_n(self.interface_bodies(k)); 2])
            .collect();
        if self.floor().is_some() {
            out.extend((0..n).flat_map(|i| [e_n((SceneBody::Block(i + 1), SceneBody::Floor)); 4]));
        }
        out
    }

    /// The geometry of interface k (the sizes of its lower and upper body).
    pub(crate) fn interface(&self, k: usize) -> Interface {
        let seat = self.arrangement().seats()[k];
        Interface::new(self.size(body_index(seat.lower)), self.size(seat.upper))
    }

    /// All contacts at time t, coordinates q and velocities u (length 3n each).
    ///
    /// # Panics
    /// When q or u is shorter than 3n.
    #[must_use]
    pub fn contacts<T: Scalar>(&self, t: f64, q: &[T], u: &[T]) -> StackContacts<T> {
        let mut out = StackContacts::default();
        self.contacts_into(t, q, u, &mut out);
        out
    }

    /// [`Scene::contacts`] into a reused buffer (no allocation after the first call).
    ///
    /// # Panics
    /// When q or u is shorter than 3n.
    pub fn contacts_into<T: Scalar>(&self, t: f64, q: &[T], u: &[T], out: &mut StackContacts<T>) {
        self.contacts_into_needed(t, q, u, |_| true, None, out);
    }

    /// [`Scene::contacts_into`] with the rows of only the groups `needed` accepts, and
    /// with the interfaces whose gaps hold their contact given by `holds` (one entry per
    /// interface; `None`: [`InterfaceContacts::holds`] at this q). The numbering stays
    /// the same: a group left out gets `None` gaps and a zero slip; an interface left out
    /// has its [`StackContacts::interfaces`] detail at the bodies' real parts (its cases, support
    /// and holding exact; no derivative directions). For a caller that knows those rows
    /// are not needed (a derivative pass for a Newton matrix without them), and for the
    /// stepper's system, which decides the holding once per step
    /// ([`crate::system::StackSystem::hold_interfaces`]).
    ///
    /// # Panics
    /// When q or u is shorter than 3n, or `holds` has fewer than n entries.
    pub fn contacts_into_needed<T: Scalar>(
        &self,
        t: f64,
        q: &[T],
        u: &[T],
        needed: impl Fn(RowGroup) -> bool,
        holds: Option<&[bool]>,
        out: &mut StackContacts<T>,
    ) {
        let n = self.n_blocks();
        assert!(
            q.len() >= 3 * n && u.len() >= 3 * n,
            "q and u need 3 entries per block"
        );
        out.normals.clear();
        out.slips.clear();
        out.interfaces.clear();
        // Each body turned once, for all its rows (a column's block is the upper body of
        // one interface and the lower of the next, a lintel the upper body of two; in a
        // derivative pass, with the same directions in each).
        out.bodies.fill(self, t, q, u);
        let bodies = &out.bodies;
        for (k, seat) in self.arrangement().seats().iter().enumerate() {
            let lower_body = match seat.lower {
                SceneBody::Block(i) => Body::Block(i - 1),
                _ => Body::Base,
            };
            let upper_body = Body::Block(seat.upper - 1);
            let (lower, upper) = (bodies.get(seat.lower), bodies.block(seat.upper - 1));
            if !needed(RowGroup::Interface(k)) {
                // Only its detail, which the slots read for its holding: the real parts
                // cost little in dual numbers without directions.
                let [lower, upper] = [lower, upper].map(|b| TurnedBody::lift(&b.re()));
                let rotations = (lower.rotation, upper.rotation);
                let c = self.interface(k);
                out.interfaces
                    .push(c.contacts_turned(&lower.state, &upper.state, rotations));
                out.normals.extend([None; 2]);
                out.slips.push(ContactRow::zero());
                continue;
            }
            let turned = [(lower_body, lower), (upper_body, upper)];
            let (c, gaps, slip) = self.interface_rows(k, turned, bodies.base_acceleration(), holds);
            out.normals.extend(gaps);
            out.slips.push(slip);
            out.interfaces.push(c);
        }
        if let Some(floor) = self.floor() {
            for i in 0..n {
                let corners = [0, 1, 2, 3].map(|j| needed(RowGroup::FloorCorner(i, j)));
                let law = needed(RowGroup::FloorLaw(i));
                let (block, size) = (bodies.block(i), self.size(i + 1));
                if !law && !corners.contains(&true) {
                    out.normals.extend([None; 4]);
                    out.slips.push(ContactRow::zero());
                    continue;
                }
                if law && !corners.contains(&false) {
                    let c = floor.contacts_turned(block, size);
                    for g in &c.gaps {
                        out.normals.push(Some(single(g, i)));
                    }
                    out.slips.push(single(&c.slip, i));
                    continue;
                }
                // Part of the block's floor rows, without the detail.
                let (gaps, slip) = floor.rows_turned(block, size, corners, law);
                out.normals.extend(gaps.map(|g| g.map(|g| single(&g, i))));
                out.slips
                    .push(slip.map_or_else(ContactRow::zero, |s| single(&s, i)));
            }
        }
    }

    /// Interface k of the lower and upper bodies, turned (see
    /// [`Scene::contacts_into_needed`] for `holds`): its contacts, its two gap rows
    /// (`None` where its gaps do not hold the contact) and its slip row.
    fn interface_rows<T: Scalar>(
        &self,
        k: usize,
        [(lower_body, lower), (upper_body, upper)]: [(Body, &TurnedBody<T>); 2],
        base_acc: &Twist<T>,
        holds: Option<&[bool]>,
    ) -> InterfaceRows<T> {
        let rotations = (lower.rotation, upper.rotation);
        let (lower, upper) = (&lower.state, &upper.state);
        let c = self.interface(k).contacts_turned(lower, upper, rotations);
        let fold = |row: &PairRow<T>| fold_pair(row, lower_body, lower, base_acc, upper_body);
        let holds = holds_contact(holds, k, &c);
        let gaps = [
            holds.then(|| fold(&c.left.row)),
            holds.then(|| fold(&c.right.row)),
        ];
        let slip = fold(&c.slip);
        (c, gaps, slip)
    }

    /// The rows of interface k at time t with the given states of its lower and upper
    /// body (a derivative pass seeds them on directions of their own), with the holding
    /// of its gaps decided by `holds` as in [`Scene::contacts_into_needed`]: its two
    /// gap rows and its slip row.
    pub(crate) fn interface_rows_at<T: Scalar>(
        &self,
        k: usize,
        t: f64,
        [lower, upper]: [&BodyState<T>; 2],
        holds: Option<&[bool]>,
    ) -> ([Option<ContactRow<T>>; 2], ContactRow<T>) {
        let seat = self.arrangement().seats()[k];
        let (base, base_acc) = self.base().state_and_acceleration(t);
        let (base, base_acc) = (BodyState::lift(&base), Twist::lift(&base_acc));
        let (lower_body, lower) = match seat.lower {
            SceneBody::Block(i) => (Body::Block(i - 1), lower),
            _ => (Body::Base, &base),
        };
        let bodies = [
            (lower_body, &TurnedBody::of(*lower)),
            (Body::Block(seat.upper - 1), &TurnedBody::of(*upper)),
        ];
        let (_, gaps, slip) = self.interface_rows(k, bodies, &base_acc, holds);
        (gaps, slip)
    }

    /// Whether the gaps of each interface hold its contact at (t, q, u)
    /// ([`InterfaceContacts::holds`]), without the rest of the contacts.
    ///
    /// # Panics
    /// When q or u is shorter than 3n.
    #[must_use]
    pub fn interfaces_holding(&self, t: f64, q: &[f64], u: &[f64]) -> Vec<bool> {
        let base = Frame::of(&self.base().state(t).pose);
        let frame = |b: SceneBody| match b {
            SceneBody::Block(i) => Frame::of(&block_state(q, u, i - 1).pose),
            _ => base,
        };
        // Each body's frame once where it can be.
        let mut last: Option<(SceneBody, Frame, SceneBody, Frame)> = None;
        self.arrangement()
            .seats()
            .iter()
            .enumerate()
            .map(|(k, seat)| {
                let upper_body = SceneBody::Block(seat.upper);
                let framed = |b: SceneBody| match last {
                    Some((l, f, _, _)) if l == b => f,
                    Some((_, _, u, f)) if u == b => f,
                    _ => frame(b),
                };
                let (lower, upper) = (framed(seat.lower), framed(upper_body));
                last = Some((seat.lower, lower, upper_body, upper));
                self.interface(k).holds(&lower, &upper)
            })
            .collect()
    }
}

/// An interface's contacts, its two gap rows and its slip row.
type InterfaceRows<T> = (
    InterfaceContacts<T>,
    [Option<ContactRow<T>>; 2],
    ContactRow<T>,
);

/// Whether interface `k`, with contacts `c` at the evaluated q, holds its contact with
/// its own gaps: the decision in `holds` if one was made for the step, else
/// [`InterfaceContacts::holds`] at this q.
pub(crate) fn holds_contact<T>(holds: Option<&[bool]>, k: usize, c: &InterfaceContacts<T>) -> bool {
    holds.map_or_else(|| c.holds(), |h| h[k])
}

/// The state of block k (0-based) read from q and u.
pub(crate) fn block_state<T: Scalar>(q: &[T], u: &[T], k: usize) -> BodyState<T> {
    BodyState::new(
        Pose::from_slice(&q[3 * k..3 * k + 3]),
        Twist::from_slice(&u[3 * k..3 * k + 3]),
    )
}

/// A row on (lower body, upper block) in global coordinates; a base's terms go into χ, ζ.
fn fold_pair<T: Scalar>(
    row: &PairRow<T>,
    lower: Body,
    lower_state: &BodyState<T>,
    base_acc: &Twist<T>,
    upper: Body,
) -> ContactRow<T> {
    let zero = Twist::new(T::zero(), T::zero(), T::zero());
    let (first, base_vel) = match lower {
        Body::Base => (None, lower_state.twist),
        Body::Block(i) => (Some(i), zero),
    };
    let second = match upper {
        Body::Base => None,
        Body::Block(j) => Some(j),
    };
    pair_row(row, [first, second], &base_vel, base_acc)
}

/// A row on two bodies in the coordinates of the free blocks: `blocks` holds the 0-based
/// block of the first and the second body of `row`, `None` for the base, whose prescribed
/// velocity and acceleration (`base_vel`, `base_acc`) go into χ and ζ.
pub(crate) fn pair_row<T: Scalar>(
    row: &PairRow<T>,
    blocks: [Option<usize>; 2],
    base_vel: &Twist<T>,
    base_acc: &Twist<T>,
) -> ContactRow<T> {
    let mut w = SparseColumn::empty();
    let mut chi = T::zero();
    let mut zeta = row.zeta;
    for (body, wb) in blocks.into_iter().zip([&row.w_first, &row.w_second]) {
        match body {
            Some(i) => w.push3(i, wb),
            None => {
                chi += wb[0] * base_vel.vx + wb[1] * base_vel.vy + wb[2] * base_vel.omega;
                zeta += wb[0] * base_acc.vx + wb[1] * base_acc.vy + wb[2] * base_acc.omega;
            }
        }
    }
    ContactRow {
        value: row.value,
        w,
        chi,
        zeta,
    }
}

/// A floor row: only the block moves.
fn single<T: Scalar>(row: &PairRow<T>, block: usize) -> ContactRow<T> {
    let mut w = SparseColumn::empty();
    w.push3(block, &row.w_first);
    ContactRow {
        value: row.value,
        w,
        chi: T::zero(),
        zeta: row.zeta,
    }
}
