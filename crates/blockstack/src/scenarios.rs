//! The scenes of Ch. 4 with the thesis's parameters: the Leaning Tower of Lire (§4.3),
//! the harmonically shaken column (§4.4) and the column on a sliding base (§4.5).
//!
//! Block numbering: the thesis calls the base block 1 and the free blocks 2, 3, …; here
//! the base is block 0 and the free blocks are 1..n. So "five blocks" of §4.4–4.5 (footnotes
//! 5 and 6: w¹ is the base) is a base and four free blocks, and ϑ⁵ of Figure 4.7 is the
//! top free block.

use crate::base::{Base, BaseMotion};
use crate::block::Block;
use crate::error::BlockError;
use crate::floor::Floor;
use crate::scene::{stack_on, ContactParams, Prox, Scene, SolverParams};
use std::f64::consts::PI;

/// Which block of the Lire tower is pushed outward by 1 % of its width (§4.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Perturbation {
    /// The exact maximum-overhang configuration: an unstable equilibrium.
    #[default]
    None,
    /// The top block: it topples alone.
    Top,
    /// The lowest free block: the whole column collapses (Figure 4.4).
    Bottom,
}

impl Perturbation {
    /// Parses `none`, `top` or `bottom`.
    ///
    /// # Errors
    /// Any other name.
    pub fn from_name(name: &str) -> Result<Self, BlockError> {
        match name {
            "none" => Ok(Self::None),
            "top" => Ok(Self::Top),
            "bottom" => Ok(Self::Bottom),
            _ => Err(BlockError::Scene(format!(
                "unknown perturbation '{name}' (expected none, top or bottom)"
            ))),
        }
    }
}

/// The relative perturbation of §4.3: 1 % of the block width.
pub const LIRE_PERTURBATION: f64 = 0.01;

/// Overhangs of the maximum-overhang stack of n identical blocks of width w, bottom to
/// top: block k (1-based from the bottom) sticks out beyond the block below it (the table
/// for k = 1) by w / (2(n − k + 1)), i.e. w/8, w/6, w/4, w/2 for n = 4 (ERRATA 16: the
/// total is Σ w/(2k), not Σ w/(2n) as (4.3.1) prints).
#[must_use]
pub fn harmonic_overhangs(n: usize, width: f64) -> Vec<f64> {
    (1..=n)
        .map(|k| width / (2.0 * (n - k + 1) as f64))
        .collect()
}

/// Total overhang O_max = Σ_{k=1}^{n} w/(2k) (half the harmonic number times w), (4.3.1)
/// corrected per ERRATA 16.
#[must_use]
pub fn maximum_overhang(n: usize, width: f64) -> f64 {
    harmonic_overhangs(n, width).iter().sum()
}

/// Centre x of each block of the maximum-overhang stack on a table of width w centred at
/// x = 0 (right edge at w/2), bottom to top: every block's right edge lies at the centre
/// of mass of the blocks above it (Figure 4.3).
#[must_use]
pub fn lire_positions(n: usize, width: f64) -> Vec<f64> {
    let mut edge = 0.5 * width;
    harmonic_overhangs(n, width)
        .into_iter()
        .map(|o| {
            edge += o;
            edge - 0.5 * width
        })
        .collect()
}

/// The Leaning Tower of Lire (§4.3, Figure 4.4) as the thesis has it: n blocks w = 1,
/// h = 0.2, m = 1 on a fixed table of the same size, μ = 0.3, e_N = e_F = 0, g = 1,
/// Δt = 0.01, ρ∞ = 0.5, tol 1e-10, t_end = 10, in the maximum-overhang configuration.
/// Nothing lies below the table: the blocks that fall off it fall freely. See
/// [`lire_on_floor`] for a floor that they land on.
///
/// # Errors
/// Only for n = 0.
pub fn lire(n: usize, perturbation: Perturbation) -> Result<Scene, BlockError> {
    lire_scene(n, perturbation, false)
}

/// The Lire tower of [`lire`] with a floor at the bottom of the table (beyond the
/// thesis, ERRATA 23), so that the blocks that fall land and come to rest.
///
/// The landing is the costly part of a collapse: several corners close at once, and the
/// blocks come to rest leaning on the table edge and on each other with redundant
/// contacts, whose forces are not unique.
///
/// # Errors
/// Only for n = 0.
pub fn lire_on_floor(n: usize, perturbation: Perturbation) -> Result<Scene, BlockError> {
    lire_scene(n, perturbation, true)
}

fn lire_scene(n: usize, perturbation: Perturbation, floor: bool) -> Result<Scene, BlockError> {
    let (w, h) = (1.0, 0.2);
    let base = Base::new(w, h, BaseMotion::Fixed)?;
    let mut xs = lire_positions(n, w);
    match perturbation {
        Perturbation::None => {}
        Perturbation::Top => {
            if let Some(x) = xs.last_mut() {
                *x += LIRE_PERTURBATION * w;
            }
        }
        Perturbation::Bottom => {
            if let Some(x) = xs.first_mut() {
                *x += LIRE_PERTURBATION * w;
            }
        }
    }
    let block = Block::new(w, h, 1.0)?;
    let blocks = stack_on(
        &base,
        &xs.iter().map(|&x| (block, x, 0.0)).collect::<Vec<_>>(),
    )?;
    let floor = floor.then(|| Floor::new(base.bottom()));
    Scene::new(
        base,
        blocks,
        floor,
        ContactParams {
            mu: 0.3,
            e_n: 0.0,
            e_f: 0.0,
        },
        SolverParams::default(),
    )
}

/// Step between the bottom-block shifts of [`nearby_lire_collapses`], in block widths.
pub const NEARBY_SHIFT: f64 = 1e-6;

/// `count` Lire collapses of `n` blocks next to [`Perturbation::Bottom`]: the bottom
/// block shifted outward by (1 % + k·10⁻⁶) of its width, k = 0..count (k = 0 is the
/// scene of §4.3 itself).
///
/// The collapse runs through an unstable equilibrium, so round-off-sized differences
/// (10⁻¹⁶ grows like e^{2.7t} to 10⁻¹⁰ by t = 5) change which later steps need retries.
/// The cost of one run is therefore partly luck; the mean over these neighbours is a
/// steadier measure of the solver's speed than any single run.
///
/// # Errors
/// Only for n = 0.
pub fn nearby_lire_collapses(n: usize, count: usize) -> Result<Vec<Scene>, BlockError> {
    nearby(&lire(n, Perturbation::Bottom)?, count)
}

/// The collapses of [`nearby_lire_collapses`] on the floor of [`lire_on_floor`]: their
/// landings differ from one neighbour to the next.
///
/// # Errors
/// Only for n = 0.
pub fn nearby_lire_landings(n: usize, count: usize) -> Result<Vec<Scene>, BlockError> {
    nearby(&lire_on_floor(n, Perturbation::Bottom)?, count)
}

fn nearby(scene: &Scene, count: usize) -> Result<Vec<Scene>, BlockError> {
    (0..count)
        .map(|k| {
            let mut blocks = scene.blocks().to_vec();
            if let Some(b) = blocks.first_mut() {
                b.initial.x += k as f64 * NEARBY_SHIFT * b.width();
            }
            Scene::new(
                scene.base().clone(),
                blocks,
                scene.floor(),
                scene.contact,
                scene.solver,
            )
        })
        .collect()
}

/// Parameters of the shaken column (§4.4, Figure 4.6).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shaking {
    /// Number of free blocks (Figure 4.6: 4).
    pub blocks: usize,
    /// Base amplitude A (the thesis's "A = w²" is ambiguous; default 0.2).
    pub amplitude: f64,
    /// Angular frequency ω of the base.
    pub omega: f64,
    /// Number of base periods simulated.
    pub periods: f64,
    /// Steps per period: Δt = 2π/(steps ω) (Figure 4.6: 100; ERRATA 21).
    pub steps_per_period: f64,
    /// Friction coefficient (Figure 4.6: 0.2).
    pub mu: f64,
    /// The blocks start moving with the base (velocity Aω, at rest relative to it)
    /// instead of at rest (Figure 4.6, the default). From rest, the bottom interface
    /// slides at t = 0 and friction kicks the column; a column that moves with its base
    /// is only loaded by the base's acceleration −Aω² sin ωt, which tips a column of n
    /// blocks once it exceeds g w/(h n) (docs/method.md §8.2, tall columns).
    pub start_with_base: bool,
}

impl Shaking {
    /// A tall column of `blocks` on a base that barely moves, x = 0.001 sin 2t (μ = 0.2,
    /// Δt = 2π/628, one period): at rest and kicked by the base's velocity at t = 0, or
    /// moving with the base when `start_with_base` (docs/method.md §8.2, tall columns;
    /// `rollstack blocks shake --blocks N --omega 2 --amplitude 0.001 --mu 0.2
    /// --steps-per-period 314`).
    #[must_use]
    pub fn tall_column(blocks: usize, start_with_base: bool) -> Self {
        Self {
            blocks,
            amplitude: 0.001,
            omega: 2.0,
            periods: 1.0,
            steps_per_period: 314.0,
            mu: 0.2,
            start_with_base,
        }
    }

    /// The base period 2π/ω.
    #[must_use]
    pub fn period(&self) -> f64 {
        2.0 * PI / self.omega
    }

    /// The time simulated: the periods times 2π/ω.
    #[must_use]
    pub fn duration(&self) -> f64 {
        self.periods * self.period()
    }
}

impl Default for Shaking {
    fn default() -> Self {
        Self {
            blocks: 4,
            amplitude: 0.2,
            omega: 2.0,
            periods: 10.0,
            steps_per_period: 100.0,
            mu: 0.2,
            start_with_base: false,
        }
    }
}

/// The size of the free blocks of a shaken column and the gravity it falls in. The
/// thesis's blocks are w = 0.2, h = 0.4 with g = 1 (lengths in any unit L, times in
/// √(L/g)); blocks in metres with g = 9.81 make the times seconds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ColumnUnits {
    /// Width w of each free block.
    pub width: f64,
    /// Height h of each free block.
    pub height: f64,
    /// Gravity g, along −y.
    pub gravity: f64,
}

impl Default for ColumnUnits {
    fn default() -> Self {
        Self {
            width: 0.2,
            height: 0.4,
            gravity: 1.0,
        }
    }
}

/// The harmonically shaken column (§4.4): identical blocks w = 0.2, h = 0.4, m = 1,
/// aligned on a base w = 1, h = 0.1 moving as x⁰ = A sin ωt; floor at the base's bottom.
///
/// # Errors
/// Bad parameters (ω ≤ 0, negative μ, …).
pub fn shaking_column(p: &Shaking) -> Result<Scene, BlockError> {
    shaking_column_in(p, &ColumnUnits::default())
}

/// [`shaking_column`] with blocks of another size or another gravity (`units`); the
/// base keeps w = 1, h = 0.1.
///
/// # Errors
/// Bad parameters (ω ≤ 0, negative μ, a block size not positive, g < 0, …).
pub fn shaking_column_in(p: &Shaking, units: &ColumnUnits) -> Result<Scene, BlockError> {
    input::positive("omega", p.omega)?;
    input::positive("periods", p.periods)?;
    input::positive("steps per period", p.steps_per_period)?;
    let base = Base::new(1.0, 0.1, BaseMotion::harmonic(p.amplitude, p.omega)?)?;
    let mut block = Block::new(units.width, units.height, 1.0)?;
    if p.start_with_base {
        block = block.moving(base.motion.at(0.0).velocity, 0.0, 0.0)?;
    }
    let blocks = stack_on(&base, &vec![(block, 0.0, 0.0); p.blocks])?;
    let floor = Some(Floor::new(base.bottom()));
    let solver = SolverParams {
        dt: p.period() / p.steps_per_period,
        t_end: p.duration(),
        gravity: units.gravity,
        ..SolverParams::default()
    };
    Scene::new(
        base,
        blocks,
        floor,
        ContactParams {
            mu: p.mu,
            e_n: 0.0,
            e_f: 0.0,
        },
        solver,
    )
}

/// Parameters of the column on a pulled base (§4.5, Figure 4.7).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sliding {
    /// Number of free blocks (Figure 4.7: 4).
    pub blocks: usize,
    /// Speed v₀ of the base from t = 0.
    pub v0: f64,
    /// End time (Figure 4.7: 3; ERRATA 21 notes the published runs stopped at 2.5).
    pub t_end: f64,
    /// Friction coefficient at every contact (Figure 4.7: 0.2).
    pub mu: f64,
}

impl Default for Sliding {
    /// Figure 4.7 at v₀ = 1: four blocks, t_end = 3, μ = 0.2.
    fn default() -> Self {
        Self {
            blocks: 4,
            v0: 1.0,
            t_end: 3.0,
            mu: 0.2,
        }
    }
}

/// The column on a sliding base (§4.5, Figure 4.7): base and blocks all w = 0.2, h = 0.4,
/// m = 1, friction `p.mu` (0.2 in the thesis); the base moves at v₀ from t = 0; the
/// blocks land on a floor at the base's bottom; t_end = 3 in Figure 4.7.
///
/// # Errors
/// Bad parameters (a negative μ, …).
pub fn sliding_column(p: &Sliding) -> Result<Scene, BlockError> {
    sliding_column_in(p, &ColumnUnits::default())
}

/// [`sliding_column`] with free blocks of another size or another gravity (`units`);
/// the base keeps w = 0.2, h = 0.4.
///
/// # Errors
/// Bad parameters (a negative μ, a block size not positive, g < 0, …).
pub fn sliding_column_in(p: &Sliding, units: &ColumnUnits) -> Result<Scene, BlockError> {
    let base = Base::new(0.2, 0.4, BaseMotion::constant_velocity(p.v0)?)?;
    let block = Block::new(units.width, units.height, 1.0)?;
    let stacked = stack_on(&base, &vec![(block, 0.0, 0.0); p.blocks])?;
    let floor = Some(Floor::new(base.bottom()));
    let solver = SolverParams {
        t_end: p.t_end,
        gravity: units.gravity,
        ..SolverParams::default()
    };
    Scene::new(
        base,
        stacked,
        floor,
        ContactParams {
            mu: p.mu,
            e_n: 0.0,
            e_f: 0.0,
        },
        solver,
    )
}

/// A column of n identical blocks w = 0.2, h = 0.4, m = 1 at rest on a fixed base
/// (w = 1, h = 0.1), μ = 0.2, no floor, Δt = 0.01: the accuracy and size-scaling test
/// of a chain (every block touches only its neighbours).
///
/// # Errors
/// Only for n = 0.
pub fn resting_column(blocks: usize, t_end: f64) -> Result<Scene, BlockError> {
    let base = Base::new(1.0, 0.1, BaseMotion::Fixed)?;
    let block = Block::new(0.2, 0.4, 1.0)?;
    let stacked = stack_on(&base, &vec![(block, 0.0, 0.0); blocks])?;
    let solver = SolverParams {
        t_end,
        ..SolverParams::default()
    };
    Scene::new(
        base,
        stacked,
        None,
        ContactParams {
            mu: 0.2,
            e_n: 0.0,
            e_f: 0.0,
        },
        solver,
    )
}

/// The thesis's constant prox parameter r = 0.3 (§4.2), for reproducing its runs.
pub const THESIS_PROX: Prox = Prox::Constant(0.3);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn harmonic_overhang_exceeds_one_width_for_four_blocks() {
        let o = harmonic_overhangs(4, 1.0);
        assert_eq!(o, vec![1.0 / 8.0, 1.0 / 6.0, 1.0 / 4.0, 1.0 / 2.0]);
        assert!((maximum_overhang(4, 1.0) - 25.0 / 24.0).abs() < 1e-15);
        // The printed (4.3.1) would give w/2.
        assert!(maximum_overhang(4, 1.0) > 1.0);
    }

    #[test]
    fn every_block_edge_is_at_the_centre_of_mass_above_it() {
        let n = 4;
        let xs = lire_positions(n, 1.0);
        for k in 0..n {
            let edge = if k == 0 { 0.5 } else { xs[k - 1] + 0.5 };
            let above = &xs[k..];
            let com = above.iter().sum::<f64>() / above.len() as f64;
            assert!((com - edge).abs() < 1e-15, "block {}", k + 1);
        }
    }

    #[test]
    fn lire_scenes_are_valid_and_perturbed_as_asked() {
        let none = lire(4, Perturbation::None).unwrap();
        let top = lire(4, Perturbation::Top).unwrap();
        let bottom = lire(4, Perturbation::Bottom).unwrap();
        let (q0, qt, qb) = (
            none.initial_coordinates(),
            top.initial_coordinates(),
            bottom.initial_coordinates(),
        );
        assert!((qt[9] - q0[9] - 0.01).abs() < 1e-15);
        assert!((qb[0] - q0[0] - 0.01).abs() < 1e-15);
        assert!((q0[1] - 0.2).abs() < 1e-15 && (q0[10] - 0.8).abs() < 1e-15);
        // All contacts of the unperturbed tower are closed and supported.
        let c = none.contacts(0.0, &q0, &[0.0; 12]);
        assert!(c.normals[..8]
            .iter()
            .all(|g| g.is_some_and(|g| g.value.abs() < 1e-14)));
    }

    #[test]
    fn the_thesis_tower_has_no_floor_and_the_landing_one_has_it_under_the_table() {
        let thesis = lire(4, Perturbation::Bottom).unwrap();
        assert_eq!(thesis.floor(), None);
        assert_eq!(thesis.n_normal_contacts(), 8);
        let landing = lire_on_floor(4, Perturbation::Bottom).unwrap();
        assert_eq!(landing.floor().map(|f| f.y), Some(landing.base().bottom()));
        assert_eq!(landing.n_normal_contacts(), 8 + 4 * 4);
        assert_eq!(thesis.initial_coordinates(), landing.initial_coordinates());
        let (near, land) = (
            nearby_lire_collapses(4, 3).unwrap(),
            nearby_lire_landings(4, 3).unwrap(),
        );
        assert_eq!(near[0].initial_coordinates(), thesis.initial_coordinates());
        assert!(near.iter().all(|s| s.floor().is_none()));
        assert!(land.iter().all(|s| s.floor().is_some()));
        let shift = near[2].initial_coordinates()[0] - near[0].initial_coordinates()[0];
        assert!((shift - 2.0 * NEARBY_SHIFT).abs() < 1e-15);
    }

    #[test]
    fn shaking_and_sliding_defaults() {
        let s = shaking_column(&Shaking {
            omega: 4.0,
            ..Shaking::default()
        })
        .unwrap();
        assert_eq!(s.n_blocks(), 4);
        assert!((s.solver.dt - 2.0 * PI / 400.0).abs() < 1e-15);
        assert!((s.base().height() - 0.1).abs() < 1e-15);
        let s = sliding_column(&Sliding::default()).unwrap();
        assert_eq!(s.n_blocks(), 4);
        assert!((s.contact.mu - 0.2).abs() < 1e-15);
        assert!((s.solver.t_end - 3.0).abs() < 1e-15);
        let rough = Sliding {
            mu: 0.5,
            ..Sliding::default()
        };
        assert!((sliding_column(&rough).unwrap().contact.mu - 0.5).abs() < 1e-15);
        let negative = Sliding {
            mu: -0.1,
            ..Sliding::default()
        };
        assert!(sliding_column(&negative).is_err());
        assert_eq!(s.n_normal_contacts(), 8 + 16);
    }
}

/// A block sliding on one corner over a fixed table (App. I, point contact), set up so
/// that the corner's normal acceleration is ÿ_P = A + B n (n the normal force per mg).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PainleveCorner {
    /// Block angle θ (rad); the lowest corner touches the table.
    pub theta: f64,
    /// Friction coefficient μ.
    pub mu: f64,
    /// Slip speed ẋ_P of the corner (its sign is sgn ẋ_P of (I.1.8)).
    pub slip: f64,
    /// A: the corner's normal acceleration without contact force, in units of g (> −1:
    /// it sets the spin, A = −1 − θ̇² r_y / g).
    pub free_acceleration: f64,
    /// Sign of the spin θ̇.
    pub spin_sign: f64,
    /// Time step Δt of the scene. The discrete step's B differs from App. I's by O(Δt):
    /// near b = 0 a case is in Painlevé's region for one and not for the other
    /// ([`crate::studies::painleve::corner_scan`] refines it there).
    pub dt: f64,
}

impl Default for PainleveCorner {
    /// A case of Painlevé's indeterminacy for w/h = 0.5: θ = 0.9, μ = 2, sliding right,
    /// A = 0.5 g and B = −0.76 < 0, so that both n = 0 (lift-off) and n = −A/B (contact)
    /// solve the contact problem.
    fn default() -> Self {
        Self {
            theta: 0.9,
            mu: 2.0,
            slip: 0.5,
            free_acceleration: 0.5,
            spin_sign: 1.0,
            dt: 1e-3,
        }
    }
}

impl PainleveCorner {
    /// Block size (w, h) and table height of the scene.
    const SIZE: (f64, f64) = (0.2, 0.4);

    /// The lowest corner relative to the centre, r = P − c.
    #[must_use]
    pub fn corner(&self) -> (f64, f64) {
        let (w, h) = Self::SIZE;
        let (s, c) = self.theta.sin_cos();
        [(-0.5 * w, -0.5 * h), (0.5 * w, -0.5 * h)]
            .iter()
            .map(|&(a, b)| (c * a - s * b, s * a + c * b))
            .fold((0.0, f64::INFINITY), |m, p| if p.1 < m.1 { p } else { m })
    }

    /// Whether the block rests on a side, both bottom corners level (θ = 0 in the scan):
    /// a line contact (App. I.2, whose LCP (I.2.10) has one solution), not App. I.1's
    /// single point.
    #[must_use]
    pub fn line_contact(&self) -> bool {
        let (w, h) = Self::SIZE;
        let (s, c) = self.theta.sin_cos();
        let mut heights = [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)]
            .map(|(a, b): (f64, f64)| s * a * w + c * b * h);
        heights.sort_by(f64::total_cmp);
        heights[1] - heights[0] <= 1e-12 * h
    }

    /// B of ÿ_P = A + B n for unit mass and g = 1: 1 + r_x (r_x + μ sgn(ẋ_P) r_y)/I.
    /// The paradoxes need B < 0 (App. I: b ≤ 0); with A > 0 the contact problem has two
    /// solutions.
    #[must_use]
    pub fn response(&self) -> f64 {
        let (w, h) = Self::SIZE;
        let inertia = (w * w + h * h) / 12.0;
        let (rx, ry) = self.corner();
        1.0 + rx * (rx + self.mu * self.slip.signum() * ry) / inertia
    }

    /// The scene: the block (m = 1) with its lowest corner on a fixed table (w = 10,
    /// h = 0.1, top at y = 0.05), the corner moving along the table at `slip`, g = 1,
    /// Δt = `dt`, t_end = 10 Δt.
    ///
    /// # Errors
    /// A free acceleration of −1 or less (no spin gives it) or non-finite input.
    pub fn scene(&self) -> Result<Scene, BlockError> {
        input::finite("theta", self.theta)?;
        input::finite("slip", self.slip)?;
        input::positive("dt", self.dt)?;
        if self.free_acceleration <= -1.0 || !self.free_acceleration.is_finite() {
            return Err(BlockError::Scene(format!(
                "the corner's free acceleration must be above -1 (g units), got {}",
                self.free_acceleration
            )));
        }
        let (w, h) = Self::SIZE;
        let (rx, ry) = self.corner();
        let omega = self.spin_sign.signum() * ((1.0 + self.free_acceleration) / -ry).sqrt();
        let base = Base::new(10.0, 0.1, BaseMotion::Fixed)?;
        let mut block = Block::new(w, h, 1.0)?;
        block.initial = crate::Pose {
            x: 0.0,
            y: base.top() - ry,
            theta: self.theta,
        };
        block.velocity = crate::Twist {
            vx: self.slip + omega * ry,
            vy: -omega * rx,
            omega,
        };
        let solver = SolverParams {
            dt: self.dt,
            t_end: 10.0 * self.dt,
            ..SolverParams::default()
        };
        Scene::new(
            base,
            vec![block],
            None,
            ContactParams {
                mu: self.mu,
                e_n: 0.0,
                e_f: 0.0,
            },
            solver,
        )
    }
}
