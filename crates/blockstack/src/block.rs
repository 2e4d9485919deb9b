//! One rigid block of the stack: its size, mass, moment of inertia and initial pose.

use crate::coordinates::{Pose, Twist};
use crate::error::BlockError;
use input::{finite, positive};

/// A rectangular rigid block of width w, height h and mass m (§4.2).
///
/// Its moment of inertia about the centre of mass is I = m(w² + h²)/12 (§4.2). The
/// initial pose (x, y, θ) of its centre of mass is the starting value of the coordinates
/// (4.2.1)–(4.2.2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Block {
    width: f64,
    height: f64,
    mass: f64,
    /// Initial pose of the centre of mass.
    pub initial: Pose,
    /// Initial velocity (v_x, v_y, ω) of the centre (default: at rest).
    pub velocity: Twist,
}

impl Block {
    /// A block at rest at the origin.
    ///
    /// # Errors
    /// When a size or the mass is not finite and positive.
    pub fn new(width: f64, height: f64, mass: f64) -> Result<Self, BlockError> {
        Ok(Self {
            width: positive("width", width)?,
            height: positive("height", height)?,
            mass: positive("mass", mass)?,
            initial: Pose::default(),
            velocity: Twist::default(),
        })
    }

    /// The same block with the initial pose (x, y, θ).
    ///
    /// # Errors
    /// When a coordinate is not finite.
    pub fn at(mut self, x: f64, y: f64, theta: f64) -> Result<Self, BlockError> {
        self.initial = Pose::new(finite("x", x)?, finite("y", y)?, finite("theta", theta)?);
        Ok(self)
    }

    /// The block set moving with centre velocity (vx, vy) and angular velocity ω.
    ///
    /// # Errors
    /// A NaN or infinite component.
    pub fn moving(mut self, vx: f64, vy: f64, omega: f64) -> Result<Self, BlockError> {
        self.velocity = Twist::new(
            finite("vx", vx)?,
            finite("vy", vy)?,
            finite("omega", omega)?,
        );
        Ok(self)
    }

    /// Width w (along the block's own e₁).
    #[must_use]
    pub fn width(&self) -> f64 {
        self.width
    }

    /// Height h (along the block's own e₂).
    #[must_use]
    pub fn height(&self) -> f64 {
        self.height
    }

    /// Mass m.
    #[must_use]
    pub fn mass(&self) -> f64 {
        self.mass
    }

    /// Moment of inertia about the centre of mass, I = m(w² + h²)/12 (§4.2).
    #[must_use]
    pub fn inertia(&self) -> f64 {
        self.mass * (self.width * self.width + self.height * self.height) / 12.0
    }

    /// The diagonal of the block's mass matrix for (x, y, θ): (m, m, I).
    #[must_use]
    pub fn mass_diagonal(&self) -> [f64; 3] {
        [self.mass, self.mass, self.inertia()]
    }

    /// Half the vertical extent of the block turned by θ: the height of its centre above
    /// its lowest corner, (w/2)|sin θ| + (h/2)|cos θ|.
    #[must_use]
    pub fn half_vertical_extent(&self, theta: f64) -> f64 {
        self.half_vertical_extent_turned(theta.sin(), theta.cos())
    }

    /// [`Block::half_vertical_extent`] from sin θ and cos θ evaluated already.
    #[must_use]
    pub fn half_vertical_extent_turned(&self, sin: f64, cos: f64) -> f64 {
        0.5 * self.width * sin.abs() + 0.5 * self.height * cos.abs()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inertia_of_a_unit_square() {
        let b = Block::new(1.0, 1.0, 6.0).unwrap();
        assert!((b.inertia() - 1.0).abs() < 1e-15);
        assert_eq!(b.mass_diagonal(), [6.0, 6.0, 1.0]);
    }

    #[test]
    fn rejects_bad_sizes() {
        assert!(matches!(
            Block::new(-1.0, 1.0, 1.0),
            Err(BlockError::Input(input::InputError::NotPositive { .. }))
        ));
        assert!(matches!(
            Block::new(1.0, 0.0, 1.0),
            Err(BlockError::Input(input::InputError::NotPositive { .. }))
        ));
        assert!(matches!(
            Block::new(1.0, 1.0, f64::NAN),
            Err(BlockError::Input(input::InputError::NonFinite(_)))
        ));
        assert!(Block::new(1.0, 1.0, 1.0)
            .unwrap()
            .at(0.0, f64::INFINITY, 0.0)
            .is_err());
    }
}
