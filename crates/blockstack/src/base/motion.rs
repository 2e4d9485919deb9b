//! The prescribed motion of one component of the base (x, y or θ): a position, velocity
//! and acceleration known at every t.

use super::pulse::Pulse;
use super::record::Accelerogram;
use super::spline::CubicSpline;
use super::BaseKinematics;
use crate::error::BlockError;
use input::finite;

/// The prescribed motion of one component of the base: along E₁ (the thesis's only
/// one), along E₂, or its rotation about its centre. Lengths for x and y, radians for θ.
#[derive(Debug, Clone, PartialEq)]
pub enum BaseMotion {
    /// The component does not move (the table of §4.3).
    Fixed,
    /// A sin ωt (§4.4).
    Harmonic {
        /// Amplitude A (length, or radians).
        amplitude: f64,
        /// Angular frequency ω (rad per time unit).
        omega: f64,
    },
    /// A rate v₀ from t = 0 on (§4.5): an impulsive start, the blocks begin at rest.
    ConstantVelocity {
        /// Speed v₀ (length, or radians, per time unit).
        v0: f64,
    },
    /// A given displacement from the position at the first sample, interpolated by a
    /// natural cubic spline through samples (so that position, velocity and acceleration
    /// are continuous); outside the sampled interval it is extended linearly with the end
    /// slope.
    Displacement(CubicSpline),
    /// An acceleration pulse from rest (one-sine, one-cosine, Ricker).
    Pulse(Pulse),
    /// A recorded acceleration, integrated exactly.
    Record(Accelerogram),
}

impl BaseMotion {
    /// The motions' names in scene files.
    pub const NAMES: [&'static str; 6] = [
        "fixed",
        "harmonic",
        "constant-velocity",
        "displacement",
        "pulse",
        "record",
    ];

    /// A harmonic motion A sin ωt.
    ///
    /// # Errors
    /// When A or ω is not finite.
    pub fn harmonic(amplitude: f64, omega: f64) -> Result<Self, BlockError> {
        Ok(Self::Harmonic {
            amplitude: finite("base amplitude", amplitude)?,
            omega: finite("base omega", omega)?,
        })
    }

    /// A constant velocity v₀ from t = 0.
    ///
    /// # Errors
    /// When v₀ is not finite.
    pub fn constant_velocity(v0: f64) -> Result<Self, BlockError> {
        Ok(Self::ConstantVelocity {
            v0: finite("base v0", v0)?,
        })
    }

    /// The motion's name in scene files ([`BaseMotion::NAMES`]).
    #[must_use]
    pub fn name(&self) -> &'static str {
        let i = match self {
            Self::Fixed => 0,
            Self::Harmonic { .. } => 1,
            Self::ConstantVelocity { .. } => 2,
            Self::Displacement(_) => 3,
            Self::Pulse(_) => 4,
            Self::Record(_) => 5,
        };
        Self::NAMES[i]
    }

    /// The period 2π/|ω| of a harmonic motion with ω ≠ 0 (time units); `None` for the
    /// other motions.
    #[must_use]
    pub fn period(&self) -> Option<f64> {
        match self {
            Self::Harmonic { omega, .. } if *omega != 0.0 => {
                Some(2.0 * std::f64::consts::PI / omega.abs())
            }
            _ => None,
        }
    }

    /// Whether the component stands still from time t on: its displacement constant and
    /// its velocity and acceleration zero at every later time (a fixed component, a
    /// harmonic motion of zero amplitude or frequency, a cycloidal pulse after its end, a
    /// record after its last sample when it ends at rest). `false` where that is not
    /// known (a Ricker pulse's tail, a displacement's linear extension).
    #[must_use]
    pub fn still_from(&self, t: f64) -> bool {
        match self {
            Self::Fixed => true,
            Self::Harmonic { amplitude, omega } => *amplitude == 0.0 || *omega == 0.0,
            Self::ConstantVelocity { v0 } => *v0 == 0.0,
            Self::Displacement(_) => false,
            Self::Pulse(pulse) => pulse.ended_by(t),
            Self::Record(record) => record.at_rest_from(t),
        }
    }

    /// Position (from the start), velocity and acceleration at time t.
    #[must_use]
    pub fn at(&self, t: f64) -> BaseKinematics {
        match self {
            Self::Fixed => BaseKinematics::default(),
            Self::Harmonic { amplitude, omega } => {
                let (s, c) = (omega * t).sin_cos();
                BaseKinematics {
                    displacement: amplitude * s,
                    velocity: amplitude * omega * c,
                    acceleration: -amplitude * omega * omega * s,
                }
            }
            Self::ConstantVelocity { v0 } => BaseKinematics {
                displacement: v0 * t,
                velocity: *v0,
                acceleration: 0.0,
            },
            Self::Displacement(spline) => spline.at(t),
            Self::Pulse(pulse) => pulse.at(t),
            Self::Record(record) => record.at(t),
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// The velocity and acceleration of `motion` at t against central differences.
    pub(crate) fn check_derivatives(motion: &BaseMotion, t: f64) {
        let h = 1e-5;
        let k = motion.at(t);
        let (p, m) = (motion.at(t + h), motion.at(t - h));
        assert!(((p.displacement - m.displacement) / (2.0 * h) - k.velocity).abs() < 1e-7);
        assert!(((p.velocity - m.velocity) / (2.0 * h) - k.acceleration).abs() < 1e-6);
    }

    /// Which motions stand still from a time on: a fixed base, a harmonic motion of zero
    /// amplitude or frequency, a constant velocity of zero, a cycloidal pulse after its
    /// period; not a moving one, a Ricker pulse (its tail goes on) or a displacement.
    #[test]
    fn a_base_stands_still_where_its_motion_is_over_for_good() {
        use super::super::pulse::{Pulse, PulseShape};
        assert!(BaseMotion::Fixed.still_from(0.0));
        assert!(BaseMotion::harmonic(0.0, 3.0).unwrap().still_from(0.0));
        assert!(!BaseMotion::harmonic(0.2, 3.0).unwrap().still_from(1e6));
        assert!(BaseMotion::constant_velocity(0.0).unwrap().still_from(0.0));
        assert!(!BaseMotion::constant_velocity(0.1).unwrap().still_from(1e6));
        let sine = Pulse::new(PulseShape::OneSine, 2.0, 0.5, 1.0).unwrap();
        let still = BaseMotion::Pulse(sine);
        assert!(!still.still_from(1.4) && still.still_from(1.5));
        assert_eq!(still.at(1.5), still.at(7.0));
        let ricker = Pulse::new(PulseShape::Ricker, 2.0, 0.5, 1.0).unwrap();
        assert!(!BaseMotion::Pulse(ricker).still_from(1e3));
    }

    #[test]
    fn harmonic_motion_derivatives_agree() {
        let m = BaseMotion::harmonic(0.2, 3.0).unwrap();
        for t in [0.0, 0.3, 1.7] {
            check_derivatives(&m, t);
        }
        assert!((m.at(std::f64::consts::PI / 6.0).displacement - 0.2).abs() < 1e-15);
    }

    #[test]
    fn constant_velocity_starts_at_once() {
        let m = BaseMotion::constant_velocity(1.5).unwrap();
        assert_eq!(m.at(0.0).velocity, 1.5);
        assert_eq!(m.at(0.0).displacement, 0.0);
        assert!((m.at(2.0).displacement - 3.0).abs() < 1e-15);
    }
}
