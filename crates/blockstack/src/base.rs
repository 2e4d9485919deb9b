//! The base (block 0): a block whose horizontal motion is prescribed (§4.4, §4.5).
//!
//! The base never rotates and keeps its height; only x⁰(t) is given. Following ERRATA 20,
//! the motion is evaluated at the integrator's own time t (no resampled grid), so its
//! position, velocity and acceleration always agree.

use crate::coordinates::{BodyState, Pose, Twist};
use crate::error::BlockError;
use input::{finite, positive};

/// Position, velocity and acceleration of the base along E₁ at one time.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BaseKinematics {
    /// x⁰(t) − x⁰(0): displacement from the initial position.
    pub displacement: f64,
    /// ẋ⁰(t).
    pub velocity: f64,
    /// ẍ⁰(t).
    pub acceleration: f64,
}

/// The prescribed horizontal motion of the base.
#[derive(Debug, Clone, PartialEq)]
pub enum BaseMotion {
    /// The base does not move (the table of §4.3).
    Fixed,
    /// x⁰ = A sin ωt (§4.4).
    Harmonic {
        /// Amplitude A (length).
        amplitude: f64,
        /// Angular frequency ω (rad per time unit).
        omega: f64,
    },
    /// ẋ⁰ = v₀ from t = 0 on (§4.5): an impulsive start, the blocks begin at rest.
    ConstantVelocity {
        /// Speed v₀ (length per time unit).
        v0: f64,
    },
    /// A given displacement x⁰(t) − x⁰(0), interpolated by a natural cubic spline through
    /// samples (so that position, velocity and acceleration are continuous); constant
    /// outside the sampled interval is *not* assumed: it is extended linearly with the end
    /// slope.
    Displacement(CubicSpline),
}

impl BaseMotion {
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

    /// The motion's name in scene files: `fixed`, `harmonic`, `constant-velocity` or
    /// `displacement`.
    #[must_use]
    pub fn name(&self) -> &'static str {
        match self {
            Self::Fixed => "fixed",
            Self::Harmonic { .. } => "harmonic",
            Self::ConstantVelocity { .. } => "constant-velocity",
            Self::Displacement(_) => "displacement",
        }
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

    /// Position, velocity and acceleration at time t.
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
        }
    }
}

/// The base block: its size, the height of its centre, its initial x and its motion.
#[derive(Debug, Clone, PartialEq)]
pub struct Base {
    width: f64,
    height: f64,
    /// x⁰(0).
    pub x0: f64,
    /// y⁰ (constant).
    pub y: f64,
    /// Prescribed motion.
    pub motion: BaseMotion,
}

impl Base {
    /// A base of the given size with its centre at (0, 0).
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
        })
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

    /// Height of the top face, y⁰ + h⁰/2.
    #[must_use]
    pub fn top(&self) -> f64 {
        self.y + 0.5 * self.height
    }

    /// Height of the bottom face, y⁰ − h⁰/2 (where the optional floor is by default).
    #[must_use]
    pub fn bottom(&self) -> f64 {
        self.y - 0.5 * self.height
    }

    /// Pose and velocities of the base at time t (θ⁰ = 0 always).
    #[must_use]
    pub fn state(&self, t: f64) -> BodyState {
        let k = self.motion.at(t);
        BodyState::new(
            Pose::new(self.x0 + k.displacement, self.y, 0.0),
            Twist::new(k.velocity, 0.0, 0.0),
        )
    }

    /// Acceleration (ẍ⁰, 0, 0) of the base at time t.
    #[must_use]
    pub fn acceleration(&self, t: f64) -> Twist {
        Twist::new(self.motion.at(t).acceleration, 0.0, 0.0)
    }
}

/// A natural cubic spline through samples (tᵢ, xᵢ), with linear extension outside.
#[derive(Debug, Clone, PartialEq)]
pub struct CubicSpline {
    t: Vec<f64>,
    x: Vec<f64>,
    /// Second derivatives at the knots.
    m: Vec<f64>,
}

impl CubicSpline {
    /// The natural cubic spline through the samples (strictly increasing times).
    ///
    /// # Errors
    /// Fewer than two samples, non-finite values, or times not strictly increasing.
    pub fn new(samples: &[(f64, f64)]) -> Result<Self, BlockError> {
        if samples.len() < 2 {
            return Err(BlockError::Scene(
                "a displacement needs at least two samples [t, x]".into(),
            ));
        }
        for (i, &(t, x)) in samples.iter().enumerate() {
            finite(&format!("displacement sample {i} time"), t)?;
            finite(&format!("displacement sample {i} value"), x)?;
        }
        if samples.windows(2).any(|w| w[1].0 <= w[0].0) {
            return Err(BlockError::Scene(
                "displacement sample times must be strictly increasing".into(),
            ));
        }
        let t: Vec<f64> = samples.iter().map(|s| s.0).collect();
        let x: Vec<f64> = samples.iter().map(|s| s.1).collect();
        let n = t.len();
        // Tridiagonal system for the knot curvatures, natural ends m₀ = m_{n−1} = 0.
        let mut m = vec![0.0; n];
        if n > 2 {
            let mut diag = vec![0.0; n];
            let mut rhs = vec![0.0; n];
            let mut upper = vec![0.0; n];
            for i in 1..n - 1 {
                let h0 = t[i] - t[i - 1];
                let h1 = t[i + 1] - t[i];
                diag[i] = 2.0 * (h0 + h1);
                upper[i] = h1;
                rhs[i] = 6.0 * ((x[i + 1] - x[i]) / h1 - (x[i] - x[i - 1]) / h0);
                if i > 1 {
                    let w = h0 / diag[i - 1];
                    diag[i] -= w * upper[i - 1];
                    rhs[i] -= w * rhs[i - 1];
                }
            }
            for i in (1..n - 1).rev() {
                m[i] = (rhs[i] - upper[i] * m[i + 1]) / diag[i];
            }
        }
        Ok(Self { t, x, m })
    }

    /// Displacement relative to the first sample, velocity and acceleration at time s.
    #[must_use]
    pub fn at(&self, s: f64) -> BaseKinematics {
        let n = self.t.len();
        let x_first = self.x[0];
        let seg = |i: usize, s: f64| {
            let (t0, t1) = (self.t[i], self.t[i + 1]);
            let h = t1 - t0;
            let (a, b) = ((t1 - s) / h, (s - t0) / h);
            let (m0, m1) = (self.m[i], self.m[i + 1]);
            let x = a * self.x[i]
                + b * self.x[i + 1]
                + ((a * a * a - a) * m0 + (b * b * b - b) * m1) * h * h / 6.0;
            let v = (self.x[i + 1] - self.x[i]) / h
                + (-(3.0 * a * a - 1.0) * m0 + (3.0 * b * b - 1.0) * m1) * h / 6.0;
            let acc = a * m0 + b * m1;
            (x, v, acc)
        };
        let (x, v, acc) = if s <= self.t[0] {
            let (x, v, _) = seg(0, self.t[0]);
            (x + v * (s - self.t[0]), v, 0.0)
        } else if s >= self.t[n - 1] {
            let (x, v, _) = seg(n - 2, self.t[n - 1]);
            (x + v * (s - self.t[n - 1]), v, 0.0)
        } else {
            let i = self
                .t
                .partition_point(|&ti| ti <= s)
                .saturating_sub(1)
                .min(n - 2);
            seg(i, s)
        };
        BaseKinematics {
            displacement: x - x_first,
            velocity: v,
            acceleration: acc,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check_derivatives(motion: &BaseMotion, t: f64) {
        let h = 1e-5;
        let k = motion.at(t);
        let (p, m) = (motion.at(t + h), motion.at(t - h));
        assert!(((p.displacement - m.displacement) / (2.0 * h) - k.velocity).abs() < 1e-7);
        assert!(((p.velocity - m.velocity) / (2.0 * h) - k.acceleration).abs() < 1e-6);
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

    #[test]
    fn spline_interpolates_and_is_smooth() {
        let samples: Vec<(f64, f64)> = (0..20)
            .map(|i| (0.1 * f64::from(i), (0.1 * f64::from(i)).sin()))
            .collect();
        let s = CubicSpline::new(&samples).unwrap();
        for &(t, x) in &samples {
            assert!((s.at(t).displacement - x).abs() < 1e-12);
        }
        let m = BaseMotion::Displacement(s);
        for t in [0.35, 0.91, 1.55] {
            check_derivatives(&m, t);
            // A sine sampled at 0.1 is reproduced closely.
            assert!((m.at(t).displacement - t.sin()).abs() < 1e-4);
        }
    }

    #[test]
    fn spline_rejects_bad_samples() {
        assert!(CubicSpline::new(&[(0.0, 0.0)]).is_err());
        assert!(CubicSpline::new(&[(0.0, 0.0), (0.0, 1.0)]).is_err());
        assert!(CubicSpline::new(&[(0.0, 0.0), (1.0, f64::NAN)]).is_err());
    }
}
