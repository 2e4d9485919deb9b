//! A scene: the base, the blocks bottom to top, the optional floor, and the contact and
//! solver parameters (§4.2, "Simulation Parameters"), validated.

use crate::arrangement::Arrangement;
use crate::base::Base;
use crate::block::Block;
use crate::coordinates::{BodyState, Pose, Scalar, Twist};
use crate::error::BlockError;
use crate::floor::Floor;
use crate::interface::Size;
use crate::materials::Materials;
use crate::overlap::{deepest_among, scene_bodies, Body};
use input::{finite, positive};

/// Coulomb friction and restitution (§4.2): the scene's defaults, which
/// [`Materials`] may override per kind of interface and per pair of bodies.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactParams {
    /// Friction coefficient μ ≥ 0 (static = dynamic, §4.2).
    pub mu: f64,
    /// Normal restitution e_N ∈ [0, 1].
    pub e_n: f64,
    /// Tangential restitution e_F ∈ [0, 1] (ERRATA 19: its own value, not e_N).
    pub e_f: f64,
}

impl ContactParams {
    /// Checks μ ≥ 0 and e_N, e_F ∈ [0, 1].
    ///
    /// # Errors
    /// The first parameter out of range.
    pub fn validate(&self) -> Result<(), BlockError> {
        input::non_negative("mu", self.mu)?;
        input::in_range("e_n", self.e_n, 0.0..=1.0, "[0, 1]")?;
        input::in_range("e_f", self.e_f, 0.0..=1.0, "[0, 1]")?;
        Ok(())
    }
}

/// The prox parameter r of the contact laws (docs/method.md §4): nsga's own choice,
/// `Prox::Scaled(α)` (r_k = α/(w_kᵀM⁻¹w_k), α ∈ (0, 2)) or `Prox::Constant(r)` (the
/// thesis: r = 0.3).
pub use nsga::Prox;

/// Parameters of the time integration (§4.2 "Simulation Parameters").
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverParams {
    /// Time step Δt.
    pub dt: f64,
    /// End time.
    pub t_end: f64,
    /// Spectral radius at infinite frequency ρ∞ ∈ [0, 1] (thesis: 0.5).
    pub rho_inf: f64,
    /// Prox parameter.
    pub prox: Prox,
    /// Newton tolerance (thesis: 1e-10).
    pub tol: f64,
    /// Gravity g (thesis: 1), acting along −E₂.
    pub gravity: f64,
}

impl Default for SolverParams {
    /// The thesis's values (§4.2): Δt = 0.01, ρ∞ = 0.5, tol = 1e-10, g = 1, t_end = 10,
    /// with the prox parameter scaled (α = 1) rather than the constant r = 0.3.
    fn default() -> Self {
        Self {
            dt: 0.01,
            t_end: 10.0,
            rho_inf: 0.5,
            prox: Prox::Scaled(1.0),
            tol: 1e-10,
            gravity: 1.0,
        }
    }
}

impl SolverParams {
    /// Checks Δt, t_end, tol > 0, ρ∞ ∈ [0, 1], r > 0 (α ∈ (0, 2)), g finite and ≥ 0.
    ///
    /// # Errors
    /// The first parameter out of range.
    pub fn validate(&self) -> Result<(), BlockError> {
        positive("dt", self.dt)?;
        positive("t_end", self.t_end)?;
        positive("tol", self.tol)?;
        input::in_range("rho_inf", self.rho_inf, 0.0..=1.0, "[0, 1]")?;
        match self.prox {
            Prox::Constant(r) => {
                positive("r", r)?;
            }
            Prox::Scaled(alpha) => {
                positive("r_alpha", alpha)?;
                if alpha >= 2.0 {
                    return Err(input::InputError::OutOfRange {
                        name: "r_alpha".into(),
                        range: "(0, 2)",
                        value: alpha,
                    }
                    .into());
                }
            }
        }
        input::non_negative("gravity", self.gravity)?;
        Ok(())
    }
}

/// A validated block stack: base (block 0), blocks 1..n bottom to top, optional floor.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    base: Base,
    blocks: Vec<Block>,
    floor: Option<Floor>,
    /// Friction and restitution: the defaults of every contact.
    pub contact: ContactParams,
    /// Time-integration parameters.
    pub solver: SolverParams,
    /// Overrides of `contact` per kind of interface and per pair (none by default).
    materials: Materials,
    /// Which bodies each block rests on: the interfaces (crate::arrangement).
    arrangement: Arrangement,
    /// The blocks' names from a scene file (`None`: unnamed), for messages.
    names: Vec<Option<String>>,
    /// Whether a block touches only the bodies an interface joins it to (the thesis's
    /// code: block k meets blocks k − 1 and k + 1), never another block or the base.
    neighbours_only: bool,
}

/// Relative tolerance on initial overlaps (of the largest block size).
const OVERLAP_TOL: f64 = 1e-9;

/// The most free blocks a scene may have, checked before memory is taken for them (a
/// column of 10 000 blocks takes about 1 GB). A column that moves with its base takes 100
/// steps of 1000 blocks in about a second, and 10 steps of 10 000 blocks at Δt = 0.005 in
/// about 15 s; but a kicked column's steps cost far more than n times a short one's
/// (docs/method.md §8.2, tall columns: 6 to 10 s for 10 steps at 300 blocks), taller
/// columns may end their tipping step on a band of open interfaces (3000 blocks: 93 s to
/// t = 0.1), and one that tips within its first step (10 000 blocks at Δt = 0.01) does
/// not take it. The ten-minute time guard ([`crate::time_guard`]) stops what would run
/// longer, within a step if need be. The thesis's stacks have 4 to 20.
pub const MAX_BLOCKS: usize = 10_000;

/// [`MAX_BLOCKS`] as the range of a block count, for error messages.
pub const BLOCK_COUNT_RANGE: &str = "[1, 10000]";

/// Refuses a number of blocks over [`MAX_BLOCKS`] (or zero) before anything is
/// allocated for them; `name` is what the user typed (`--blocks`, `blocks`, a scene's
/// `[[blocks]] count`), so that the error names it:
/// `--blocks must lie in [1, 10000], got 1000000000`.
///
/// # Errors
/// Zero blocks, or more than [`MAX_BLOCKS`].
pub fn check_block_count(name: &str, n: usize) -> Result<usize, BlockError> {
    if (1..=MAX_BLOCKS).contains(&n) {
        return Ok(n);
    }
    #[allow(clippy::cast_precision_loss)]
    let value = n as f64;
    Err(input::InputError::OutOfRange {
        name: name.to_owned(),
        range: BLOCK_COUNT_RANGE,
        value,
    }
    .into())
}

impl Scene {
    /// A scene, checked: parameters in range, at least one block, no two bodies
    /// overlapping at the start, every block above the floor, and the floor not above the
    /// base's bottom face.
    ///
    /// # Errors
    /// The first problem found, as one line.
    pub fn new(
        base: Base,
        blocks: Vec<Block>,
        floor: Option<Floor>,
        contact: ContactParams,
        solver: SolverParams,
    ) -> Result<Self, BlockError> {
        Self::named(base, blocks, floor, contact, solver, Vec::new())
    }

    /// [`Scene::new`] with the blocks named (one entry per block, in their order; `None`:
    /// unnamed; fewer entries: the rest unnamed), as a scene file names them: errors and
    /// messages then say `block 3 (lintel)`.
    ///
    /// # Errors
    /// As [`Scene::new`].
    pub fn named(
        base: Base,
        blocks: Vec<Block>,
        floor: Option<Floor>,
        contact: ContactParams,
        solver: SolverParams,
        names: Vec<Option<String>>,
    ) -> Result<Self, BlockError> {
        contact.validate()?;
        solver.validate()?;
        if blocks.is_empty() {
            return Err(BlockError::Scene(
                "a scene needs at least one block above the base".into(),
            ));
        }
        check_block_count("the number of blocks", blocks.len())?;
        // Poses are public fields: check them here too.
        finite("base x", base.x0)?;
        finite("base y", base.y)?;
        for (k, b) in blocks.iter().enumerate() {
            let p = &b.initial;
            for (what, v) in [("x", p.x), ("y", p.y), ("theta", p.theta)] {
                finite(&format!("block {} {what}", k + 1), v)?;
            }
        }
        let scene = Self {
            base,
            blocks,
            floor,
            contact,
            solver,
            materials: Materials::default(),
            arrangement: Arrangement::default(),
            names,
            neighbours_only: false,
        };
        scene.check_overlaps()?;
        scene.check_floor()?;
        let arrangement = Arrangement::of(&scene);
        Ok(Self {
            arrangement,
            ..scene
        })
    }

    fn check_floor(&self) -> Result<(), BlockError> {
        let Some(floor) = self.floor else {
            return Ok(());
        };
        finite("floor y", floor.y)?;
        let scale = self.length_scale();
        if floor.y > self.base.bottom() + OVERLAP_TOL * scale {
            return Err(BlockError::Scene(format!(
                "the floor (y = {}) is above the bottom of the base (y = {})",
                floor.y,
                self.base.bottom()
            )));
        }
        for (k, b) in self.blocks.iter().enumerate() {
            let low = b.initial.y - b.half_vertical_extent(b.initial.theta);
            if low < floor.y - OVERLAP_TOL * scale {
                return Err(BlockError::Scene(format!(
                    "block {} starts below the floor",
                    k + 1
                )));
            }
        }
        Ok(())
    }

    fn length_scale(&self) -> f64 {
        self.blocks
            .iter()
            .map(|b| b.width().max(b.height()))
            .fold(self.base.width().max(self.base.height()), f64::max)
    }

    /// Rejects any two bodies (base included) that interpenetrate by more than a
    /// round-off tolerance. Touching is allowed.
    fn check_overlaps(&self) -> Result<(), BlockError> {
        let tol = OVERLAP_TOL * self.length_scale();
        let bodies = scene_bodies(self, 0.0, &self.initial_coordinates());
        match deepest_among(&bodies) {
            Some(p) if p.depth > tol => Err(BlockError::Overlap {
                first: self.body_label(p.first),
                second: self.body_label(p.second),
                depth: p.depth,
            }),
            _ => Ok(()),
        }
    }

    /// The scene with contact parameters overridden per interface kind and pair.
    ///
    /// # Errors
    /// A value out of range or a pair that names a body the scene lacks
    /// ([`Materials::validate`]).
    pub fn with_materials(mut self, materials: Materials) -> Result<Self, BlockError> {
        materials.validate(self.n_blocks())?;
        self.materials = materials;
        Ok(self)
    }

    /// The scene with contacts between neighbours only, or between any two bodies
    /// (`[contact] neighbours_only`).
    #[must_use]
    pub fn with_neighbours_only(mut self, neighbours_only: bool) -> Self {
        self.neighbours_only = neighbours_only;
        self
    }

    /// Whether a block touches only the bodies an interface joins it to (a column:
    /// block k meets the body beneath it and the block above it), as in the thesis's
    /// code; otherwise any two bodies may touch at their corners.
    #[must_use]
    pub fn neighbours_only(&self) -> bool {
        self.neighbours_only
    }

    /// The name of block k (1-based), if it has one.
    #[must_use]
    pub fn block_name(&self, k: usize) -> Option<&str> {
        self.names.get(k.checked_sub(1)?)?.as_deref()
    }

    /// A body as messages name it: `the base`, `block 3`, or `block 3 (lintel)`.
    #[must_use]
    pub fn body_label(&self, body: Body) -> String {
        match body {
            Body::Block(k) => match self.block_name(k) {
                Some(name) => format!("{body} ({name})"),
                None => body.to_string(),
            },
            other => other.to_string(),
        }
    }

    /// Which bodies each block rests on: the interfaces of App. G, numbered as
    /// [`crate::arrangement`] says (a column: interface k joins body k − 1 and block k).
    #[must_use]
    pub fn arrangement(&self) -> &Arrangement {
        &self.arrangement
    }

    /// The number of interfaces (a column: one per block).
    #[must_use]
    pub fn n_interfaces(&self) -> usize {
        self.arrangement.seats().len()
    }

    /// The overrides of the contact parameters.
    #[must_use]
    pub fn materials(&self) -> &Materials {
        &self.materials
    }

    /// μ, e_N and e_F of the contacts between bodies `a` and `b` ([`Materials::between`]).
    #[must_use]
    pub fn contact_between(&self, a: Body, b: Body) -> ContactParams {
        self.materials.between(&self.contact, a, b)
    }

    /// The base (block 0).
    #[must_use]
    pub fn base(&self) -> &Base {
        &self.base
    }

    /// The blocks 1..n, bottom to top.
    #[must_use]
    pub fn blocks(&self) -> &[Block] {
        &self.blocks
    }

    /// The floor, if the scene has one.
    #[must_use]
    pub fn floor(&self) -> Option<Floor> {
        self.floor
    }

    /// Number n of free blocks.
    #[must_use]
    pub fn n_blocks(&self) -> usize {
        self.blocks.len()
    }

    /// Size of body k: 0 is the base, 1..=n the blocks.
    #[must_use]
    pub fn size(&self, k: usize) -> Size {
        if k == 0 {
            Size::new(self.base.width(), self.base.height())
        } else {
            let b = &self.blocks[k - 1];
            Size::new(b.width(), b.height())
        }
    }

    /// The smallest width or height of any block (the scale of the contact tolerances).
    #[must_use]
    pub fn smallest_block_dimension(&self) -> f64 {
        self.blocks
            .iter()
            .map(|b| b.width().min(b.height()))
            .fold(f64::INFINITY, f64::min)
    }

    /// The smallest block height (the scale of the opening and penetration tolerances).
    #[must_use]
    pub fn smallest_block_height(&self) -> f64 {
        self.blocks
            .iter()
            .map(Block::height)
            .fold(f64::INFINITY, f64::min)
    }

    /// Initial coordinates q₀ = (x¹, y¹, θ¹, …, xⁿ, yⁿ, θⁿ), (4.2.1)–(4.2.2).
    #[must_use]
    pub fn initial_coordinates(&self) -> Vec<f64> {
        self.blocks
            .iter()
            .flat_map(|b| [b.initial.x, b.initial.y, b.initial.theta])
            .collect()
    }

    /// Initial velocities u₀ = (ẋ¹, ẏ¹, θ̇¹, …) (zero unless a block was set moving).
    #[must_use]
    pub fn initial_velocities(&self) -> Vec<f64> {
        self.blocks
            .iter()
            .flat_map(|b| b.velocity.as_array())
            .collect()
    }

    /// Diagonal of the mass matrix, (m, m, I) per block.
    #[must_use]
    pub fn mass_diagonal(&self) -> Vec<f64> {
        self.blocks.iter().flat_map(Block::mass_diagonal).collect()
    }

    /// Applied forces h: gravity (0, −m g, 0) per block (no gyroscopic terms in 2D).
    #[must_use]
    pub fn gravity_forces(&self) -> Vec<f64> {
        self.blocks
            .iter()
            .flat_map(|b| [0.0, -b.mass() * self.solver.gravity, 0.0])
            .collect()
    }

    /// The state of every block from q and u (3 entries per block), bottom to top.
    #[must_use]
    pub fn block_states<T: Scalar>(&self, q: &[T], u: &[T]) -> Vec<BodyState<T>> {
        (0..self.n_blocks())
            .map(|k| {
                BodyState::new(
                    Pose::from_slice(&q[3 * k..]),
                    Twist::from_slice(&u[3 * k..]),
                )
            })
            .collect()
    }

    /// Potential plus kinetic energy of the blocks (for energy checks of unforced runs).
    #[must_use]
    pub fn energy(&self, q: &[f64], u: &[f64]) -> f64 {
        self.blocks
            .iter()
            .enumerate()
            .map(|(k, b)| {
                let m = b.mass_diagonal();
                let kin = 0.5
                    * (m[0] * u[3 * k] * u[3 * k]
                        + m[1] * u[3 * k + 1] * u[3 * k + 1]
                        + m[2] * u[3 * k + 2] * u[3 * k + 2]);
                kin + b.mass() * self.solver.gravity * q[3 * k + 1]
            })
            .sum()
    }
}

/// Builds a column: blocks placed bottom to top on the base, each at its own x and θ,
/// its y such that its lowest point rests on the top of the block below.
///
/// # Errors
/// A block turned by ±π/2 or more (it cannot rest on its bottom face).
pub fn stack_on(base: &Base, blocks: &[(Block, f64, f64)]) -> Result<Vec<Block>, BlockError> {
    let mut top = base.top();
    let mut out = Vec::with_capacity(blocks.len());
    for (k, &(block, x, theta)) in blocks.iter().enumerate() {
        let b = stack_on_top(top, block, x, theta, k)?;
        top = b.initial.y + b.half_vertical_extent(theta);
        out.push(b);
    }
    Ok(out)
}

/// Places block number k (0-based) with its lowest point at height `top`.
pub(crate) fn stack_on_top(
    top: f64,
    block: Block,
    x: f64,
    theta: f64,
    k: usize,
) -> Result<Block, BlockError> {
    if theta.abs() >= std::f64::consts::FRAC_PI_2 {
        return Err(input::InputError::OutOfRange {
            name: format!("block {} theta", k + 1),
            range: "(-pi/2, pi/2)",
            value: theta,
        }
        .into());
    }
    block.at(x, top + block.half_vertical_extent(theta), theta)
}
