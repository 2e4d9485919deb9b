//! The base (block 0): a block whose motion is prescribed (§4.4, §4.5).
//!
//! The thesis moves the base along E₁ only. Here each of its three components, x⁰(t),
//! y⁰(t) and its rotation θ⁰(t) about its centre, is a [`BaseMotion`] of its own
//! (fixed, harmonic, constant-velocity, spline-joined displacement samples, an
//! acceleration [`Pulse`], or a recorded [`Accelerogram`]); the contacts with the base
//! read its full pose, twist and acceleration, so a tilting or heaving base moves its
//! corners and faces as a block's would. Following ERRATA 20, the motion is evaluated at
//! the integrator's own time t (no resampled grid), so its position, velocity and
//! acceleration always agree.
//!
//! - [`motion`]: one component's motion;
//! - [`spline`]: displacement samples joined by a natural cubic spline;
//! - [`pulse`]: one-sine, one-cosine and Ricker acceleration pulses;
//! - [`record`]: a recorded acceleration integrated exactly, with its baseline
//!   correction;
//! - [`record_file`]: reading records from `.AT2` and CSV files.

pub mod motion;
pub mod pulse;
pub mod record;
pub mod record_file;
pub mod spline;

pub use motion::BaseMotion;
pub use pulse::{Pulse, PulseShape};
pub use record::{Accelerogram, Baseline};
pub use record_file::{load_record, RecordOptions};
pub use spline::CubicSpline;

use crate::coordinates::{BodyState, Pose, Twist};
use crate::error::BlockError;
use input::positive;

/// Position, velocity and acceleration of one component of the base at one time.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BaseKinematics {
    /// The displacement from the initial position (x⁰(t) − x⁰(0), …).
    pub displacement: f64,
    /// Its rate.
    pub velocity: f64,
    /// Its second rate.
    pub acceleration: f64,
}

/// The base block: its size, the initial position of its centre and its motion.
#[derive(Debug, Clone, PartialEq)]
pub struct Base {
    width: f64,
    height: f64,
    /// x⁰(0).
    pub x0: f64,
    /// y⁰(0).
    pub y: f64,
    /// Prescribed motion along E₁.
    pub motion: BaseMotion,
    /// Prescribed motion along E₂ (fixed unless a scene says otherwise).
    pub vertical: BaseMotion,
    /// Prescribed rotation θ⁰ about the base's centre, radians (fixed unless a scene
    /// says otherwise). The blocks are placed on the base as it is at t = 0, level for
    /// every motion that starts at 0.
    pub rotation: BaseMotion,
}

impl Base {
    /// A base of the given size with its centre at (0, 0), moving along E₁ only.
    ///
    /// # Errors
    /// When a size is not finite and positive.
    pub fn new(width: f64, height: f64, motion: BaseMotion) -> Result<Self, BlockError> {
        Ok(Self {
            width: positive("base width", width)?,
            height: positive("base height", height)?,
            x0: 0.0,
            y: 0.0,
            motion,
            vertical: BaseMotion::Fixed,
            rotation: BaseMotion::Fixed,
        })
    }

    /// The same base with its motion along E₂ and its rotation.
    #[must_use]
    pub fn moving_also(self, vertical: BaseMotion, rotation: BaseMotion) -> Self {
        Self {
            vertical,
            rotation,
            ..self
        }
    }

    /// Whether the base stands still from time t on, in every component
    /// ([`BaseMotion::still_from`]).
    #[must_use]
    pub fn still_from(&self, t: f64) -> bool {
        [&self.motion, &self.vertical, &self.rotation]
            .iter()
            .all(|m| m.still_from(t))
    }

    /// Width w⁰.
    #[must_use]
    pub fn width(&self) -> f64 {
        self.width
    }

    /// Height h⁰.
    #[must_use]
    pub fn height(&self) -> f64 {
        self.height
    }

    /// Height of the top face at t = 0, y⁰ + h⁰/2.
    #[must_use]
    pub fn top(&self) -> f64 {
        self.y + 0.5 * self.height
    }

    /// Height of the bottom face at t = 0, y⁰ − h⁰/2 (where the optional floor is by
    /// default).
    #[must_use]
    pub fn bottom(&self) -> f64 {
        self.y - 0.5 * self.height
    }

    /// The names of the components' motions other than x's that are not fixed:
    /// `[("y", "pulse")]`.
    #[must_use]
    pub fn other_motions(&self) -> Vec<(&'static str, &'static str)> {
        [("y", &self.vertical), ("rotation", &self.rotation)]
            .into_iter()
            .filter(|(_, m)| **m != BaseMotion::Fixed)
            .map(|(c, m)| (c, m.name()))
            .collect()
    }

    /// Pose and velocities of the base at time t.
    #[must_use]
    pub fn state(&self, t: f64) -> BodyState {
        self.state_of(&self.components(t))
    }

    /// Acceleration (ẍ⁰, ÿ⁰, θ̈⁰) of the base at time t.
    #[must_use]
    pub fn acceleration(&self, t: f64) -> Twist {
        acceleration_of(&self.components(t))
    }

    /// [`Base::state`] and [`Base::acceleration`] at time t, the motions evaluated once
    /// for both (a harmonic one is a `sin_cos` of ωt).
    #[must_use]
    pub fn state_and_acceleration(&self, t: f64) -> (BodyState, Twist) {
        let components = self.components(t);
        (self.state_of(&components), acceleration_of(&components))
    }

    fn state_of(&self, (x, y, th): &Components) -> BodyState {
        BodyState::new(
            Pose::new(
                self.x0 + x.displacement,
                self.y + y.displacement,
                th.displacement,
            ),
            Twist::new(x.velocity, y.velocity, th.velocity),
        )
    }

    fn components(&self, t: f64) -> Components {
        (self.motion.at(t), self.vertical.at(t), self.rotation.at(t))
    }
}

/// The motions of x, y and θ of the base at one time.
type Components = (BaseKinematics, BaseKinematics, BaseKinematics);

fn acceleration_of((x, y, th): &Components) -> Twist {
    Twist::new(x.acceleration, y.acceleration, th.acceleration)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The state and the acceleration from one evaluation of the motions are those of
    /// the two calls apart, to the bit, with every component moving.
    #[test]
    fn state_and_acceleration_together_equal_each_apart() {
        let harmonic = |a, w| BaseMotion::harmonic(a, w).unwrap();
        let base = Base::new(1.0, 0.1, harmonic(0.1, 3.0))
            .unwrap()
            .moving_also(
                harmonic(0.02, 5.0),
                BaseMotion::constant_velocity(0.3).unwrap(),
            );
        for t in [0.0, 0.37, 2.9] {
            let apart = (base.state(t), base.acceleration(t));
            assert_eq!(base.state_and_acceleration(t), apart, "t = {t}");
        }
    }
}
