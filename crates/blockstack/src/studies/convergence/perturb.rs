//! The perturbation ensemble: copies of a scene with its initial state or its base's
//! timing changed by a tiny relative amount.
//!
//! - **Initial positions**: every block's x is moved by δ·w·s, w its width and s in
//!   [−1, 1) drawn from the member's seed. A horizontal shift keeps each block resting
//!   on the one below (no gap, no overlap), so the perturbed state is as consistent as
//!   the scene's own.
//! - **Base frequency** (a harmonic base, ω → ω(1 + δ)): a phase lag δωt that grows from
//!   zero, so that the base's timing is perturbed without a jump of its position or
//!   velocity at t = 0; a base pulled at constant speed has v₀ → v₀(1 + δ). Today's base
//!   motions have no phase of their own to perturb. A fixed base, or one given by
//!   displacement samples, is not perturbed: its members perturb the initial positions.
//!
//! The magnitudes δ are [`MAGNITUDES`], from far below the error of any time step to a
//! ten-thousandth of a block; each magnitude has the same number of members.

use crate::base::{BaseMotion, Pulse};
use crate::error::BlockError;
use crate::scene::Scene;

/// The relative sizes δ of the perturbations: 1e-10 (near round-off of the positions,
/// far below the local error of any step), 1e-7 and 1e-4 (a ten-thousandth of a block,
/// still invisible in a drawing).
pub const MAGNITUDES: [f64; 3] = [1e-10, 1e-7, 1e-4];

/// What a member perturbs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Perturbed {
    /// The blocks' initial x.
    InitialPositions,
    /// The base's frequency (or speed).
    BaseFrequency,
}

impl Perturbed {
    /// `initial_positions` or `base_frequency`, as in JSON.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::InitialPositions => "initial_positions",
            Self::BaseFrequency => "base_frequency",
        }
    }

    /// `initial x` or `base frequency`.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Self::InitialPositions => "initial x",
            Self::BaseFrequency => "base frequency",
        }
    }
}

/// One member of the ensemble.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Perturbation {
    /// What it perturbs.
    pub perturbed: Perturbed,
    /// Its relative size δ.
    pub magnitude: f64,
    /// The seed of its directions s.
    pub seed: u64,
}

impl Perturbation {
    /// The scene perturbed.
    ///
    /// # Errors
    /// A perturbed scene the checks refuse (a block shifted into a neighbour beside it).
    pub fn apply(&self, scene: &Scene) -> Result<Scene, BlockError> {
        let mut base = scene.base().clone();
        let mut blocks = scene.blocks().to_vec();
        match self.perturbed {
            Perturbed::InitialPositions => {
                let mut s = directions(self.seed);
                for b in &mut blocks {
                    b.initial.x += self.magnitude * b.width() * s();
                }
            }
            Perturbed::BaseFrequency => {
                base.motion = faster(&base.motion, 1.0 + self.magnitude)
                    .ok_or_else(|| BlockError::Scene("the base has no frequency".into()))?;
            }
        }
        Scene::new(base, blocks, scene.floor(), scene.contact, scene.solver)?
            .with_materials(scene.materials().clone())
    }
}

/// The base motion run `factor` times faster, if it has a frequency, a speed or a pulse
/// period (a pulse `factor` times shorter); a record or samples have none.
fn faster(motion: &BaseMotion, factor: f64) -> Option<BaseMotion> {
    match *motion {
        BaseMotion::Harmonic { amplitude, omega } => Some(BaseMotion::Harmonic {
            amplitude,
            omega: omega * factor,
        }),
        BaseMotion::ConstantVelocity { v0 } => {
            Some(BaseMotion::ConstantVelocity { v0: v0 * factor })
        }
        BaseMotion::Pulse(pulse) => Some(BaseMotion::Pulse(Pulse {
            period: pulse.period / factor,
            ..pulse
        })),
        BaseMotion::Fixed | BaseMotion::Displacement(_) | BaseMotion::Record(_) => None,
    }
}

/// The ensemble of `per_magnitude` members at each of [`MAGNITUDES`]: alternately
/// initial positions and base frequency where the base has one, initial positions
/// otherwise; seeds 1, 2, … in order.
#[must_use]
pub fn ensemble(scene: &Scene, per_magnitude: usize) -> Vec<Perturbation> {
    let base_moves = faster(&scene.base().motion, 1.0).is_some();
    let mut seed = 0;
    let mut members = Vec::with_capacity(MAGNITUDES.len() * per_magnitude);
    for magnitude in MAGNITUDES {
        for j in 0..per_magnitude {
            seed += 1;
            let perturbed = if base_moves && j % 2 == 1 {
                Perturbed::BaseFrequency
            } else {
                Perturbed::InitialPositions
            };
            members.push(Perturbation {
                perturbed,
                magnitude,
                seed,
            });
        }
    }
    members
}

/// A reproducible sequence in [−1, 1) from `seed` (a linear congruential generator:
/// the members must be the same on every machine and in every run).
fn directions(seed: u64) -> impl FnMut() -> f64 {
    let mut s = seed;
    move || {
        s = s
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        #[allow(clippy::cast_precision_loss)]
        let unit = (s >> 11) as f64 / (1u64 << 53) as f64;
        2.0 * unit - 1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenes;

    #[test]
    fn members_move_the_blocks_or_the_base_by_their_magnitude() {
        let scene = scenes::find("shaking").unwrap().load().unwrap().scene;
        let members = ensemble(&scene, 2);
        assert_eq!(members.len(), 2 * MAGNITUDES.len());
        let x0: Vec<f64> = scene.blocks().iter().map(|b| b.initial.x).collect();
        let moved = members[2].apply(&scene).unwrap();
        assert_eq!(members[2].perturbed, Perturbed::InitialPositions);
        for (b, x) in moved.blocks().iter().zip(&x0) {
            let shift = (b.initial.x - x).abs();
            assert!(shift > 0.0 && shift <= 1e-7 * b.width(), "{shift}");
        }
        let faster = members[3].apply(&scene).unwrap();
        let (BaseMotion::Harmonic { omega: w0, .. }, BaseMotion::Harmonic { omega: w1, .. }) =
            (&scene.base().motion, &faster.base().motion)
        else {
            panic!("a harmonic base")
        };
        assert!((w1 / w0 - 1.0 - 1e-7).abs() < 1e-15);
        // A fixed table perturbs the blocks only.
        let lire = scenes::find("lire-collapse").unwrap().load().unwrap().scene;
        assert!(ensemble(&lire, 3)
            .iter()
            .all(|m| m.perturbed == Perturbed::InitialPositions));
    }
    /// A member is the same scene but for its perturbation: its materials per interface
    /// too (they were dropped when the study and the materials were merged).
    #[test]
    fn a_member_keeps_the_scene_s_materials() {
        let scene = scenes::find("rocking-block").unwrap().load().unwrap().scene;
        assert!(!scene.materials().is_empty(), "the scene has materials");
        for member in ensemble(&scene, 2) {
            assert_eq!(member.apply(&scene).unwrap().materials(), scene.materials());
        }
    }
}
